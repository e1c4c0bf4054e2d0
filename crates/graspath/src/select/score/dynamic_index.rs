//! The dynamic task-relevant manipulability of a candidate
//! ([`DynamicManipulability`]): evaluated at each path sample with the carried object held at
//! the tool, ranked by with `index.measure: dynamic`, and reported for the chosen motion as
//! the task's norm of its series whenever the arm's dynamics is known (the object has a mass,
//! or the task ranks by it).

use super::path::{index_along, ObjectMotion};
use super::Scoring;
use crate::manipulability::DynamicManipulability;
use crate::manipulability::{IndexMeasure, RankedIndex};
use nalgebra::Matrix6xX;

/// The dynamic index's workspace for `scoring`'s candidate: the arm's dynamics with the object
/// (its mass properties moved from the object frame to the tool frame by the grasp) held at the
/// tool. `None` when the arm's dynamics is not part of the task or a joint has no effort limit
/// (the task builder refuses the latter when the task ranks by the measure).
pub(super) fn dynamic_workspace<'a>(scoring: &Scoring<'a>) -> Option<DynamicManipulability<'a>> {
    let dynamics = scoring.setup.arm.dynamics.as_deref()?;
    let wrist_from_object = scoring.candidate.object_from_wrist.inverse();
    let payload = scoring
        .setup
        .world
        .payload
        .map(|body| body.transformed(&wrist_from_object));
    DynamicManipulability::new(dynamics, payload).ok()
}

/// The task's norm of `M_D` along the path part `path_q` of the chosen motion (the samples
/// marked in `counted`; `times` in s).
pub(super) fn dynamic_norm(
    scoring: &Scoring<'_>,
    workspace: &mut DynamicManipulability<'_>,
    motion: &ObjectMotion,
    path_q: &[Vec<f64>],
    (times, counted): (&[f64], &[bool]),
) -> Option<f64> {
    let setup = scoring.setup;
    let dynamic = RankedIndex {
        measure: IndexMeasure::Dynamic,
        joint_limit_penalty: None,
        over: setup.ranked.over,
    };
    let mut jacobian = Matrix6xX::zeros(setup.arm.chain.dof());
    let series = index_along(
        &setup.arm.chain,
        motion,
        &scoring.candidate.object_from_wrist,
        path_q,
        (setup.rows, dynamic),
        &mut jacobian,
        Some(workspace),
    );
    let value = series.norms(times, counted).value(setup.norm);
    value.is_finite().then_some(value)
}
