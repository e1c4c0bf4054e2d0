//! The unit tangent of a wrist path at a sample, in the base frame, for the task-relevant index.

use super::dynamic::DynamicManipulability;
use super::indices::{task_relevant, velocity_transmission_ratio, Direction};
use super::limits::joint_limit_penalty;
use super::settings::{IndexMeasure, JacobianRows, RankedIndex};
use crate::geometry::se3_log;
use nalgebra::{Dim, Isometry3, Matrix, Matrix6xX, Storage, Vector3, Vector6, U6};

/// Twists (m or rad per step) below this norm count as "the object is still": the sample is
/// skipped rather than divided by.
pub const STILL_TWIST_TOLERANCE: f64 = 1e-9;

/// The twist moving the wrist from `base_from_wrist` to `base_from_next`, as the velocity of the
/// wrist origin and the angular velocity along base-frame axes (the quantities `J` maps to).
fn base_frame_twist(
    base_from_wrist: &Isometry3<f64>,
    base_from_next: &Isometry3<f64>,
) -> Vector6<f64> {
    let body = se3_log(&(base_from_wrist.inverse() * base_from_next));
    let r = base_from_wrist.rotation;
    let v = r * Vector3::new(body[0], body[1], body[2]);
    let w = r * Vector3::new(body[3], body[4], body[5]);
    Vector6::new(v.x, v.y, v.z, w.x, w.y, w.z)
}

/// The unit direction of motion at a sample: `log(wrist_i⁻¹ · wrist_{i+1})` expressed in the
/// base frame, reduced to the rows `mode` measures (angular part scaled by L in `Twist` mode)
/// and normalised. `None` when the motion is below [`STILL_TWIST_TOLERANCE`].
pub fn wrist_tangent(
    base_from_wrist: &Isometry3<f64>,
    base_from_next: &Isometry3<f64>,
    mode: JacobianRows,
) -> Option<Direction> {
    let twist = base_frame_twist(base_from_wrist, base_from_next);
    let linear = Vector3::new(twist[0], twist[1], twist[2]);
    let angular = Vector3::new(twist[3], twist[4], twist[5]);
    mode.direction(&linear, &angular)
}

impl JacobianRows {
    /// The unit direction this mode measures for a motion with wrist-origin velocity `linear`
    /// and angular velocity `angular` (base frame): the rows it uses, the angular part scaled
    /// by L in `Twist` mode, normalised. `None` below [`STILL_TWIST_TOLERANCE`].
    pub fn direction(&self, linear: &Vector3<f64>, angular: &Vector3<f64>) -> Option<Direction> {
        match *self {
            JacobianRows::Twist { length_scale } => {
                if (linear.norm_squared() + angular.norm_squared()).sqrt() < STILL_TWIST_TOLERANCE {
                    return None;
                }
                let scaled = Vector6::new(
                    linear.x,
                    linear.y,
                    linear.z,
                    length_scale * angular.x,
                    length_scale * angular.y,
                    length_scale * angular.z,
                );
                let norm = scaled.norm();
                (norm > 0.0).then(|| Direction::Full(scaled / norm))
            }
            JacobianRows::Translation => {
                let norm = linear.norm();
                (norm >= STILL_TWIST_TOLERANCE).then(|| Direction::Translation(linear / norm))
            }
            JacobianRows::Rotation => {
                let norm = angular.norm();
                (norm >= STILL_TWIST_TOLERANCE).then(|| Direction::Rotation(angular / norm))
            }
        }
    }

    /// `M_T` in this mode for the unit `direction` from [`wrist_tangent`]: `‖J'ᵀ u‖²` where
    /// `J'` is `J` with its angular rows multiplied by L in `Twist` mode, else `J` itself.
    pub fn task_relevant<C: Dim, S: Storage<f64, U6, C>>(
        &self,
        jacobian: &Matrix<f64, U6, C, S>,
        direction: &Direction,
    ) -> f64 {
        match (*self, direction) {
            (JacobianRows::Twist { length_scale }, Direction::Full(u)) => {
                let weighted = Vector6::new(
                    u[0],
                    u[1],
                    u[2],
                    length_scale * u[3],
                    length_scale * u[4],
                    length_scale * u[5],
                );
                task_relevant(jacobian, &Direction::Full(weighted))
            }
            _ => task_relevant(jacobian, direction),
        }
    }

    /// `J'ᵀ u` into `out` (one entry per column of `jacobian`), with `J'` as in
    /// [`JacobianRows::task_relevant`]: its squared norm is `M_T`.
    pub fn projection_into<C: Dim, S: Storage<f64, U6, C>>(
        &self,
        jacobian: &Matrix<f64, U6, C, S>,
        direction: &Direction,
        out: &mut [f64],
    ) {
        let mut weights = direction.as_full();
        if let (JacobianRows::Twist { length_scale }, Direction::Full(_)) = (*self, direction) {
            for w in weights.iter_mut().skip(3) {
                *w *= length_scale;
            }
        }
        for (c, entry) in out.iter_mut().enumerate().take(jacobian.ncols()) {
            *entry = (0..6).map(|r| jacobian[(r, c)] * weights[r]).sum();
        }
    }

    /// The velocity transmission ratio `1 / √(uᵀ (J' J'ᵀ)⁻¹ u)` in this mode for the unit
    /// `direction` from [`wrist_tangent`], with `J'` as in [`JacobianRows::task_relevant`].
    pub fn velocity_ratio<C: Dim, S: Storage<f64, U6, C>>(
        &self,
        jacobian: &Matrix<f64, U6, C, S>,
        direction: &Direction,
    ) -> f64 {
        match *self {
            JacobianRows::Twist { length_scale } => {
                let weighted = Matrix6xX::from_fn(jacobian.ncols(), |r, c| {
                    jacobian[(r, c)] * if r < 3 { 1.0 } else { length_scale }
                });
                velocity_transmission_ratio(&weighted, direction)
            }
            _ => velocity_transmission_ratio(jacobian, direction),
        }
    }
}

impl RankedIndex {
    /// The ranked value at configuration `q` (joint limits `lower`, `upper`) with Jacobian
    /// `jacobian` (base frame, rows `[v; ω]`), for the unit `direction` of motion measured in
    /// `rows`: the measure, times the joint-limit penalty when one is set. The dynamic measure
    /// is evaluated with `dynamic` (the arm's model with what it holds at `q`); without it
    /// that measure is NaN.
    pub fn value<C: Dim, S: Storage<f64, U6, C>>(
        &self,
        rows: JacobianRows,
        jacobian: &Matrix<f64, U6, C, S>,
        direction: &Direction,
        [q, lower, upper]: [&[f64]; 3],
        dynamic: Option<&mut DynamicManipulability<'_>>,
    ) -> f64 {
        let measure = match self.measure {
            IndexMeasure::TaskRelevant | IndexMeasure::Duration => {
                rows.task_relevant(jacobian, direction)
            }
            IndexMeasure::VelocityRatio => rows.velocity_ratio(jacobian, direction),
            IndexMeasure::Dynamic => {
                dynamic.map_or(f64::NAN, |d| d.task_relevant(rows, jacobian, direction, q))
            }
        };
        match self.joint_limit_penalty {
            None => measure,
            Some(k) => measure * joint_limit_penalty(q, lower, upper, k),
        }
    }
}
