//! How far a link can move between two configurations: the bound behind continuous collision
//! checks (Schwarzer, Saha and Latombe, "Exact collision checking of robot paths", 2002).
//!
//! Between `q_a` and `q_b`, joined by the straight line in joint space, every point `x` of link
//! `k` moves by at most
//!
//! ```text
//! Σ_i |Δθ_i| · (lever_{i,k} + reach)   (revolute joints i moving link k)
//! + Σ_i |Δθ_i|                          (prismatic joints)
//! ```
//!
//! where `Δθ_i` is joint `i`'s change (a mimic joint's is its multiplier times its leader's),
//! `reach` bounds `|x − origin of link k|`, and `lever_{i,k}` bounds the distance from joint
//! `i`'s origin to link `k`'s origin at every configuration: the sum of the constant offsets
//! between them plus the largest travel of every prismatic joint in between. A revolute joint
//! turning by `dθ` moves `x` by `dθ` times its distance to the axis, which is at most its
//! distance to the joint origin; summing over the joints and integrating along the line gives
//! the bound.
//!
//! **Near a known configuration** the bound tightens ([`SweepBound::displacement_near`], in the
//! spirit of Zhang, Redon and Lin's bounds for articulated models, 2007): a point's speed due to
//! revolute joint `i` is `|θ̇_i|` times its distance to joint `i`'s *axis*, and in the frame
//! after joint `i` (where that axis is fixed) the point moves only by the later joints, at most
//! `t · S_{>i}` by time `t` of the segment (`S_{>i}`: the sum above restricted to the joints
//! after `i`). Integrating over `t ∈ [0, 1]`,
//!
//! ```text
//! Σ_i |Δθ_i| · (d_i + S_{>i} / 2)   (revolute)   + Σ_i |Δθ_i|   (prismatic)
//! ```
//!
//! where `d_i` bounds the distance from joint `i`'s axis of every point of a sphere known at
//! one end of the segment (its centre's distance to the axis plus its radius). Either end may
//! serve (reverse the segment). Near the tool, where the wrist joints' axes pass close to the
//! hand, this is several times smaller than the static bound.

use super::{Chain, MotionKind};
use nalgebra::{IsometryMatrix3, Point3, Vector3};

/// One joint's share of a link's displacement bound.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Lever {
    /// The entry of `q` that drives the joint.
    source: usize,
    /// `|multiplier|` of the drive (1 without mimic joints).
    gain: f64,
    /// Revolute: the lever arm (m) to the link origin; prismatic: `None`.
    arm: Option<f64>,
}

/// Displacement bounds for every link of a chain ([`Chain::sweep_bound`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SweepBound {
    /// Per link of [`Chain::link_names`]: the joints that move it.
    levers: Vec<Vec<Lever>>,
    /// Per moving segment: a link carried by it and that link's frame in the segment's
    /// aligned frame (whose `z` axis is the joint axis), `link_from_aligned`.
    axis_links: Vec<(usize, IsometryMatrix3<f64>)>,
}

/// A joint's axis at one configuration: a point on it and its unit direction.
pub type JointAxis = (Point3<f64>, Vector3<f64>);

/// Every moving joint's axis at one configuration, in the frame the link frames were given
/// in ([`SweepBound::axes_into`]).
pub type JointAxes = Vec<JointAxis>;

impl SweepBound {
    /// An upper bound (m) on how far any point within `reach` (m) of link `link`'s origin
    /// moves, in the chain's base frame, while the configuration moves along the straight line
    /// from `qa` to `qb` (rad / m). Links before the first moving joint never move (0).
    pub fn displacement(&self, link: usize, reach: f64, qa: &[f64], qb: &[f64]) -> f64 {
        self.levers[link]
            .iter()
            .map(|lever| {
                let turn = lever.gain * (qb[lever.source] - qa[lever.source]).abs();
                match lever.arm {
                    Some(arm) => turn * (arm + reach),
                    None => turn,
                }
            })
            .sum()
    }

    /// Every moving joint's axis (a point and the unit direction) in `frame` (empty when some
    /// moving joint carries no link of the chain: then the bound is the static one), given the link
    /// frames `base_from_link` of one configuration ([`Chain::link_frames_into`]) and
    /// `frame_from_base`, into `out` (cleared).
    pub fn axes_into(
        &self,
        frame_from_base: &IsometryMatrix3<f64>,
        frames: &[IsometryMatrix3<f64>],
        out: &mut JointAxes,
    ) {
        out.clear();
        out.extend(self.axis_links.iter().map(|(link, link_from_aligned)| {
            let aligned = frame_from_base * frames[*link] * link_from_aligned;
            (
                Point3::from(aligned.translation.vector),
                aligned.rotation * Vector3::z(),
            )
        }));
    }

    /// An upper bound (m) on how far any point of the sphere (`centre`, `radius`) riding on link
    /// `link` moves while the configuration moves along the straight line from `qa` to `qb`,
    /// where the sphere and the joint `axes` are known at `qa` (or, equally, at `qb`: the bound is
    /// symmetric in the ends), all in one frame. `reach` bounds the distance of the sphere's
    /// points from the link origin, as in [`SweepBound::displacement`]. Never larger than
    /// [`SweepBound::displacement`] (see the module documentation).
    pub fn displacement_near(
        &self,
        link: usize,
        reach: f64,
        (centre, radius): (&Point3<f64>, f64),
        axes: &[JointAxis],
        qa: &[f64],
        qb: &[f64],
    ) -> f64 {
        let mut near = 0.0;
        // The static bound of the joints after the current one.
        let mut later = 0.0;
        for (i, lever) in self.levers[link].iter().enumerate().rev() {
            let turn = lever.gain * (qb[lever.source] - qa[lever.source]).abs();
            match lever.arm {
                Some(arm) => {
                    let to_axis = axes.get(i).map_or(arm + reach, |(point, axis)| {
                        (centre - point).cross(axis).norm() + radius
                    });
                    near += turn * (to_axis + 0.5 * later);
                    later += turn * (arm + reach);
                }
                None => {
                    near += turn;
                    later += turn;
                }
            }
        }
        near.min(later)
    }

    /// Whether link `link` moves with some joint.
    pub fn moves(&self, link: usize) -> bool {
        !self.levers[link].is_empty()
    }
}

impl Chain {
    /// The moving joint (index in chain order, mimic joints counted) that carries link `link`
    /// directly, `None` for links before the first moving joint. Links carried by the same
    /// joint form one rigid body; links of consecutive joints are adjacent.
    pub fn link_joint(&self, link: usize) -> Option<usize> {
        self.link_slots.get(link).and_then(|slot| slot.segment)
    }

    /// The displacement bounds of every link (see the module documentation of `sweep`).
    pub fn sweep_bound(&self) -> SweepBound {
        let drive = |i: usize| match &self.drives {
            None => (i, 1.0, 0.0),
            Some(d) => (d[i].source, d[i].multiplier, d[i].offset),
        };
        let levers = self
            .link_slots
            .iter()
            .map(|slot| {
                let Some(last) = slot.segment else {
                    return Vec::new();
                };
                (0..=last)
                    .map(|i| {
                        let (source, multiplier, _) = drive(i);
                        let arm = match self.segments[i].kind {
                            MotionKind::Prismatic => None,
                            MotionKind::Revolute => {
                                // From joint i's origin to the link origin: every later
                                // offset, every prismatic travel from i on, and the link's own
                                // offset in its segment's frame.
                                let mut arm = slot.translation.norm();
                                for m in i..=last {
                                    if m > i {
                                        arm += self.segments[m].translation.norm();
                                    }
                                    arm += self.travel(m);
                                }
                                Some(arm)
                            }
                        };
                        Lever {
                            source,
                            gain: multiplier.abs(),
                            arm,
                        }
                    })
                    .collect()
            })
            .collect();
        let axis_links = (0..self.segments.len())
            .map(|i| {
                let link = self
                    .link_slots
                    .iter()
                    .position(|slot| slot.segment == Some(i))?;
                let slot = &self.link_slots[link];
                let aligned_from_link = IsometryMatrix3::from_parts(
                    slot.translation.into(),
                    nalgebra::Rotation3::from_matrix_unchecked(slot.rotation),
                );
                Some((link, aligned_from_link.inverse()))
            })
            .collect::<Option<Vec<_>>>()
            // Without a link on every moving joint the axes are unknown: the static bound.
            .unwrap_or_default();
        SweepBound { levers, axis_links }
    }
}

#[cfg(test)]
mod tests {
    use crate::robot::builtin::{baxter, Arm};
    use rand::{rngs::StdRng, RngExt, SeedableRng};

    #[test]
    fn no_point_of_any_link_moves_farther_than_the_bound() {
        // Oracle: the link frames along a finely subdivided straight joint motion; the path
        // length of points at distance `reach` from each link origin (along the frame axes)
        // never exceeds the bound.
        let chain = baxter(Arm::Left);
        let bound = chain.sweep_bound();
        let mut rng = StdRng::seed_from_u64(7);
        let n = chain.dof();
        let reach = 0.3;
        for _ in 0..50 {
            let qa: Vec<f64> = (0..n)
                .map(|j| rng.random_range(chain.lower()[j]..chain.upper()[j]))
                .collect();
            let qb: Vec<f64> = qa
                .iter()
                .enumerate()
                .map(|(j, &v)| {
                    (v + rng.random_range(-0.4..0.4)).clamp(chain.lower()[j], chain.upper()[j])
                })
                .collect();
            let steps = 400;
            let frames: Vec<_> = (0..=steps)
                .map(|s| {
                    let t = s as f64 / steps as f64;
                    let q: Vec<f64> = qa.iter().zip(&qb).map(|(a, b)| a + t * (b - a)).collect();
                    chain.link_frames(&q).unwrap()
                })
                .collect();
            for link in 0..chain.link_names().len() {
                let limit = bound.displacement(link, reach, &qa, &qb);
                for offset in [
                    nalgebra::Point3::origin(),
                    nalgebra::Point3::new(reach, 0.0, 0.0),
                    nalgebra::Point3::new(0.0, -reach, 0.0),
                    nalgebra::Point3::new(0.0, 0.0, reach),
                ] {
                    let travelled: f64 = frames
                        .windows(2)
                        .map(|w| (w[1][link] * offset - w[0][link] * offset).norm())
                        .sum();
                    assert!(
                        travelled <= limit + 1e-12,
                        "link {link}: travelled {travelled} > bound {limit}"
                    );
                }
                if !bound.moves(link) {
                    assert_eq!(limit, 0.0);
                }
            }
        }
    }

    #[test]
    fn the_bound_near_a_configuration_holds_and_is_tighter() {
        // Oracle: as above, the path length of sample points of spheres on every link along a
        // finely subdivided straight joint motion; the near bound, taken at either end, is
        // never below it and never above the static bound.
        let chain = baxter(Arm::Left);
        let bound = chain.sweep_bound();
        let mut rng = StdRng::seed_from_u64(8);
        let n = chain.dof();
        let identity = nalgebra::IsometryMatrix3::identity();
        let (mut near_total, mut static_total) = (0.0, 0.0);
        for _ in 0..40 {
            let qa: Vec<f64> = (0..n)
                .map(|j| rng.random_range(chain.lower()[j]..chain.upper()[j]))
                .collect();
            let step = rng.random_range(0.01..0.4);
            let qb: Vec<f64> = qa
                .iter()
                .enumerate()
                .map(|(j, &v)| {
                    (v + rng.random_range(-step..step)).clamp(chain.lower()[j], chain.upper()[j])
                })
                .collect();
            let steps = 400;
            let frames: Vec<_> = (0..=steps)
                .map(|s| {
                    let t = s as f64 / steps as f64;
                    let q: Vec<f64> = qa.iter().zip(&qb).map(|(a, b)| a + t * (b - a)).collect();
                    chain.link_frames(&q).unwrap()
                })
                .collect();
            let mut axes_a = Vec::new();
            let mut axes_b = Vec::new();
            bound.axes_into(&identity, &frames[0], &mut axes_a);
            bound.axes_into(&identity, &frames[steps], &mut axes_b);
            for link in 0..chain.link_names().len() {
                if !bound.moves(link) {
                    continue;
                }
                // A sphere of radius 0.05 centred 0.1 m along the link's x axis.
                let (offset, radius) = (nalgebra::Point3::new(0.1, 0.0, 0.0), 0.05);
                let reach = 0.1 + radius;
                let at_a = frames[0][link] * offset;
                let at_b = frames[steps][link] * offset;
                let near_a =
                    bound.displacement_near(link, reach, (&at_a, radius), &axes_a, &qa, &qb);
                let near_b =
                    bound.displacement_near(link, reach, (&at_b, radius), &axes_b, &qa, &qb);
                let fixed = bound.displacement(link, reach, &qa, &qb);
                for point in [
                    offset,
                    offset + nalgebra::Vector3::new(radius, 0.0, 0.0),
                    offset + nalgebra::Vector3::new(0.0, -radius, 0.0),
                    offset + nalgebra::Vector3::new(0.0, 0.0, radius),
                ] {
                    let travelled: f64 = frames
                        .windows(2)
                        .map(|w| (w[1][link] * point - w[0][link] * point).norm())
                        .sum();
                    for near in [near_a, near_b] {
                        assert!(
                            travelled <= near + 1e-12,
                            "link {link}: travelled {travelled} > near bound {near}"
                        );
                    }
                }
                assert!(near_a <= fixed && near_b <= fixed);
                near_total += near_a;
                static_total += fixed;
            }
        }
        assert!(
            near_total < 0.8 * static_total,
            "near {near_total} vs static {static_total}"
        );
    }
}
