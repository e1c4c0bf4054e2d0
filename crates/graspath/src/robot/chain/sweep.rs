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

use super::{Chain, MotionKind};

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
}

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
        // The largest |value| of segment i's joint: the travel a prismatic joint adds.
        let travel = |i: usize| {
            let (source, multiplier, offset) = drive(i);
            multiplier.abs() * self.lower[source].abs().max(self.upper[source].abs()) + offset.abs()
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
                                    if self.segments[m].kind == MotionKind::Prismatic {
                                        arm += travel(m);
                                    }
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
        SweepBound { levers }
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
}
