//! One attempt of the Levenberg–Marquardt kernel and what every solver does around it: where
//! attempt `k` starts and how joint limits enter it, its evaluation cap, the proof that no
//! attempt can reach a target, and the continuous joints of a result brought back near the
//! start. Single-pose solves ([`super::single_pose`]) and trajectory solves
//! ([`super::trajectory`]) share these, so that both make the same attempts in the same order.
//!
//! Frames and units as in [`super::kernel`]: base frame, m, rad.

use super::kernel::{Budget, Kernel, Patience, RunEnd, Strategy, Target, Workspace};
use crate::robot::chain::{Chain, OutOfReach};

/// Evaluations allowed for the attempts from the start configuration.
pub(crate) const START_ATTEMPT_CAP: usize = 80;
/// Evaluations allowed for an attempt from a random restart.
pub(crate) const RESTART_ATTEMPT_CAP: usize = 50;

/// A proof that no configuration reaches `target`, within the kernel's tolerances (see
/// [`Chain::out_of_reach`]).
pub(crate) fn out_of_reach(kernel: &Kernel<'_>, target: &Target) -> Option<OutOfReach> {
    kernel.chain.out_of_reach(
        &target.position,
        &target.rotation,
        kernel.position_tolerance,
        kernel.rotation_tolerance,
    )
}

/// The start of attempt `k`: `q_start` for the first two attempts (one per strategy), then a
/// uniformly random configuration, alternating the strategies.
pub(crate) fn prepare_attempt<R: rand::Rng>(
    kernel: &Kernel<'_>,
    k: usize,
    q_start: &[f64],
    rng: &mut R,
    q: &mut [f64],
) -> (Strategy, usize) {
    let n = kernel.dof();
    if k < 2 {
        q[..n].copy_from_slice(q_start);
        kernel.clamp(&mut q[..n]);
    } else {
        kernel.random_configuration(rng, &mut q[..n]);
    }
    let strategy = if k.is_multiple_of(2) {
        Strategy::Clamped
    } else {
        Strategy::LimitWeighted
    };
    let cap = if k < 2 {
        START_ATTEMPT_CAP
    } else {
        RESTART_ATTEMPT_CAP
    };
    (strategy, cap)
}

/// Runs one attempt: evaluates the start in `ws`, then Levenberg–Marquardt.
pub(crate) fn run_attempt(
    kernel: &Kernel<'_>,
    target: &Target,
    ws: &mut Workspace,
    strategy: Strategy,
    cap: usize,
    patience: Patience,
    budget: &mut Budget,
) -> RunEnd {
    if !budget.spend() {
        let state = ws.cur_mut();
        state.cost = f64::INFINITY;
        state.position_error = f64::INFINITY;
        state.rotation_error = f64::INFINITY;
        return RunEnd::OutOfBudget;
    }
    kernel.evaluate(target, ws.cur_mut());
    kernel.run(target, ws, strategy, cap, patience, budget)
}

/// Moves each continuous joint of `q` to within ±π of its value in `q_start` (same pose).
pub(crate) fn wrap_continuous(chain: &Chain, q_start: &[f64], q: &mut [f64]) {
    use std::f64::consts::{PI, TAU};
    for (j, v) in q.iter_mut().enumerate() {
        if chain.lower()[j].is_infinite() && chain.upper()[j].is_infinite() {
            let delta = *v - q_start[j];
            if delta.abs() > PI {
                *v = q_start[j] + (delta + PI).rem_euclid(TAU) - PI;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Isometry3;

    #[test]
    fn wrap_keeps_continuous_joints_near_the_start() {
        use crate::robot::{ChainSpec, JointKind, JointSpec};
        let joint = |name: &str, kind| JointSpec {
            name: name.into(),
            child_link: String::new(),
            kind,
            parent_from_joint: Isometry3::translation(0.0, 0.0, 0.1),
            axis: nalgebra::Vector3::z(),
            lower: if kind == JointKind::Continuous {
                f64::NEG_INFINITY
            } else {
                -1.0
            },
            upper: if kind == JointKind::Continuous {
                f64::INFINITY
            } else {
                1.0
            },
            mimic: None,
            limits: Default::default(),
            child_inertial: None,
        };
        let chain = Chain::from_spec(&ChainSpec {
            source_name: "test".into(),
            base_link: "a".into(),
            tip_link: "b".into(),
            joints: vec![
                joint("c", JointKind::Continuous),
                joint("r", JointKind::Revolute),
            ],
            tip_from_tool: None,
        })
        .expect("valid");
        let mut q = vec![7.0, 0.5];
        wrap_continuous(&chain, &[0.0, 0.0], &mut q);
        assert!((q[0] - (7.0 - std::f64::consts::TAU)).abs() < 1e-12);
        assert_eq!(q[1], 0.5);
    }
}
