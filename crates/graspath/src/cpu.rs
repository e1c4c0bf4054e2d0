//! What the processor offers beyond the baseline instruction set, asked in one place.
//!
//! Every run-time choice of a vector form is made here: the forward kinematics passes and
//! batches (`robot::chain`), the Levenberg–Marquardt runs and lanes of inverse kinematics
//! (`robot::ik`), the grasp model's kernel sums (`grasp::model`), and the tests that compare
//! each vector form with its portable twin bit for bit. Each vector form performs its twin's
//! IEEE operations in the same order, so the answer changes speed, never results. Another
//! backend (NEON, wider vectors) adds its detection here.

/// Whether this x86-64 processor runs AVX2 instructions. Detected on the first call and cached
/// (by the standard library's feature detection), so a later call is one load and a bit test,
/// cheap enough for every kernel entry.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) fn has_avx2() -> bool {
    std::is_x86_feature_detected!("avx2")
}
