//! Norms of the task-relevant index over the samples of a path (paper eq. 15–17).

use super::settings::Norm;

/// One sample of the index along a path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleIndex {
    /// Time of the sample (s).
    pub time: f64,
    /// `M_T` at the sample, or `None` where the object is still (the sample is skipped).
    pub value: Option<f64>,
}

/// `μ_l2`, `μ_l∞`, `μ_l1` and `μ_rms` of a sequence of `M_T` values.
///
/// Skipped samples (the object is still) are left out of `μ_l2` and `μ_l∞`; `μ_l1` and
/// `μ_rms` integrate only over intervals whose two ends were evaluated.
///
/// `μ_l2` (the paper's eq. 15) sums over samples, so it grows with their number (×√10 when
/// the path is sampled ten times as densely); `μ_rms` and `μ_l1` are integrals over time,
/// properties of the path that converge as its sampling is refined.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathNorms {
    /// `‖M‖₂` over the evaluated samples (maximise).
    pub l2: f64,
    /// The root mean square of `M` over the path's time, `√((1/T) ∫ M(t)² dt)` by the
    /// trapezoidal rule on `M²` over the intervals whose two ends were evaluated, `T` their
    /// total duration (the same units as `M`; maximise). The continuous counterpart of `μ_l2`
    /// (for evenly spaced samples they rank alike, up to the end samples' half weight), but
    /// independent of how densely the path is sampled. Without such an interval of positive
    /// duration, the root mean square of the evaluated samples (0 when there is none).
    pub rms: f64,
    /// `max_i 1/M_i` over the evaluated samples; `+∞` when a sample is singular along the path
    /// (`M_i = 0`); 0 when no sample was evaluated. Used as a constraint `μ_l∞ ≤ μ0`.
    pub linf: f64,
    /// Trapezoidal integral `½ Σ (M_i + M_{i+1}) Δt_i` (s · index units).
    pub l1: f64,
    /// How many samples were evaluated.
    pub evaluated: usize,
    /// How many samples were skipped because the object was still.
    pub skipped: usize,
}

impl PathNorms {
    /// The value of `norm` among these norms.
    pub fn value(&self, norm: Norm) -> f64 {
        match norm {
            Norm::Rms => self.rms,
            Norm::L2 => self.l2,
            Norm::L1 => self.l1,
        }
    }

    /// The norms of `samples` (in time order).
    pub fn of(samples: &[SampleIndex]) -> Self {
        let mut sum_squares = 0.0;
        let mut linf: f64 = 0.0;
        let mut evaluated = 0;
        for value in samples.iter().filter_map(|s| s.value) {
            evaluated += 1;
            sum_squares += value * value;
            linf = linf.max(if value > 0.0 {
                1.0 / value
            } else {
                f64::INFINITY
            });
        }
        let mut l1 = 0.0;
        let mut integral_of_squares = 0.0;
        let mut duration = 0.0;
        for pair in samples.windows(2) {
            if let (Some(a), Some(b)) = (pair[0].value, pair[1].value) {
                let dt = pair[1].time - pair[0].time;
                l1 += 0.5 * (a + b) * dt;
                integral_of_squares += 0.5 * (a * a + b * b) * dt;
                duration += dt;
            }
        }
        let rms = if duration > 0.0 {
            (integral_of_squares / duration).sqrt()
        } else if evaluated > 0 {
            (sum_squares / evaluated as f64).sqrt()
        } else {
            0.0
        };
        Self {
            l2: sum_squares.sqrt(),
            rms,
            linf,
            l1,
            evaluated,
            skipped: samples.len() - evaluated,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn samples(values: &[Option<f64>]) -> Vec<SampleIndex> {
        values
            .iter()
            .enumerate()
            .map(|(i, &value)| SampleIndex {
                time: 0.5 * i as f64,
                value,
            })
            .collect()
    }

    #[test]
    fn norms_of_a_known_sequence() {
        let n = PathNorms::of(&samples(&[Some(1.0), Some(2.0), Some(4.0)]));
        assert_relative_eq!(n.l2, 21f64.sqrt());
        // ½(1+4)·0.5 + ½(4+16)·0.5 = 6.25 over 1 s.
        assert_relative_eq!(n.rms, 6.25f64.sqrt());
        assert_relative_eq!(n.linf, 1.0);
        // ½(1+2)·0.5 + ½(2+4)·0.5
        assert_relative_eq!(n.l1, 0.75 + 1.5);
        assert_eq!((n.evaluated, n.skipped), (3, 0));
    }

    #[test]
    fn still_samples_are_skipped_not_divided() {
        let n = PathNorms::of(&samples(&[Some(2.0), None, Some(4.0), Some(4.0)]));
        assert_relative_eq!(n.l2, 36f64.sqrt());
        assert_relative_eq!(n.linf, 0.5);
        assert_relative_eq!(n.l1, 2.0);
        // Only the interval 4 → 4 (0.5 s) counts.
        assert_relative_eq!(n.rms, 4.0);
        assert_eq!((n.evaluated, n.skipped), (3, 1));
        assert!(n.l1.is_finite() && n.linf.is_finite());
    }

    /// `M(t) = 2 + sin t` on `[0, T]`: `∫ M² dt = 4.5 T − 4 cos T + 4 − sin(2T) / 4` in closed
    /// form. `μ_rms` converges to `√(∫ M² dt / T)` as the sampling is refined (the trapezoidal
    /// rule's error falls 100-fold for 10× the samples), whatever the spacing; `μ_l2` grows
    /// with the square root of the sample count.
    #[test]
    fn rms_converges_to_the_integral_and_l2_grows_with_the_sampling() {
        let t_end = 3.0_f64;
        let exact =
            ((4.5 * t_end - 4.0 * t_end.cos() + 4.0 - (2.0 * t_end).sin() / 4.0) / t_end).sqrt();
        let sampled = |n: usize, uneven: bool| -> Vec<SampleIndex> {
            (0..=n)
                .map(|i| {
                    let x = i as f64 / n as f64;
                    // An uneven spacing: t = T x² stretches the late intervals.
                    let time = t_end * if uneven { x * x } else { x };
                    SampleIndex {
                        time,
                        value: Some(2.0 + time.sin()),
                    }
                })
                .collect()
        };
        for uneven in [false, true] {
            let coarse = PathNorms::of(&sampled(50, uneven));
            let fine = PathNorms::of(&sampled(500, uneven));
            let (e_coarse, e_fine) = ((coarse.rms - exact).abs(), (fine.rms - exact).abs());
            assert!(e_coarse < 1e-3 * exact, "{e_coarse}");
            assert!(e_fine < 0.02 * e_coarse, "{e_fine} vs {e_coarse}");
        }
        let (coarse, fine) = (
            PathNorms::of(&sampled(50, false)),
            PathNorms::of(&sampled(500, false)),
        );
        let growth = fine.l2 / coarse.l2 / (501.0f64 / 51.0).sqrt();
        assert!((growth - 1.0).abs() < 0.02, "{growth}");
        // One sample, or none: the samples' own root mean square.
        let one = PathNorms::of(&samples(&[Some(3.0)]));
        assert_relative_eq!(one.rms, 3.0);
        assert_eq!(PathNorms::of(&samples(&[None, None])).rms, 0.0);
    }

    #[test]
    fn a_singular_sample_makes_linf_infinite() {
        let n = PathNorms::of(&samples(&[Some(2.0), Some(0.0)]));
        assert!(n.linf.is_infinite());
    }
}
