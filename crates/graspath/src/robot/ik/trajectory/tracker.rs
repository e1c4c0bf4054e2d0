//! The state of one trajectory's solve ([`Tracker`]) and what its branch search, tracking and
//! recovery share: the joint-space distance that accepts a step, the seeded generators of the
//! restarts, the text that names a joint outside its limits.

use super::options::TrajectoryIkOptions;
use crate::random::trajectory_restart_seed;
use crate::robot::ik::kernel::Kernel;
use nalgebra::Isometry3;
use rand::rngs::Xoshiro256PlusPlus;
use rand::SeedableRng;

/// Random restarts anywhere in the limits, to tell a discontinuity from unreachability.
pub(super) const CLASSIFY_RESTARTS: usize = 3;

/// Largest absolute difference between two configurations (rad / m).
pub(super) fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// One trajectory's solve: the kernel (the chain, its limits and the tolerances), the tip poses
/// (chain base frame, m, in order) and the options. Its branch search at the first pose, its
/// tracking and its per-sample recovery are in the files beside this one.
pub(super) struct Tracker<'a> {
    pub(super) kernel: Kernel<'a>,
    pub(super) poses: &'a [Isometry3<f64>],
    pub(super) options: &'a TrajectoryIkOptions,
}

impl Tracker<'_> {
    /// The number of joints.
    pub(super) fn n(&self) -> usize {
        self.kernel.dof()
    }

    /// The generator of the restarts of `branch` at `sample`, from the options' random seed.
    pub(super) fn rng(&self, branch: usize, sample: usize) -> Xoshiro256PlusPlus {
        Xoshiro256PlusPlus::seed_from_u64(trajectory_restart_seed(
            self.options.ik.random_seed,
            branch,
            sample,
        ))
    }

    /// Names the joint farthest outside its limits in `q`.
    pub(super) fn limit_detail(&self, q: &[f64]) -> String {
        let chain = self.kernel.chain;
        let (mut worst, mut excess) = (0usize, 0.0f64);
        for (j, &v) in q.iter().enumerate() {
            let e = (chain.lower()[j] - v).max(v - chain.upper()[j]);
            if e > excess {
                worst = j;
                excess = e;
            }
        }
        format!(
            "the nearest solution needs joint '{}' at {:.4}, outside its limits [{:.4}, {:.4}]",
            chain.joint_names()[worst],
            q[worst],
            chain.lower()[worst],
            chain.upper()[worst]
        )
    }
}
