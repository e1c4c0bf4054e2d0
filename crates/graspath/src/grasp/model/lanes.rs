//! The hot loop of a query density: the kernel sum over runs of kernels.
//!
//! The kernels are stored as one array per coordinate (structure of arrays), padded with three
//! kernels that can never count, so that every group of four can be loaded whole. On x86-64
//! processors with AVX2 (detected at run time) four kernels are evaluated at once, and a group
//! wholly outside the cut-offs skips its exponentials; elsewhere one kernel at a time. Both do
//! the same IEEE operations in the same order per kernel (no fused multiply–add) and add into
//! the same four partial sums, so they give bit-identical results.

use nalgebra::{Quaternion, UnitQuaternion};

/// Kernels that are padding sit this far away (m): beyond any position cut-off.
const FAR: f64 = 1e30;

/// One kernel: position (m), rotation and weight.
pub(super) type WeightedKernel = ([f64; 3], UnitQuaternion<f64>, f64);

/// Pose kernels (position in m, unit quaternion) and weights, one array per coordinate.
#[derive(Debug, Clone, Default)]
pub(super) struct KernelTable {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    qw: Vec<f64>,
    qx: Vec<f64>,
    qy: Vec<f64>,
    qz: Vec<f64>,
    weight: Vec<f64>,
    len: usize,
}

/// One evaluation's query pose and cut-offs.
#[derive(Debug, Clone, Copy)]
pub(super) struct LaneQuery {
    /// Query position (m).
    pub position: [f64; 3],
    /// Query rotation as `[w, x, y, z]`.
    pub rotation: [f64; 4],
    /// `1/σp²` (m⁻²).
    pub inv_var: f64,
    /// κ of the rotation kernel.
    pub kappa: f64,
    /// Squared position cut-off (m²).
    pub cut_p: f64,
    /// Rotation-distance cut-off.
    pub cut_q: f64,
}

impl KernelTable {
    /// A table of `(position, rotation, weight)` kernels, in the given order.
    pub(super) fn new(kernels: impl IntoIterator<Item = WeightedKernel>) -> Self {
        let mut table = Self::default();
        for (p, r, w) in kernels {
            table.push(p, [r.w, r.i, r.j, r.k], w);
        }
        table.len = table.x.len();
        for _ in 0..3 {
            table.push([FAR; 3], [1.0, 0.0, 0.0, 0.0], 0.0);
        }
        table
    }

    fn push(&mut self, p: [f64; 3], r: [f64; 4], w: f64) {
        self.x.push(p[0]);
        self.y.push(p[1]);
        self.z.push(p[2]);
        self.qw.push(r[0]);
        self.qx.push(r[1]);
        self.qy.push(r[2]);
        self.qz.push(r[3]);
        self.weight.push(w);
    }

    /// The number of kernels (padding excluded).
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// Whether the table has no kernel.
    pub(super) fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Kernel `k`'s position (m).
    pub(super) fn position(&self, k: usize) -> [f64; 3] {
        [self.x[k], self.y[k], self.z[k]]
    }

    /// Kernel `k`'s rotation.
    pub(super) fn rotation(&self, k: usize) -> UnitQuaternion<f64> {
        UnitQuaternion::new_unchecked(Quaternion::new(
            self.qw[k], self.qx[k], self.qy[k], self.qz[k],
        ))
    }

    /// `Σ_k w_k · exp(−(‖p − p_k‖²/σp² + κ(1 − |q·q_k|)))` over the kernels of `runs` that lie
    /// within the cut-offs. Kernel `k` of a run starting at `s` is added to partial sum
    /// `(k − s) mod 4`; the partial sums `a, b, c, d` are combined as `(a + b) + (c + d)`.
    #[inline]
    pub(super) fn sum(&self, runs: &[std::ops::Range<usize>], query: &LaneQuery) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::has_avx2() {
            // SAFETY: the processor supports AVX2 (checked just above).
            return unsafe { self.sum_avx2(runs, query) };
        }
        self.sum_portable(runs, query)
    }

    /// [`KernelTable::sum`], one kernel at a time, for any processor.
    pub(crate) fn sum_portable(&self, runs: &[std::ops::Range<usize>], query: &LaneQuery) -> f64 {
        let [px, py, pz] = query.position;
        let [rw, rx, ry, rz] = query.rotation;
        let mut sums = [0.0; 4];
        for run in runs {
            for k in run.start..run.end.min(self.len) {
                let (dx, dy, dz) = (px - self.x[k], py - self.y[k], pz - self.z[k]);
                let d2 = dx * dx + dy * dy + dz * dz;
                let dot = rw * self.qw[k] + rx * self.qx[k] + ry * self.qy[k] + rz * self.qz[k];
                let dq = 1.0 - dot.abs();
                let exponent = d2 * query.inv_var + query.kappa * dq;
                if d2 < query.cut_p && dq < query.cut_q && exponent < 25.0 {
                    sums[(k - run.start) % 4] += self.weight[k] * exp_of_negative(exponent);
                }
            }
        }
        (sums[0] + sums[1]) + (sums[2] + sums[3])
    }

    /// [`KernelTable::sum`] four kernels at a time with AVX2: the same operations as
    /// [`KernelTable::sum_portable`] in every lane, so the result is bit-identical. A group of
    /// four wholly outside the cut-offs skips its exponentials (most groups do).
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub(crate) unsafe fn sum_avx2(
        &self,
        runs: &[std::ops::Range<usize>],
        query: &LaneQuery,
    ) -> f64 {
        use std::arch::x86_64::*;
        let set = _mm256_set1_pd;
        let [px, py, pz] = query.position.map(|v| set(v));
        let [rw, rx, ry, rz] = query.rotation.map(|v| set(v));
        let (inv_var, kappa) = (set(query.inv_var), set(query.kappa));
        let (cut_p, cut_q, cut_e) = (set(query.cut_p), set(query.cut_q), set(25.0));
        let sign_bit = set(-0.0);
        let lane_offsets = _mm256_setr_epi64x(0, 1, 2, 3);
        let mut acc = _mm256_setzero_pd();
        for run in runs {
            let end = run.end.min(self.len);
            let limit = _mm256_set1_epi64x(end as i64);
            let mut k = run.start;
            while k < end {
                // The tables hold three padding kernels, so four values from `k < len` exist.
                let load = |v: &[f64]| _mm256_loadu_pd(v.as_ptr().add(k));
                let dx = _mm256_sub_pd(px, load(&self.x));
                let dy = _mm256_sub_pd(py, load(&self.y));
                let dz = _mm256_sub_pd(pz, load(&self.z));
                let d2 = _mm256_add_pd(
                    _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                    _mm256_mul_pd(dz, dz),
                );
                let dot = _mm256_add_pd(
                    _mm256_add_pd(
                        _mm256_add_pd(
                            _mm256_mul_pd(rw, load(&self.qw)),
                            _mm256_mul_pd(rx, load(&self.qx)),
                        ),
                        _mm256_mul_pd(ry, load(&self.qy)),
                    ),
                    _mm256_mul_pd(rz, load(&self.qz)),
                );
                let dq = _mm256_sub_pd(set(1.0), _mm256_andnot_pd(sign_bit, dot));
                let exponent = _mm256_add_pd(_mm256_mul_pd(d2, inv_var), _mm256_mul_pd(kappa, dq));
                let index = _mm256_add_epi64(_mm256_set1_epi64x(k as i64), lane_offsets);
                let inside = _mm256_and_pd(
                    _mm256_and_pd(
                        _mm256_castsi256_pd(_mm256_cmpgt_epi64(limit, index)),
                        _mm256_cmp_pd::<_CMP_LT_OQ>(d2, cut_p),
                    ),
                    _mm256_and_pd(
                        _mm256_cmp_pd::<_CMP_LT_OQ>(dq, cut_q),
                        _mm256_cmp_pd::<_CMP_LT_OQ>(exponent, cut_e),
                    ),
                );
                if _mm256_movemask_pd(inside) != 0 {
                    let term = _mm256_mul_pd(load(&self.weight), exp_of_negative_avx2(exponent));
                    acc = _mm256_add_pd(acc, _mm256_and_pd(inside, term));
                }
                k += 4;
            }
        }
        let mut sums = [0.0; 4];
        _mm256_storeu_pd(sums.as_mut_ptr(), acc);
        (sums[0] + sums[1]) + (sums[2] + sums[3])
    }
}

/// Taylor coefficients 1/k! for k = 2..=13: on |r| ≤ ln2/2 the omitted terms are < 1e-17.
const EXP_COEFFS: [f64; 12] = [
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5_040.0,
    1.0 / 40_320.0,
    1.0 / 362_880.0,
    1.0 / 3_628_800.0,
    1.0 / 39_916_800.0,
    1.0 / 479_001_600.0,
    1.0 / 6_227_020_800.0,
];
const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
/// Adding and subtracting 1.5·2⁵² rounds to the nearest integer.
const SHIFTER: f64 = 6_755_399_441_055_744.0;
/// Arguments of [`exp_of_negative`] are clamped to this.
const EXP_CLAMP: f64 = 30.0;

/// `exp(−e)` for `e ≥ 0`, to about one unit in the last place for `e ≤ 30` (larger `e` are
/// clamped to 30).
#[inline(always)]
pub(super) fn exp_of_negative(e: f64) -> f64 {
    let x = -(if e < EXP_CLAMP { e } else { EXP_CLAMP });
    // x = k·ln2 + r, k = round(x/ln2), |r| ≤ ln2/2.
    let shifted = x * std::f64::consts::LOG2_E + SHIFTER;
    let k = shifted - SHIFTER;
    let r = (x - k * LN2_HI) - k * LN2_LO;
    // Estrin's scheme: a short dependency chain.
    let r2 = r * r;
    let r4 = r2 * r2;
    let r8 = r4 * r4;
    let pair = |i: usize| EXP_COEFFS[i] + EXP_COEFFS[i + 1] * r;
    let low = (pair(0) + pair(2) * r2) + (pair(4) + pair(6) * r2) * r4;
    let p = low + (pair(8) + pair(10) * r2) * r8;
    let exp_r = 1.0 + r + r2 * p;
    // 2^k from k's integer value in the low bits of `shifted` (k ∈ [−44, 0]).
    let k_bits = shifted.to_bits().wrapping_sub(SHIFTER.to_bits());
    let scale = f64::from_bits(k_bits.wrapping_add(1023) << 52);
    exp_r * scale
}

/// [`exp_of_negative`] of four lanes with AVX2, bit-identical to it in every lane.
///
/// # Safety
/// The processor must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn exp_of_negative_avx2(e: std::arch::x86_64::__m256d) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::*;
    let set = _mm256_set1_pd;
    let (add, mul) = (_mm256_add_pd, _mm256_mul_pd);
    // `minpd` returns the second operand for NaN, like the scalar comparison.
    let x = _mm256_xor_pd(_mm256_min_pd(e, set(EXP_CLAMP)), set(-0.0));
    let shifted = add(mul(x, set(std::f64::consts::LOG2_E)), set(SHIFTER));
    let k = _mm256_sub_pd(shifted, set(SHIFTER));
    let r = _mm256_sub_pd(_mm256_sub_pd(x, mul(k, set(LN2_HI))), mul(k, set(LN2_LO)));
    let r2 = mul(r, r);
    let r4 = mul(r2, r2);
    let r8 = mul(r4, r4);
    let pair = |i: usize| add(set(EXP_COEFFS[i]), mul(set(EXP_COEFFS[i + 1]), r));
    let low = add(
        add(pair(0), mul(pair(2), r2)),
        mul(add(pair(4), mul(pair(6), r2)), r4),
    );
    let p = add(low, mul(add(pair(8), mul(pair(10), r2)), r8));
    let exp_r = add(add(set(1.0), r), mul(r2, p));
    let k_bits = _mm256_sub_epi64(
        _mm256_castpd_si256(shifted),
        _mm256_castpd_si256(set(SHIFTER)),
    );
    let scale = _mm256_slli_epi64::<52>(_mm256_add_epi64(k_bits, _mm256_set1_epi64x(1023)));
    mul(exp_r, _mm256_castsi256_pd(scale))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grasp::model::kernel::{item_rng, unit_vector};
    use nalgebra::Vector3;
    use rand::RngExt;

    #[test]
    fn exp_matches_the_standard_library() {
        let mut worst: f64 = 0.0;
        for i in 0..=300_000 {
            let e = 30.0 * i as f64 / 300_000.0;
            let reference = (-e).exp();
            worst = worst.max(((exp_of_negative(e) - reference) / reference).abs());
        }
        assert!(
            worst <= 3.0 * f64::EPSILON,
            "worst relative error {worst:e}"
        );
        assert_eq!(exp_of_negative(0.0), 1.0);
        assert_eq!(exp_of_negative(1e6), (-30.0f64).exp());
    }

    fn random_table(n: usize) -> (KernelTable, Vec<WeightedKernel>) {
        let mut rng = item_rng(3, 0, 0);
        let kernels: Vec<_> = (0..n)
            .map(|_| {
                let p = unit_vector(&mut rng) * 0.02 * rng.random::<f64>();
                let r = UnitQuaternion::from_scaled_axis(unit_vector(&mut rng) * 0.3);
                ([p.x, p.y, p.z], r, rng.random::<f64>())
            })
            .collect();
        (KernelTable::new(kernels.clone()), kernels)
    }

    #[test]
    fn lane_sums_match_the_defining_sum() {
        let (table, kernels) = random_table(203);
        let mut rng = item_rng(4, 0, 0);
        for _ in 0..200 {
            let p = unit_vector(&mut rng) * 0.01;
            let r = UnitQuaternion::from_scaled_axis(unit_vector(&mut rng) * 0.2);
            let query = LaneQuery {
                position: [p.x, p.y, p.z],
                rotation: [r.w, r.i, r.j, r.k],
                inv_var: 1.0 / 0.005f64.powi(2),
                kappa: 100.0,
                cut_p: 25.0 * 0.005f64.powi(2),
                cut_q: 0.25,
            };
            let start = rng.random_range(0..100);
            let end = rng.random_range(start..=203);
            let middle = rng.random_range(start..=end);
            let got = table.sum(&[start..middle, middle..end], &query);
            let expected: f64 = kernels[start..end]
                .iter()
                .map(|(c, q, w)| {
                    let d2 = (p - Vector3::from(*c)).norm_squared();
                    let dq = 1.0 - r.coords.dot(&q.coords).abs();
                    let e = d2 * query.inv_var + query.kappa * dq;
                    if d2 < query.cut_p && dq < query.cut_q && e < 25.0 {
                        w * (-e).exp()
                    } else {
                        0.0
                    }
                })
                .sum();
            assert!(
                (got - expected).abs() <= 1e-13 * expected.max(1e-300),
                "{got} vs {expected}"
            );
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_and_portable_sums_are_bit_identical() {
        if !crate::cpu::has_avx2() {
            eprintln!("no AVX2 on this processor: nothing to compare");
            return;
        }
        let (table, _) = random_table(1000);
        let mut rng = item_rng(5, 0, 0);
        for _ in 0..500 {
            // Near and far queries, loose and tight rotation cut-offs: groups wholly inside,
            // wholly outside and mixed.
            let p = unit_vector(&mut rng) * 0.05 * rng.random::<f64>();
            let r = UnitQuaternion::from_scaled_axis(unit_vector(&mut rng) * 0.3);
            let kappa = if rng.random::<bool>() { 60.0 } else { 2000.0 };
            let query = LaneQuery {
                position: [p.x, p.y, p.z],
                rotation: [r.w, r.i, r.j, r.k],
                inv_var: 1.0 / 0.005f64.powi(2),
                kappa,
                cut_p: 25.0 * 0.005f64.powi(2),
                cut_q: 25.0 / kappa,
            };
            let runs: Vec<std::ops::Range<usize>> = (0..rng.random_range(1..8))
                .map(|_| {
                    let start = rng.random_range(0..1000);
                    start..rng.random_range(start..=1003)
                })
                .collect();
            let a = table.sum_portable(&runs, &query);
            // SAFETY: AVX2 is present (checked above).
            let b = unsafe { table.sum_avx2(&runs, &query) };
            assert_eq!(a.to_bits(), b.to_bits(), "{runs:?}");
        }
    }
}
