//! Norms of the task-relevant index over the samples of a path (paper eq. 15–17).

/// One sample of the index along a path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleIndex {
    /// Time of the sample (s).
    pub time: f64,
    /// `M_T` at the sample, or `None` where the object is still (the sample is skipped).
    pub value: Option<f64>,
}

/// `μ_l2`, `μ_l∞` and `μ_l1` of a sequence of `M_T` values.
///
/// Skipped samples (the object is still) are left out of `μ_l2` and `μ_l∞`; `μ_l1` integrates
/// only over intervals whose two ends were evaluated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathNorms {
    /// `‖M‖₂` over the evaluated samples (maximise).
    pub l2: f64,
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
        let l1 = samples
            .windows(2)
            .filter_map(|pair| match (pair[0].value, pair[1].value) {
                (Some(a), Some(b)) => Some(0.5 * (a + b) * (pair[1].time - pair[0].time)),
                _ => None,
            })
            .sum();
        Self {
            l2: sum_squares.sqrt(),
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
        assert_eq!((n.evaluated, n.skipped), (3, 1));
        assert!(n.l1.is_finite() && n.linf.is_finite());
    }

    #[test]
    fn a_singular_sample_makes_linf_infinite() {
        let n = PathNorms::of(&samples(&[Some(2.0), Some(0.0)]));
        assert!(n.linf.is_infinite());
    }
}
