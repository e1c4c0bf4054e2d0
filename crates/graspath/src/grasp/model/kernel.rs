//! Pose kernels: the antipodally symmetric quaternion distance, von Mises–Fisher rotations
//! on S³ (Wood's algorithm), kernel sampling, and per-item random generators derived from one
//! seed (so that parallel work gives the same numbers at any thread count).

use crate::random::derive_seed;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rand::{rngs::StdRng, RngExt, SeedableRng};
use rand_distr::{Beta, Distribution, StandardNormal};

/// `1 − |a·b|`: zero for the same rotation (q or −q), 1 for rotations half a turn apart;
/// ≈ θ²/8 for a small relative angle θ. The vectorised query kernels compute it inline; this
/// scalar form is the oracle their tests compare against.
#[cfg(test)]
pub(super) fn quaternion_distance(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> f64 {
    1.0 - a.coords.dot(&b.coords).abs()
}

/// The random generator of item `index` of stream `stream` under `seed`.
pub(super) fn item_rng(seed: u64, stream: u64, index: u64) -> StdRng {
    StdRng::seed_from_u64(derive_seed(seed, stream, index))
}

/// A uniform unit 3-vector.
pub(super) fn unit_vector(rng: &mut StdRng) -> Vector3<f64> {
    loop {
        let v = Vector3::from_fn(|_, _| StandardNormal.sample(rng));
        let n: f64 = v.norm();
        if n > 1e-12 {
            return v / n;
        }
    }
}

/// A rotation δ drawn from the von Mises–Fisher density on S³ centred at the identity with
/// concentration `kappa` (Wood 1994, m = 4); `E[1 − |δ.w|] ≈ 3/(2κ)` for large κ.
pub(super) fn sample_vmf_rotation(kappa: f64, rng: &mut StdRng) -> UnitQuaternion<f64> {
    if kappa.is_nan() || kappa <= 1e-9 {
        // Uniform rotation.
        let q = Quaternion::new(
            StandardNormal.sample(rng),
            StandardNormal.sample(rng),
            StandardNormal.sample(rng),
            StandardNormal.sample(rng),
        );
        return UnitQuaternion::from_quaternion(q);
    }
    // b = (2/3)(√(κ² + 9/4) − κ), written without cancellation.
    let b = 1.5 / ((kappa * kappa + 2.25).sqrt() + kappa);
    let x0 = (1.0 - b) / (1.0 + b);
    let c = kappa * x0 + 3.0 * (1.0 - x0 * x0).ln();
    let beta = Beta::new(1.5, 1.5).expect("valid shape");
    let w = loop {
        let z: f64 = beta.sample(rng);
        let w = (1.0 - (1.0 + b) * z) / (1.0 - (1.0 - b) * z);
        let u: f64 = rng.random();
        if kappa * w + 3.0 * (1.0 - x0 * w).ln() - c >= u.max(f64::MIN_POSITIVE).ln() {
            break w;
        }
    };
    let v = unit_vector(rng) * (1.0 - w * w).max(0.0).sqrt();
    UnitQuaternion::from_quaternion(Quaternion::new(w, v.x, v.y, v.z))
}

/// A pose drawn from the kernel centred at `mean`: position `μp + u·|ε|` (u uniform unit,
/// ε ~ N(0, σp²)), orientation `μq ⊗ δ` with δ ~ vMF(κ).
pub(super) fn sample_pose_kernel(
    mean: &Isometry3<f64>,
    sigma_p: f64,
    kappa: f64,
    rng: &mut StdRng,
) -> Isometry3<f64> {
    let e: f64 = StandardNormal.sample(rng);
    let offset = unit_vector(rng) * (e * sigma_p).abs();
    let rotation = mean.rotation * sample_vmf_rotation(kappa, rng);
    Isometry3::from_parts(
        Translation3::from(mean.translation.vector + offset),
        rotation,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vmf_mean_distance_matches_three_over_two_kappa() {
        let mut rng = item_rng(7, 0, 0);
        for kappa in [200.0, 1000.0, 10000.0] {
            let n = 20000;
            let mean: f64 = (0..n)
                .map(|_| 1.0 - sample_vmf_rotation(kappa, &mut rng).w.abs())
                .sum::<f64>()
                / n as f64;
            let expected = 3.0 / (2.0 * kappa);
            assert!(
                (mean / expected - 1.0).abs() < 0.05,
                "κ={kappa}: {mean} vs {expected}"
            );
        }
    }

    #[test]
    fn quaternion_distance_is_antipodal_and_small_angle_consistent() {
        let a = UnitQuaternion::from_scaled_axis(Vector3::new(0.1, 0.2, 0.3));
        let b = a * UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.02));
        let minus_b = UnitQuaternion::new_unchecked(-b.into_inner());
        assert_eq!(
            quaternion_distance(&a, &b),
            quaternion_distance(&a, &minus_b)
        );
        assert!((quaternion_distance(&a, &b) - 0.02f64.powi(2) / 8.0).abs() < 1e-9);
    }
}
