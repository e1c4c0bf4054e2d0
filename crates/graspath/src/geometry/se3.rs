//! The exponential and logarithm maps of SO(3) and SE(3).

use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3, Vector6};

/// A twist `[v; ω]`: linear part (m, or m/s) first, angular part (rad, or rad/s) second.
pub type Twist = Vector6<f64>;

/// Below this rotation angle (rad) the closed forms switch to their Taylor series.
const SMALL_ANGLE: f64 = 1e-6;

fn skew(w: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

/// The rotation vector `θ·axis` (rad) of a rotation matrix: the logarithm of SO(3).
///
/// Accurate near the identity and near a half turn (there it goes through the quaternion,
/// whose axis is well defined).
pub fn so3_log(rotation: &Rotation3<f64>) -> Vector3<f64> {
    let q = UnitQuaternion::from_rotation_matrix(rotation);
    quaternion_log(&q)
}

fn quaternion_log(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    // Take the representative with w >= 0 so the angle is in [0, π].
    let (w, v) = if q.w < 0.0 {
        (-q.w, -q.imag())
    } else {
        (q.w, q.imag())
    };
    let sin_half = v.norm();
    if sin_half < SMALL_ANGLE {
        // θ·axis = 2·v·(θ/2)/sin(θ/2) ≈ 2v(1 + sin²/6)
        return v * (2.0 * (1.0 + sin_half * sin_half / 6.0));
    }
    let angle = 2.0 * sin_half.atan2(w);
    v * (angle / sin_half)
}

/// The SE(3) logarithm: the twist `ξ = [v; ω]` with `se3_exp(ξ) == pose`.
///
/// `ω` is the rotation vector (rad) and `v` the linear part (m) of the screw, both in the
/// frame the pose maps from (a body twist when `pose = a_from_a'`).
pub fn se3_log(pose: &Isometry3<f64>) -> Twist {
    let omega = quaternion_log(&pose.rotation);
    let t = pose.translation.vector;
    let theta = omega.norm();
    let w = skew(&omega);
    // V⁻¹ = I − ½W + c·W², c = (1 − θ sinθ / (2(1 − cosθ))) / θ²
    let c = if theta < 1e-4 {
        1.0 / 12.0 + theta * theta / 720.0
    } else {
        (1.0 - theta * theta.sin() / (2.0 * (1.0 - theta.cos()))) / (theta * theta)
    };
    let v = t - 0.5 * (w * t) + c * (w * (w * t));
    Vector6::new(v.x, v.y, v.z, omega.x, omega.y, omega.z)
}

/// The SE(3) exponential of a twist `[v; ω]` (m, rad).
pub fn se3_exp(twist: &Twist) -> Isometry3<f64> {
    let v = Vector3::new(twist[0], twist[1], twist[2]);
    let omega = Vector3::new(twist[3], twist[4], twist[5]);
    let theta = omega.norm();
    let w = skew(&omega);
    // V = I + b·W + c·W², b = (1 − cosθ)/θ², c = (θ − sinθ)/θ³
    let (b, c) = if theta < 1e-4 {
        let t2 = theta * theta;
        (0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0)
    } else {
        let t2 = theta * theta;
        (
            (1.0 - theta.cos()) / t2,
            (theta - theta.sin()) / (t2 * theta),
        )
    };
    let translation = v + b * (w * v) + c * (w * (w * v));
    Isometry3::from_parts(
        Translation3::from(translation),
        UnitQuaternion::from_scaled_axis(omega),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    fn twist_strategy() -> impl Strategy<Value = Twist> {
        (
            prop::array::uniform3(-2.0..2.0f64),
            prop::array::uniform3(-1.7..1.7f64),
        )
            .prop_map(|(v, w)| Vector6::new(v[0], v[1], v[2], w[0], w[1], w[2]))
    }

    proptest! {
        #[test]
        fn log_inverts_exp(twist in twist_strategy()) {
            let back = se3_log(&se3_exp(&twist));
            prop_assert!((back - twist).norm() < 1e-9, "{back} vs {twist}");
        }

        #[test]
        fn exp_matches_finite_flow(twist in twist_strategy()) {
            // Oracle: integrate the body velocity ẋ = x·ξ^ with many small steps.
            let steps = 4000;
            let mut x = Isometry3::identity();
            let dt = 1.0 / steps as f64;
            let v = Vector3::new(twist[0], twist[1], twist[2]);
            let w = Vector3::new(twist[3], twist[4], twist[5]);
            for _ in 0..steps {
                let step = Isometry3::from_parts(
                    Translation3::from(v * dt + 0.5 * w.cross(&v) * dt * dt),
                    UnitQuaternion::from_scaled_axis(w * dt),
                );
                x *= step;
            }
            let e = se3_exp(&twist);
            prop_assert!((e.translation.vector - x.translation.vector).norm() < 1e-5);
            prop_assert!(e.rotation.angle_to(&x.rotation) < 1e-6);
        }
    }

    #[test]
    fn log_near_half_turn_is_accurate() {
        let axis = Vector3::new(1.0, 2.0, -0.5).normalize();
        let angle = std::f64::consts::PI - 1e-9;
        let rot = Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle);
        let w = so3_log(&rot);
        assert_relative_eq!(w.norm(), angle, epsilon = 1e-12);
        assert_relative_eq!(w.normalize(), axis, epsilon = 1e-7);
    }

    #[test]
    fn log_of_pure_translation_is_translation() {
        let pose = Isometry3::translation(0.1, -0.2, 0.3);
        let xi = se3_log(&pose);
        assert_relative_eq!(
            xi,
            Vector6::new(0.1, -0.2, 0.3, 0.0, 0.0, 0.0),
            epsilon = 1e-15
        );
    }
}
