//! Two arms moving at once: every moving body of one against every moving body of the other,
//! at every shared sample and between samples (both arms' displacement bounds add up), with
//! the same proven bound as a single arm's motion ([`super::motion`]).

use super::arm::ArmBodies;
use super::body::Placed;
use super::motion::CollisionHit;
use nalgebra::{Isometry3, IsometryMatrix3};

/// Every link frame of a chain at one configuration.
type Frames = Vec<IsometryMatrix3<f64>>;

/// One arm's whole motion for the arm-against-arm check.
#[derive(Debug, Clone, Copy)]
pub struct ArmMotion<'a> {
    /// The arm's bodies.
    pub arm: &'a ArmBodies,
    /// Where its base is, `world_from_base`.
    pub world_from_base: &'a Isometry3<f64>,
    /// Its configurations, one per shared sample (rad / m).
    pub q: &'a [Vec<f64>],
    /// A prefix for body names in messages (`left arm: `).
    pub label: &'a str,
}

/// The first sample (or interval) where a moving body of `first` touches a moving body of
/// `second`; both motions must have the same number of samples (the shorter is used
/// otherwise). Touching counts: the arms must keep apart. `resolution` is the continuous
/// check's resolution (m).
pub fn check_arms(
    first: &ArmMotion<'_>,
    second: &ArmMotion<'_>,
    resolution: f64,
) -> Option<CollisionHit> {
    let n = first.q.len().min(second.q.len());
    let moving = |m: &ArmMotion<'_>| -> Vec<usize> {
        (0..m.arm.bodies.len())
            .filter(|&i| m.arm.bodies[i].group > 0)
            .collect()
    };
    let (a_bodies, b_bodies) = (moving(first), moving(second));
    if a_bodies.is_empty() || b_bodies.is_empty() || n == 0 {
        return None;
    }
    let frames_of = |m: &ArmMotion<'_>, q: &[f64]| -> Option<Vec<IsometryMatrix3<f64>>> {
        m.arm.chain().link_frames(q).ok()
    };
    let base =
        |m: &ArmMotion<'_>| -> IsometryMatrix3<f64> { nalgebra::convert(*m.world_from_base) };
    let (base_a, base_b) = (base(first), base(second));
    let distance_at =
        |fa: &[IsometryMatrix3<f64>], fb: &[IsometryMatrix3<f64>], i: usize, j: usize| {
            let pa = first.arm.place(i, &base_a, fa);
            let pb = second.arm.place(j, &base_b, fb);
            (pa.gap(&pb), pa, pb)
        };
    let name = |m: &ArmMotion<'_>, p: &Placed<'_>| format!("{}{}", m.label, p.body.name());
    let mut previous: Option<(Frames, Frames)> = None;
    for s in 0..n {
        let fa = frames_of(first, &first.q[s])?;
        let fb = frames_of(second, &second.q[s])?;
        for &i in &a_bodies {
            for &j in &b_bodies {
                let (gap, pa, pb) = distance_at(&fa, &fb, i, j);
                let d = if gap > 0.0 { gap } else { pa.distance(&pb) };
                if d <= 0.0 {
                    return Some(CollisionHit {
                        sample: s,
                        between: false,
                        bodies: [name(first, &pa), name(second, &pb)],
                        distance: d,
                        required: 0.0,
                    });
                }
                let Some((pfa, pfb)) = &previous else {
                    continue;
                };
                let r = s - 1;
                let bound = first.arm.displacement(i, &first.q[r], &first.q[s])
                    + second.arm.displacement(j, &second.q[r], &second.q[s]);
                let (gap_before, qa, qb) = distance_at(pfa, pfb, i, j);
                if gap_before + d - bound > 0.0 {
                    continue;
                }
                let before = qa.distance(&qb);
                let exact_now = pa.distance(&pb);
                let search = PairSearch {
                    first,
                    second,
                    base_a: &base_a,
                    base_b: &base_b,
                    i,
                    j,
                    resolution,
                };
                if let Some(mut hit) = search.run(
                    (&first.q[r], &second.q[r], before),
                    (&first.q[s], &second.q[s], exact_now),
                    bound,
                ) {
                    hit.sample = r;
                    return Some(hit);
                }
            }
        }
        previous = Some((fa, fb));
    }
    None
}

/// The continuous check of one body pair of two arms over one interval.
struct PairSearch<'s, 'a> {
    first: &'s ArmMotion<'a>,
    second: &'s ArmMotion<'a>,
    base_a: &'s IsometryMatrix3<f64>,
    base_b: &'s IsometryMatrix3<f64>,
    i: usize,
    j: usize,
    resolution: f64,
}

impl PairSearch<'_, '_> {
    fn run(
        &self,
        (qa0, qb0, d0): (&[f64], &[f64], f64),
        (qa1, qb1, d1): (&[f64], &[f64], f64),
        bound: f64,
    ) -> Option<CollisionHit> {
        if d0 + d1 - bound > 0.0 || bound < self.resolution {
            return None;
        }
        let mid = |x: &[f64], y: &[f64]| -> Vec<f64> {
            x.iter().zip(y).map(|(a, b)| 0.5 * (a + b)).collect()
        };
        let (qa, qb) = (mid(qa0, qa1), mid(qb0, qb1));
        let fa = self.first.arm.chain().link_frames(&qa).ok()?;
        let fb = self.second.arm.chain().link_frames(&qb).ok()?;
        let pa = self.first.arm.place(self.i, self.base_a, &fa);
        let pb = self.second.arm.place(self.j, self.base_b, &fb);
        let d = pa.distance(&pb);
        if d <= 0.0 {
            return Some(CollisionHit {
                sample: 0,
                between: true,
                bodies: [
                    format!("{}{}", self.first.label, pa.body.name()),
                    format!("{}{}", self.second.label, pb.body.name()),
                ],
                distance: d,
                required: 0.0,
            });
        }
        self.run((qa0, qb0, d0), (&qa, &qb, d), bound / 2.0)
            .or_else(|| self.run((&qa, &qb, d), (qa1, qb1, d1), bound / 2.0))
    }
}
