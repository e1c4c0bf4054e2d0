//! Query densities: for each involved link, weighted pose kernels of the link on a new object,
//! built by placing demonstrated link-to-surface relations on object features of similar
//! curvature (spec §3), and their fast evaluation through a uniform grid.

use super::contact::{curvature_bandwidth, ContactModel};
use super::kernel::{item_rng, sample_pose_kernel};
use super::lanes::{KernelTable, LaneQuery, WeightedKernel};
use super::ModelParams;
use crate::cloud::{PointIndex, SurfaceFeature};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::{rngs::StdRng, RngExt};
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;

/// Cells per position cut-off radius in the kernel grid.
const REACH: i64 = 2;
/// Rows of cells an evaluation scans at most.
const ROWS: usize = ((2 * REACH + 1) * (2 * REACH + 1)) as usize;

/// Largest density-distance cost (matched cost bound × 10).
pub const DENSITY_DISTANCE_MAX: f64 = 10.0 * (2.5e-5 + 0.01 * 0.25);

/// The query density `Q_i` of one link: kernel centres `object_from_link` with weights.
#[derive(Debug, Clone)]
pub struct QueryDensity {
    /// The link's index in the hand.
    pub link_index: usize,
    /// `ln` of the link's weight factor `exp(−pen_i)` (curvature-statistics penalty).
    pub log_factor: f64,
    kernels: KernelTable,
    cumulative: Vec<f64>,
    sigma_p: f64,
    kappa: f64,
    grid: Grid,
}

#[derive(Debug, Clone)]
struct Grid {
    origin: [f64; 3],
    inv_cell: f64,
    dims: [usize; 3],
    starts: Vec<u32>,
}

impl Grid {
    fn cell_of(&self, p: &[f64; 3]) -> [i64; 3] {
        std::array::from_fn(|a| ((p[a] - self.origin[a]) * self.inv_cell).floor() as i64)
    }

    fn index(&self, c: [i64; 3]) -> Option<usize> {
        if (0..3).any(|a| c[a] < 0 || c[a] >= self.dims[a] as i64) {
            return None;
        }
        Some((c[2] as usize * self.dims[1] + c[1] as usize) * self.dims[0] + c[0] as usize)
    }
}

struct Kernel {
    pose: Isometry3<f64>,
    weight: f64,
}

/// The object-level statistics used by the curvature-bandwidth adaptation.
pub fn object_curvature_stats(features: &[SurfaceFeature], factor: f64) -> ([f64; 2], [f64; 2]) {
    curvature_bandwidth(features.iter().map(|f| f.curvature), factor)
}

/// Adapts a link's curvature widths to the object (spec §3.3): the overlap rule
/// `σ ≥ σo/5` acts as the degenerate-variance guard; the mean rule
/// `σ ≥ |μ − μo| − σo + σo/5` widens the kernel when the demonstrated curvature is far from the
/// object's and is what the penalty `pen = Σ_d (σ_new/σ_old − 1)` measures.
pub fn adapt_bandwidth(
    contact: &ContactModel,
    object_sigma: [f64; 2],
    object_mean: [f64; 2],
) -> ([f64; 2], f64) {
    let mut sigma = contact.sigma_r;
    let mut pen = 0.0;
    for d in 0..2 {
        let guarded = sigma[d].max(object_sigma[d] / 5.0);
        let mean_rule = (contact.curvature_mean[d] - object_mean[d]).abs() - object_sigma[d]
            + object_sigma[d] / 5.0;
        let adapted = guarded.max(mean_rule);
        pen += adapted / guarded - 1.0;
        sigma[d] = adapted;
    }
    (sigma, pen)
}

impl QueryDensity {
    /// Builds the density of one link from `kernels` draws (fewer if some draws find no
    /// matching curvature even after widening). Deterministic for a given `seed`.
    pub fn build(
        contact: &ContactModel,
        features: &[SurfaceFeature],
        object_index: &PointIndex,
        object_stats: ([f64; 2], [f64; 2]),
        params: &ModelParams,
        kernels: usize,
        seed: u64,
    ) -> Self {
        let (sigma_r, pen) = adapt_bandwidth(contact, object_stats.0, object_stats.1);
        let inv_var = sigma_r.map(|s| 1.0 / (s * s));
        let stride = (contact.samples.len() / params.density_points.max(1)).max(1);
        let model_points: Vec<(Point3<f64>, Vector3<f64>)> = contact
            .samples
            .iter()
            .step_by(stride)
            .map(|s| (Point3::from(s.point), Vector3::from(s.normal)))
            .collect();
        let stream = 1000 + contact.link_index as u64;
        let drawn: Vec<Option<Kernel>> = (0..kernels)
            .into_par_iter()
            .map_init(
                || vec![0.0; contact.samples.len()],
                |scratch, k| {
                    let mut rng = item_rng(seed, stream, k as u64);
                    let (feature, m) = draw_match(contact, features, &inv_var, scratch, &mut rng)?;
                    let pose = place(
                        feature,
                        &contact.samples[m].feature_from_link,
                        params.sensor_rho,
                        &mut rng,
                    );
                    let weight = if params.density_distance {
                        (-5.0 * density_distance(&pose, &model_points, features, object_index)
                            / DENSITY_DISTANCE_MAX)
                            .exp()
                    } else {
                        1.0
                    };
                    Some(Kernel { pose, weight })
                },
            )
            .collect();
        let kernels: Vec<Kernel> = drawn.into_iter().flatten().collect();
        Self::from_kernels(contact.link_index, -pen, kernels, params)
    }

    fn from_kernels(
        link_index: usize,
        log_factor: f64,
        kernels: Vec<Kernel>,
        params: &ModelParams,
    ) -> Self {
        let sigma_p = params.query_sigma_position;
        let cell = 5.0 * sigma_p / REACH as f64;
        let floor = 1e-10 / kernels.len().max(1) as f64;
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for k in &kernels {
            for a in 0..3 {
                lo[a] = lo[a].min(k.pose.translation.vector[a]);
                hi[a] = hi[a].max(k.pose.translation.vector[a]);
            }
        }
        if kernels.is_empty() {
            lo = [0.0; 3];
            hi = [0.0; 3];
        }
        let dims: [usize; 3] =
            std::array::from_fn(|a| ((hi[a] - lo[a]) / cell).floor() as usize + 1);
        let mut grid = Grid {
            origin: lo,
            inv_cell: 1.0 / cell,
            dims,
            starts: vec![0; dims[0] * dims[1] * dims[2] + 1],
        };
        let mut keyed: Vec<(usize, usize)> = kernels
            .iter()
            .enumerate()
            .map(|(i, k)| {
                let p = k.pose.translation.vector;
                (grid.index(grid.cell_of(&[p.x, p.y, p.z])).unwrap_or(0), i)
            })
            .collect();
        keyed.sort_unstable();
        for (c, _) in &keyed {
            grid.starts[c + 1] += 1;
        }
        for c in 0..grid.starts.len() - 1 {
            grid.starts[c + 1] += grid.starts[c];
        }
        let ordered: Vec<WeightedKernel> = keyed
            .into_iter()
            .map(|(_, i)| {
                let k = &kernels[i];
                let p = k.pose.translation.vector;
                ([p.x, p.y, p.z], k.pose.rotation, k.weight.max(floor))
            })
            .collect();
        let cumulative: Vec<f64> = ordered
            .iter()
            .scan(0.0, |total, &(_, _, w)| {
                *total += w;
                Some(*total)
            })
            .collect();
        let table = KernelTable::new(ordered);
        Self {
            link_index,
            log_factor,
            kernels: table,
            cumulative,
            sigma_p,
            kappa: params.query_kappa,
            grid,
        }
    }

    /// The number of kernels.
    pub fn len(&self) -> usize {
        self.kernels.len()
    }

    /// Whether the density has no kernel.
    pub fn is_empty(&self) -> bool {
        self.kernels.is_empty()
    }

    /// `Σ_k w_k` (before the link factor).
    pub fn total_weight(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0)
    }

    /// `Σ_k w_k exp(−‖p − p_k‖²/σp² − κ·dq(q, q_k))` over kernels within the cut-offs
    /// (`‖Δp‖² < 25σp²`, `dq < 25/κ`, and the whole exponent below 25, i.e. the "5 std"
    /// cut-off also applied to the joint pose distance: a skipped kernel contributes less than
    /// `e⁻²⁵ ≈ 1.4·10⁻¹¹` of its weight), for a link pose `object_from_link`.
    ///
    /// The grid's cells are half the position cut-off wide; for each row of cells along x
    /// only the cells that the cut-off sphere around `p` reaches are scanned.
    #[inline]
    pub fn evaluate(&self, object_from_link: &Isometry3<f64>) -> f64 {
        let p = object_from_link.translation.vector;
        let p = [p.x, p.y, p.z];
        let q = &object_from_link.rotation;
        let cut_p = 25.0 * self.sigma_p * self.sigma_p;
        let query = LaneQuery {
            position: p,
            rotation: [q.w, q.i, q.j, q.k],
            inv_var: 1.0 / (self.sigma_p * self.sigma_p),
            kappa: self.kappa,
            cut_p,
            cut_q: 25.0 / self.kappa,
        };
        let cell = 1.0 / self.grid.inv_cell;
        let dims = self.grid.dims;
        let centre = self.grid.cell_of(&p);
        let gap = |axis: usize, c: i64| {
            let lo = self.grid.origin[axis] + c as f64 * cell;
            if p[axis] < lo {
                lo - p[axis]
            } else if p[axis] > lo + cell {
                p[axis] - lo - cell
            } else {
                0.0
            }
        };
        let mut runs: [std::ops::Range<usize>; ROWS] = std::array::from_fn(|_| 0..0);
        let mut count = 0;
        for cz in (centre[2] - REACH).max(0)..=(centre[2] + REACH).min(dims[2] as i64 - 1) {
            let gz = gap(2, cz);
            for cy in (centre[1] - REACH).max(0)..=(centre[1] + REACH).min(dims[1] as i64 - 1) {
                let gy = gap(1, cy);
                let rest = cut_p - gz * gz - gy * gy;
                if rest <= 0.0 {
                    continue;
                }
                let rx = rest.sqrt();
                let x0 = (((p[0] - rx - self.grid.origin[0]) * self.grid.inv_cell).floor() as i64)
                    .max(0);
                let x1 = (((p[0] + rx - self.grid.origin[0]) * self.grid.inv_cell).floor() as i64)
                    .min(dims[0] as i64 - 1);
                if x0 > x1 {
                    continue;
                }
                let row = (cz as usize * dims[1] + cy as usize) * dims[0];
                let range = self.grid.starts[row + x0 as usize] as usize
                    ..self.grid.starts[row + x1 as usize + 1] as usize;
                runs[count] = range;
                count += 1;
            }
        }
        self.kernels.sum(&runs[..count], &query)
    }

    /// A link pose drawn from the density: a kernel by weight, perturbed by the kernel.
    pub fn sample(&self, rng: &mut StdRng) -> Option<Isometry3<f64>> {
        let total = self.total_weight();
        if self.is_empty() || total <= 0.0 {
            return None;
        }
        let u = rng.random::<f64>() * total;
        let k = self
            .cumulative
            .partition_point(|&c| c < u)
            .min(self.len() - 1);
        let c = self.kernels.position(k);
        let mean = Isometry3::from_parts(
            Translation3::new(c[0], c[1], c[2]),
            self.kernels.rotation(k),
        );
        Some(sample_pose_kernel(&mean, self.sigma_p, self.kappa, rng))
    }
}

/// Draws an object feature and a contact sample with matching curvature (spec §3.2 steps
/// 1–4): up to 100 trials per band, the band widening up to 10 times.
fn draw_match<'a>(
    contact: &ContactModel,
    features: &'a [SurfaceFeature],
    inv_var: &[f64; 2],
    scratch: &mut [f64],
    rng: &mut StdRng,
) -> Option<(&'a SurfaceFeature, usize)> {
    for band in 0..=10 {
        let b = 0.5f64.powi(band);
        for _ in 0..100 {
            let feature = &features[rng.random_range(0..features.len())];
            let mut total = 0.0;
            for (a, s) in scratch.iter_mut().zip(&contact.samples) {
                let e = b
                    * ((feature.curvature[0] - s.curvature[0]).powi(2) * inv_var[0]
                        + (feature.curvature[1] - s.curvature[1]).powi(2) * inv_var[1]);
                *a = if e < 25.0 { s.weight * (-e).exp() } else { 0.0 };
                total += *a;
            }
            if total > 0.0 {
                let mut u = rng.random::<f64>() * total;
                for (m, a) in scratch.iter().enumerate() {
                    if u < *a {
                        return Some((feature, m));
                    }
                    u -= a;
                }
                let last = scratch.iter().rposition(|a| *a > 0.0)?;
                return Some((feature, last));
            }
        }
    }
    None
}

/// `s = v ∘ Rz(θ) ∘ u` with the sensor model's spin θ ~ N(μθ, σθ²), μθ ∈ {0, π},
/// `σθ = π·exp(−ρ((pc1 − pc2)/pc1)²)` (π when pc1 ≈ 0).
fn place(
    feature: &SurfaceFeature,
    feature_from_link: &Isometry3<f64>,
    rho: f64,
    rng: &mut StdRng,
) -> Isometry3<f64> {
    let [pc1, pc2] = feature.curvature;
    let sigma = if pc1 <= 1e-12 {
        std::f64::consts::PI
    } else {
        std::f64::consts::PI * (-rho * ((pc1 - pc2) / pc1).powi(2)).exp()
    };
    let mean = if rng.random::<bool>() {
        0.0
    } else {
        std::f64::consts::PI
    };
    let e: f64 = StandardNormal.sample(rng);
    let theta = mean + sigma * e;
    let spin = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), theta),
    );
    feature.pose() * spin * feature_from_link
}

/// The density distance `D(s)` (spec §3.3): the mean over model points of the best match cost
/// `‖Δp‖² + 0.01(1 − n·n_obj)` among object points within 5 mm with `1 − n·n_obj ≤ 0.25`,
/// or [`DENSITY_DISTANCE_MAX`] when none matches.
pub fn density_distance(
    object_from_link: &Isometry3<f64>,
    model_points: &[(Point3<f64>, Vector3<f64>)],
    features: &[SurfaceFeature],
    object_index: &PointIndex,
) -> f64 {
    if model_points.is_empty() {
        return DENSITY_DISTANCE_MAX;
    }
    let mut total = 0.0;
    for (p, n) in model_points {
        let p = object_from_link * p;
        let n = object_from_link.rotation * n;
        let mut best = DENSITY_DISTANCE_MAX;
        object_index.for_each_within(&p, 0.005, |j, d2| {
            let misalign = 1.0 - n.dot(&features[j].normal);
            if misalign <= 0.25 {
                best = best.min(d2 + 0.01 * misalign);
            }
        });
        total += best;
    }
    total / model_points.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grasp::model::kernel::{item_rng, quaternion_distance, unit_vector};

    /// The grid evaluation against the defining sum over every kernel.
    #[test]
    fn grid_evaluation_matches_brute_force() {
        let params = ModelParams::default();
        let mut rng = item_rng(5, 0, 0);
        let kernels: Vec<Kernel> = (0..3000)
            .map(|_| {
                let p = unit_vector(&mut rng) * 0.05 + Vector3::new(0.01, -0.02, 0.3);
                let r = UnitQuaternion::from_scaled_axis(unit_vector(&mut rng) * 0.4);
                Kernel {
                    pose: Isometry3::from_parts(p.into(), r),
                    weight: rng.random::<f64>(),
                }
            })
            .collect();
        let reference: Vec<(Isometry3<f64>, f64)> =
            kernels.iter().map(|k| (k.pose, k.weight)).collect();
        let density = QueryDensity::from_kernels(0, 0.0, kernels, &params);
        let s2 = params.query_sigma_position.powi(2);
        for i in 0..300 {
            let base = reference[i * 7 % reference.len()].0;
            let jitter = Isometry3::from_parts(
                (unit_vector(&mut rng) * 0.01 * rng.random::<f64>()).into(),
                UnitQuaternion::from_scaled_axis(unit_vector(&mut rng) * 0.2 * rng.random::<f64>()),
            );
            let q = jitter * base;
            let brute: f64 = reference
                .iter()
                .map(|(k, w)| {
                    let d2 = (q.translation.vector - k.translation.vector).norm_squared();
                    let dq = quaternion_distance(&q.rotation, &k.rotation);
                    let e = d2 / s2 + params.query_kappa * dq;
                    if d2 < 25.0 * s2 && dq < 25.0 / params.query_kappa && e < 25.0 {
                        w * (-e).exp()
                    } else {
                        0.0
                    }
                })
                .sum();
            let got = density.evaluate(&q);
            assert!(
                (got - brute).abs() <= 1e-12 * brute.max(1.0),
                "{got} vs {brute}"
            );
        }
    }
}
