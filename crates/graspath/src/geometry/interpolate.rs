//! Interpolation between two poses.

use super::quaternion::quaternion_in_hemisphere_of;
use super::se3::{se3_exp, se3_log};
use nalgebra::{Isometry3, Translation3};

/// Decoupled interpolation at `s ∈ [0, 1]`: the origin moves on the straight line from `a` to
/// `b` and the orientation follows the shortest slerp (antipodal quaternions handled).
pub fn interpolate_decoupled(a: &Isometry3<f64>, b: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    let translation = a.translation.vector.lerp(&b.translation.vector, s);
    let rb = quaternion_in_hemisphere_of(&b.rotation, &a.rotation);
    let rotation = a
        .rotation
        .try_slerp(&rb, s, 1e-12)
        .unwrap_or_else(|| a.rotation.nlerp(&rb, s));
    Isometry3::from_parts(Translation3::from(translation), rotation)
}

/// Screw interpolation at `s ∈ [0, 1]`: `a · exp(s · log(a⁻¹ b))`, the constant-twist motion
/// (a rigid body rotating about and sliding along one fixed axis).
pub fn interpolate_screw(a: &Isometry3<f64>, b: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    let twist = se3_log(&(a.inverse() * b));
    a * se3_exp(&(twist * s))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{UnitQuaternion, Vector3};

    fn poses() -> (Isometry3<f64>, Isometry3<f64>) {
        let a = Isometry3::from_parts(
            Translation3::new(0.1, 0.2, 0.3),
            UnitQuaternion::from_scaled_axis(Vector3::new(0.1, 0.2, -0.3)),
        );
        let b = Isometry3::from_parts(
            Translation3::new(-0.4, 0.5, 0.0),
            UnitQuaternion::from_scaled_axis(Vector3::new(1.0, -0.5, 0.7)),
        );
        (a, b)
    }

    #[test]
    fn endpoints_are_reproduced() {
        let (a, b) = poses();
        for f in [interpolate_decoupled, interpolate_screw] {
            let start = f(&a, &b, 0.0);
            let end = f(&a, &b, 1.0);
            assert_relative_eq!(start.to_homogeneous(), a.to_homogeneous(), epsilon = 1e-12);
            assert_relative_eq!(end.to_homogeneous(), b.to_homogeneous(), epsilon = 1e-12);
        }
    }

    #[test]
    fn decoupled_midpoint_is_halfway_in_position_and_angle() {
        let (a, b) = poses();
        let mid = interpolate_decoupled(&a, &b, 0.5);
        assert_relative_eq!(
            mid.translation.vector,
            (a.translation.vector + b.translation.vector) / 2.0,
            epsilon = 1e-15
        );
        let total = a.rotation.angle_to(&b.rotation);
        assert_relative_eq!(
            a.rotation.angle_to(&mid.rotation),
            total / 2.0,
            epsilon = 1e-12
        );
    }

    #[test]
    fn antipodal_target_takes_the_short_way() {
        let a = Isometry3::identity();
        let q = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.4));
        let b = Isometry3::from_parts(
            Translation3::identity(),
            UnitQuaternion::new_unchecked(-q.into_inner()),
        );
        let mid = interpolate_decoupled(&a, &b, 0.5);
        assert_relative_eq!(mid.rotation.angle(), 0.2, epsilon = 1e-12);
    }

    #[test]
    fn screw_motion_of_a_pure_rotation_keeps_the_axis_fixed() {
        // Rotating 90° about the z axis through (1, 0, 0): the point (1, 0, 5) never moves.
        let about = Isometry3::translation(1.0, 0.0, 0.0);
        let b = about
            * Isometry3::rotation(Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2))
            * about.inverse();
        let a = Isometry3::identity();
        for k in 0..=10 {
            let x = interpolate_screw(&a, &b, k as f64 / 10.0);
            let p = x.transform_point(&nalgebra::Point3::new(1.0, 0.0, 5.0));
            assert_relative_eq!(p.coords, Vector3::new(1.0, 0.0, 5.0), epsilon = 1e-12);
        }
    }
}
