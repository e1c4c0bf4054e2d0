//! The hand-configuration model `C` (the paper's γ interpolation).
//!
//! The demonstrated hand joints form a polyline from the grasp `h^g` (γ = 0) back to the
//! pre-grasp `h^t` (γ = 1), parameterised by arc length measured in kernel widths
//! (`Σ_j (Δh_j/σ_j)²`); below 0 the first segment is extrapolated (tighter closure), above 1
//! the last one. `N` kernels sit at `γ_k` uniform in `[−β, β]`, with weights
//! `ŵ_k ∝ exp(−|γ_k|/β)` summing to 1:
//!
//! `C(c) = Σ_k ŵ_k · exp(−Σ_j (c_j − h_j(γ_k))²/σ_j²)`, kernels with exponent ≥ `cutoff²` skipped.
//!
//! For speed, each segment's sum is split as `exp(−R) · S(γ*)`, with `γ*` the projection of
//! `c` on the segment's line and `R` the scaled squared distance to that line; `S` is tabulated
//! over `γ*` once at load time (linear interpolation, 2048 entries per segment) and the cut-off
//! is applied to the along-path and across-path parts separately.

use rand::{rngs::StdRng, RngExt};
use rand_distr::{Distribution, StandardNormal};

const TABLE: usize = 2048;

/// The stored parameters of the hand-configuration model.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct ConfigurationSpec {
    /// Hand joints along the demonstration from the grasp (first) back to the pre-grasp (last).
    pub path: Vec<Vec<f64>>,
    /// Kernel width per joint (rad or m).
    pub sigma: Vec<f64>,
    /// Half-width β of the γ interval.
    pub beta: f64,
    /// Number of kernels.
    pub kernels: usize,
    /// Cut-off in kernel widths.
    pub cutoff: f64,
}

#[derive(Debug, Clone)]
struct Segment {
    /// Start point (scaled by 1/σ) and its γ.
    start: Vec<f64>,
    gamma_start: f64,
    /// dh/dγ, scaled by 1/σ.
    slope: Vec<f64>,
    /// ‖slope‖².
    a: f64,
    /// Range of γ owned by this segment's kernels.
    own: (f64, f64),
    /// Table of S over γ* ∈ [lo, hi].
    lo: f64,
    hi: f64,
    table: Vec<f64>,
}

/// The evaluable hand-configuration model.
#[derive(Debug, Clone)]
pub(super) struct ConfigurationModel {
    spec: ConfigurationSpec,
    segments: Vec<Segment>,
    gammas: Vec<f64>,
    cumulative: Vec<f64>,
}

impl ConfigurationModel {
    /// Builds the model; `spec.path` must hold at least one configuration, all of the length of
    /// `spec.sigma`, with positive widths.
    pub(super) fn new(spec: ConfigurationSpec) -> Self {
        let dof = spec.sigma.len();
        let scaled: Vec<Vec<f64>> = spec
            .path
            .iter()
            .map(|h| h.iter().zip(&spec.sigma).map(|(v, s)| v / s).collect())
            .collect();
        // Cumulative scaled arc length, normalised so that the pre-grasp is at γ = 1.
        let mut lengths = vec![0.0];
        for w in scaled.windows(2) {
            let d: f64 = w[0]
                .iter()
                .zip(&w[1])
                .map(|(a, b)| (b - a).powi(2))
                .sum::<f64>()
                .sqrt();
            lengths.push(lengths.last().copied().unwrap_or(0.0) + d);
        }
        let total = lengths.last().copied().unwrap_or(0.0);
        let n = spec.kernels.max(1);
        let gammas: Vec<f64> = (0..n)
            .map(|k| {
                if n == 1 {
                    0.0
                } else {
                    -spec.beta + 2.0 * spec.beta * k as f64 / (n - 1) as f64
                }
            })
            .collect();
        let raw: Vec<f64> = gammas
            .iter()
            .map(|g| {
                if spec.beta > 0.0 {
                    (-g.abs() / spec.beta).exp()
                } else {
                    1.0
                }
            })
            .collect();
        let z: f64 = raw.iter().sum();
        let weights: Vec<f64> = raw.iter().map(|w| w / z).collect();
        let mut cumulative = Vec::with_capacity(n);
        let mut acc = 0.0;
        for w in &weights {
            acc += w;
            cumulative.push(acc);
        }
        let mut segments = Vec::new();
        if total <= 1e-12 || scaled.len() < 2 {
            segments.push(Segment {
                start: scaled.first().cloned().unwrap_or_else(|| vec![0.0; dof]),
                gamma_start: 0.0,
                slope: vec![0.0; dof],
                a: 0.0,
                own: (f64::NEG_INFINITY, f64::INFINITY),
                lo: 0.0,
                hi: 0.0,
                table: vec![weights.iter().sum()],
            });
        } else {
            let count = scaled.len() - 1;
            for s in 0..count {
                let g0 = lengths[s] / total;
                let g1 = lengths[s + 1] / total;
                if g1 - g0 <= 1e-12 {
                    continue;
                }
                let slope: Vec<f64> = scaled[s]
                    .iter()
                    .zip(&scaled[s + 1])
                    .map(|(a, b)| (b - a) / (g1 - g0))
                    .collect();
                let a: f64 = slope.iter().map(|v| v * v).sum();
                let own = (
                    if s == 0 { f64::NEG_INFINITY } else { g0 },
                    if s + 1 == count { f64::INFINITY } else { g1 },
                );
                let members: Vec<usize> = (0..n)
                    .filter(|&k| gammas[k] >= own.0 && gammas[k] < own.1)
                    .collect();
                let reach = spec.cutoff / a.sqrt();
                let (lo, hi) = match (members.first(), members.last()) {
                    (Some(&f), Some(&l)) => (gammas[f] - reach, gammas[l] + reach),
                    _ => (0.0, 0.0),
                };
                let table: Vec<f64> = (0..TABLE)
                    .map(|i| {
                        let g = lo + (hi - lo) * i as f64 / (TABLE - 1) as f64;
                        members
                            .iter()
                            .map(|&k| {
                                let e = a * (gammas[k] - g).powi(2);
                                if e < spec.cutoff * spec.cutoff {
                                    weights[k] * (-e).exp()
                                } else {
                                    0.0
                                }
                            })
                            .sum()
                    })
                    .collect();
                segments.push(Segment {
                    start: scaled[s].clone(),
                    gamma_start: g0,
                    slope,
                    a,
                    own,
                    lo,
                    hi,
                    table,
                });
            }
        }
        Self {
            spec,
            segments,
            gammas,
            cumulative,
        }
    }

    /// The demonstrated grasp configuration `h^g`.
    pub(super) fn grasp(&self) -> &[f64] {
        &self.spec.path[0]
    }

    /// The configuration on the demonstrated path at γ (extrapolated outside `[0, 1]`).
    pub(super) fn at(&self, gamma: f64) -> Vec<f64> {
        let seg = self
            .segments
            .iter()
            .find(|s| gamma >= s.own.0 && gamma < s.own.1)
            .or(self.segments.last());
        match seg {
            Some(s) => s
                .start
                .iter()
                .zip(&s.slope)
                .zip(&self.spec.sigma)
                .map(|((h, d), sigma)| (h + d * (gamma - s.gamma_start)) * sigma)
                .collect(),
            None => self.grasp().to_vec(),
        }
    }

    /// `C(c)` (≤ 1).
    pub(super) fn density(&self, c: &[f64]) -> f64 {
        let cut2 = self.spec.cutoff * self.spec.cutoff;
        let mut total = 0.0;
        for s in &self.segments {
            // Scaled offset from the segment start.
            let mut along = 0.0;
            let mut r_full = 0.0;
            for ((ci, sigma), (h, d)) in c
                .iter()
                .zip(&self.spec.sigma)
                .zip(s.start.iter().zip(&s.slope))
            {
                let diff = ci / sigma - h;
                along += diff * d;
                r_full += diff * diff;
            }
            let (gamma_star, r) = if s.a > 0.0 {
                let t = along / s.a;
                (s.gamma_start + t, (r_full - t * t * s.a).max(0.0))
            } else {
                (0.0, r_full)
            };
            if r >= cut2 {
                continue;
            }
            let table_value = if s.table.len() == 1 {
                s.table[0]
            } else if gamma_star <= s.lo || gamma_star >= s.hi {
                0.0
            } else {
                let x = (gamma_star - s.lo) / (s.hi - s.lo) * (TABLE - 1) as f64;
                let i = (x.floor() as usize).min(TABLE - 2);
                let f = x - i as f64;
                s.table[i] * (1.0 - f) + s.table[i + 1] * f
            };
            total += (-r).exp() * table_value;
        }
        total
    }

    /// A configuration drawn from `C`: a kernel by weight, then Gaussian noise of the kernel's
    /// spread (σ_j/√2 per joint, matching `exp(−x²/σ²)`). Not clamped.
    pub(super) fn sample(&self, rng: &mut StdRng) -> Vec<f64> {
        let u: f64 = rng.random::<f64>() * self.cumulative.last().copied().unwrap_or(1.0);
        let k = self
            .cumulative
            .partition_point(|&c| c < u)
            .min(self.gammas.len() - 1);
        let mut c = self.at(self.gammas[k]);
        for (v, sigma) in c.iter_mut().zip(&self.spec.sigma) {
            let e: f64 = StandardNormal.sample(rng);
            *v += e * sigma / std::f64::consts::SQRT_2;
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grasp::model::kernel::item_rng;

    fn gripper() -> ConfigurationModel {
        ConfigurationModel::new(ConfigurationSpec {
            path: vec![vec![0.05], vec![0.07]],
            sigma: vec![0.001],
            beta: 0.5,
            kernels: 1000,
            cutoff: 5.0,
        })
    }

    /// The tabulated evaluation against the defining sum, computed directly.
    #[test]
    fn density_matches_the_kernel_sum() {
        let model = gripper();
        let n = 1000;
        let raw: Vec<f64> = (0..n).map(|k| -0.5 + k as f64 / (n - 1) as f64).collect();
        let z: f64 = raw.iter().map(|g: &f64| (-g.abs() / 0.5).exp()).sum();
        for c in [0.05, 0.0437, 0.058, 0.0601, 0.071, 0.03] {
            let direct: f64 = raw
                .iter()
                .map(|g| {
                    let h = 0.05 + 0.02 * g;
                    let e = ((c - h) / 0.001f64).powi(2);
                    if e < 25.0 {
                        (-g.abs() / 0.5).exp() / z * (-e).exp()
                    } else {
                        0.0
                    }
                })
                .sum();
            let got = model.density(&[c]);
            assert!(
                (got - direct).abs() <= 1e-3 * direct.max(1e-12) + 1e-15,
                "c={c}: {got} vs {direct}"
            );
        }
        // Peak at the grasp, falling towards both ends of [0.04, 0.06], zero beyond.
        assert!(model.density(&[0.05]) > model.density(&[0.055]));
        assert!(model.density(&[0.055]) > model.density(&[0.059]));
        assert_eq!(model.density(&[0.0701]), 0.0);
    }

    #[test]
    fn samples_stay_on_the_demonstrated_interval() {
        let model = gripper();
        let mut rng = item_rng(3, 0, 0);
        let draws: Vec<f64> = (0..2000).map(|_| model.sample(&mut rng)[0]).collect();
        assert!(draws.iter().all(|w| (0.036..0.064).contains(w)));
        let mean = draws.iter().sum::<f64>() / draws.len() as f64;
        assert!((mean - 0.05).abs() < 0.001, "{mean}");
    }

    #[test]
    fn multi_joint_polyline_is_followed() {
        let model = ConfigurationModel::new(ConfigurationSpec {
            path: vec![vec![1.0, 0.0], vec![0.5, 0.0], vec![0.5, 0.5]],
            sigma: vec![0.0157, 0.0157],
            beta: 0.4,
            kernels: 1000,
            cutoff: 5.0,
        });
        assert!((model.at(0.5)[0] - 0.5).abs() < 1e-12);
        let on = model.density(&[0.9, 0.0]);
        let off = model.density(&[0.9, 0.03]);
        assert!(on > 0.0 && off < on * 0.1, "{on} {off}");
    }
}
