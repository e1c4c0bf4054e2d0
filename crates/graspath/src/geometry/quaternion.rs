//! Quaternion helpers that treat `q` and `−q` as the same rotation.

use nalgebra::{Quaternion, UnitQuaternion};

/// `q` or `−q`, whichever lies in the same hemisphere as `reference` (non-negative dot product).
///
/// Averaging, interpolating or differencing quaternions is only meaningful after this.
pub fn quaternion_in_hemisphere_of(
    q: &UnitQuaternion<f64>,
    reference: &UnitQuaternion<f64>,
) -> UnitQuaternion<f64> {
    if q.coords.dot(&reference.coords) < 0.0 {
        UnitQuaternion::new_unchecked(-q.into_inner())
    } else {
        *q
    }
}

/// The angle (rad, in `[0, π]`) of the rotation between `a` and `b`; the same for `b` and `−b`.
pub fn quaternion_angle_between(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> f64 {
    let relative = a.inverse() * b;
    let w = relative.w.abs().min(1.0);
    let s = relative.imag().norm();
    2.0 * s.atan2(w)
}

/// A unit quaternion from `[x, y, z, w]` (the ROS / Eigen storage order), normalised.
///
/// Returns `None` when the four numbers are not finite or their norm is below 1e-9.
pub fn quaternion_xyzw(xyzw: [f64; 4]) -> Option<UnitQuaternion<f64>> {
    if xyzw.iter().any(|c| !c.is_finite()) {
        return None;
    }
    let mut q = Quaternion::new(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);
    if !q.norm_squared().is_finite() {
        // Entries so large that the norm overflows: the same rotation, scaled down.
        q = q / q.coords.amax();
    }
    if q.norm() < 1e-9 {
        return None;
    }
    Some(UnitQuaternion::from_quaternion(q))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::Vector3;

    #[test]
    fn angle_is_the_same_for_antipodal_quaternions() {
        let a = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.2, 0.1));
        let b = UnitQuaternion::from_scaled_axis(Vector3::new(-0.4, 0.9, 0.2));
        let minus_b = UnitQuaternion::new_unchecked(-b.into_inner());
        assert_relative_eq!(
            quaternion_angle_between(&a, &b),
            quaternion_angle_between(&a, &minus_b),
            epsilon = 1e-14
        );
        assert_relative_eq!(
            quaternion_angle_between(&a, &b),
            a.angle_to(&b),
            epsilon = 1e-12
        );
    }

    #[test]
    fn hemisphere_flip_keeps_the_rotation() {
        let r = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.2));
        let q = UnitQuaternion::new_unchecked(-r.into_inner());
        let flipped = quaternion_in_hemisphere_of(&q, &r);
        assert!(flipped.coords.dot(&r.coords) > 0.0);
        assert_relative_eq!(
            flipped.to_rotation_matrix(),
            q.to_rotation_matrix(),
            epsilon = 1e-15
        );
    }

    #[test]
    fn xyzw_rejects_zero_and_nan() {
        assert!(quaternion_xyzw([0.0; 4]).is_none());
        // Entries whose norm overflows keep their rotation.
        let huge = quaternion_xyzw([0.0, 0.0, 1e300, 1e300]).expect("a rotation");
        let expected = quaternion_xyzw([0.0, 0.0, 1.0, 1.0]).unwrap();
        assert!(huge.angle_to(&expected) < 1e-15);
        assert!(quaternion_xyzw([f64::NAN, 0.0, 0.0, 1.0]).is_none());
        let q = quaternion_xyzw([0.0, 0.0, 0.0, 2.0]).expect("identity");
        assert_relative_eq!(q.angle(), 0.0);
    }
}
