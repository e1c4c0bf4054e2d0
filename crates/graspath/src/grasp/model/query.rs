//! Query densities: for each involved link, weighted pose kernels of the link on a new object,
//! built by placing demonstrated link-to-surface relations on object features of similar
//! curvature (spec §3), and their fast evaluation through a sparse uniform grid.
//!
//! One file on purpose (about 700 lines, a third of them tests against brute force): building a
//! link's kernels and the sparse grid that evaluates them are one data structure.

use super::contact::{curvature_bandwidth, ContactModel};
use super::kernel::{item_rng, sample_pose_kernel};
use super::lanes::{KernelTable, LaneQuery, WeightedKernel};
use super::ModelParams;
use crate::cloud::{PointIndex, SurfaceFeature};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::{rngs::StdRng, RngExt};
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;
use rustc_hash::FxHashMap;

/// Cells per position cut-off radius in the kernel grid.
const REACH: i64 = 2;
/// Rows of cells an evaluation scans at most.
const ROWS: usize = ((2 * REACH + 1) * (2 * REACH + 1)) as usize;

/// The cells `c − REACH ..= c + REACH`, clamped to `±CELL_LIMIT`.
#[inline]
fn neighbour_cells(c: i64) -> std::ops::RangeInclusive<i64> {
    (c - REACH).max(-CELL_LIMIT)..=(c + REACH).min(CELL_LIMIT)
}

/// Largest density-distance cost (matched cost bound × 10).
pub(super) const DENSITY_DISTANCE_MAX: f64 = 10.0 * (2.5e-5 + 0.01 * 0.25);

/// The query density `Q_i` of one link: kernel centres `object_from_link` with weights.
#[derive(Debug, Clone)]
pub(super) struct QueryDensity {
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

/// The kernels' cells, stored sparsely: only non-empty cells exist, so memory and lookup time
/// depend on the number of kernels, never on how far apart they lie (a cloud with a point
/// 1 km or 1e20 m away costs the same as one without).
///
/// Cells are cubes of side `1/inv_cell` anchored at `origin` (the kernels' lower corner,
/// far outliers aside: see [`ORIGIN_SPAN`]);
/// cell coordinates are clamped to `±CELL_LIMIT`, so no float→integer conversion or
/// neighbour offset can overflow. A clamped boundary cell collects every kernel beyond it;
/// that is still exact, because the kernel sum applies the cut-offs to every kernel it visits.
///
/// The kernels are ordered by cell `(z, y, x)`, then by draw index (the order a dense grid
/// would give), so a row of cells `x0..=x1` at `(y, z)` is one contiguous run of kernels.
#[derive(Debug, Clone)]
struct Grid {
    origin: [f64; 3],
    inv_cell: f64,
    /// `(cz, cy)` → the row's range in `cell_x` / `cell_start`.
    rows: FxHashMap<(i64, i64), (usize, usize)>,
    /// Each non-empty cell's x coordinate, increasing within a row.
    cell_x: Vec<i64>,
    /// Each non-empty cell's first kernel, plus one entry (the kernel count) at the end.
    cell_start: Vec<usize>,
}

/// Kernels farther than this (m) from the kernels' median along an axis do not set the
/// grid's origin along it: the origin stays near the bulk of the kernels, whose offsets
/// `p − origin` keep their full resolution however far an outlier lies. Kernels within this
/// span of the median (every kernel of an ordinary cloud) give the plain minimum.
const ORIGIN_SPAN: f64 = 1e6;

/// Cell coordinates are clamped to `±2⁵²`, where every integer is exact as an `f64` and
/// `±REACH` cannot overflow.
const CELL_LIMIT: i64 = 1 << 52;

/// The cell coordinate of a scaled offset: `floor(v)` clamped to `±CELL_LIMIT` (NaN → 0).
#[inline]
fn cell_coordinate(v: f64) -> i64 {
    if v.is_nan() {
        return 0;
    }
    (v.floor().clamp(-(CELL_LIMIT as f64), CELL_LIMIT as f64)) as i64
}

impl Grid {
    fn cell_of(&self, p: &[f64; 3]) -> [i64; 3] {
        std::array::from_fn(|a| cell_coordinate((p[a] - self.origin[a]) * self.inv_cell))
    }

    /// Builds the grid over `positions`; returns it and the kernel order (indices into
    /// `positions`), sorted by cell then index.
    fn build(positions: &[[f64; 3]], cell: f64) -> (Self, Vec<usize>) {
        let origin: [f64; 3] = std::array::from_fn(|a| {
            let mut values: Vec<f64> = positions.iter().map(|p| p[a]).collect();
            if values.is_empty() {
                return 0.0;
            }
            let middle = values.len() / 2;
            let (_, median, _) = values.select_nth_unstable_by(middle, f64::total_cmp);
            let median = *median;
            values
                .iter()
                .filter(|v| (*v - median).abs() <= ORIGIN_SPAN)
                .fold(median, |lo, v| lo.min(*v))
        });
        let mut grid = Grid {
            origin,
            inv_cell: 1.0 / cell,
            rows: FxHashMap::default(),
            cell_x: Vec::new(),
            cell_start: Vec::new(),
        };
        let mut keyed: Vec<([i64; 3], usize)> = positions
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let [cx, cy, cz] = grid.cell_of(p);
                ([cz, cy, cx], i)
            })
            .collect();
        keyed.sort_unstable();
        let mut previous: Option<[i64; 3]> = None;
        for (k, (c, _)) in keyed.iter().enumerate() {
            if previous == Some(*c) {
                continue;
            }
            let cell_index = grid.cell_x.len();
            let row = (c[0], c[1]);
            match previous {
                Some(p) if (p[0], p[1]) == row => {}
                _ => {
                    grid.rows.insert(row, (cell_index, cell_index));
                }
            }
            if let Some(entry) = grid.rows.get_mut(&row) {
                entry.1 = cell_index + 1;
            }
            grid.cell_x.push(c[2]);
            grid.cell_start.push(k);
            previous = Some(*c);
        }
        grid.cell_start.push(keyed.len());
        (grid, keyed.into_iter().map(|(_, i)| i).collect())
    }

    /// The kernels of row `(cz, cy)` in cells `x0..=x1`, as a range of kernel indices.
    #[inline]
    fn run(&self, cz: i64, cy: i64, x0: i64, x1: i64) -> Option<std::ops::Range<usize>> {
        let &(first, last) = self.rows.get(&(cz, cy))?;
        let xs = &self.cell_x[first..last];
        let lo = first + xs.partition_point(|&x| x < x0);
        let hi = first + xs.partition_point(|&x| x <= x1);
        (lo < hi).then(|| self.cell_start[lo]..self.cell_start[hi])
    }
}

struct Kernel {
    pose: Isometry3<f64>,
    weight: f64,
}

/// The object-level statistics used by the curvature-bandwidth adaptation.
pub(super) fn object_curvature_stats(
    features: &[SurfaceFeature],
    factor: f64,
) -> ([f64; 2], [f64; 2]) {
    curvature_bandwidth(features.iter().map(|f| f.curvature), factor)
}

/// Adapts a link's curvature widths to the object (spec §3.3): the overlap rule
/// `σ ≥ σo/5` acts as the degenerate-variance guard; the mean rule
/// `σ ≥ |μ − μo| − σo + σo/5` widens the kernel when the demonstrated curvature is far from the
/// object's and is what the penalty `pen = Σ_d (σ_new/σ_old − 1)` measures.
pub(super) fn adapt_bandwidth(
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
    pub(super) fn build(
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
        let positions: Vec<[f64; 3]> = kernels
            .iter()
            .map(|k| k.pose.translation.vector.into())
            .collect();
        let (grid, order) = Grid::build(&positions, cell);
        let ordered: Vec<WeightedKernel> = order
            .into_iter()
            .map(|i| {
                let k = &kernels[i];
                (positions[i], k.pose.rotation, k.weight.max(floor))
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
    pub(super) fn len(&self) -> usize {
        self.kernels.len()
    }

    /// Whether the density has no kernel.
    pub(super) fn is_empty(&self) -> bool {
        self.kernels.is_empty()
    }

    /// `Σ_k w_k` (before the link factor).
    pub(super) fn total_weight(&self) -> f64 {
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
    pub(super) fn evaluate(&self, object_from_link: &Isometry3<f64>) -> f64 {
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
        let grid = &self.grid;
        let cell = 1.0 / grid.inv_cell;
        let centre = grid.cell_of(&p);
        // The distance from `p` to the slab of cells `c` along `axis`; zero for a clamped
        // boundary cell, which stands for everything beyond it.
        let gap = |axis: usize, c: i64| {
            if c.abs() >= CELL_LIMIT {
                return 0.0;
            }
            let lo = grid.origin[axis] + c as f64 * cell;
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
        for cz in neighbour_cells(centre[2]) {
            let gz = gap(2, cz);
            for cy in neighbour_cells(centre[1]) {
                let gy = gap(1, cy);
                let rest = cut_p - gz * gz - gy * gy;
                if rest <= 0.0 {
                    continue;
                }
                let rx = rest.sqrt();
                let x0 = cell_coordinate((p[0] - rx - grid.origin[0]) * grid.inv_cell);
                let x1 = cell_coordinate((p[0] + rx - grid.origin[0]) * grid.inv_cell);
                if let Some(range) = grid.run(cz, cy, x0, x1) {
                    runs[count] = range;
                    count += 1;
                }
            }
        }
        self.kernels.sum(&runs[..count], &query)
    }

    /// A link pose drawn from the density: a kernel by weight, perturbed by the kernel.
    pub(super) fn sample(&self, rng: &mut StdRng) -> Option<Isometry3<f64>> {
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
pub(super) fn density_distance(
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
    use rand::rngs::StdRng;

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

    /// The defining sum over every kernel, with the cut-offs of [`QueryDensity::evaluate`].
    fn brute_force(reference: &[(Isometry3<f64>, f64)], q: &Isometry3<f64>, floor: f64) -> f64 {
        let params = ModelParams::default();
        let s2 = params.query_sigma_position.powi(2);
        reference
            .iter()
            .map(|(k, w)| {
                let d2 = (q.translation.vector - k.translation.vector).norm_squared();
                let dq = quaternion_distance(&q.rotation, &k.rotation);
                let e = d2 / s2 + params.query_kappa * dq;
                if d2 < 25.0 * s2 && dq < 25.0 / params.query_kappa && e < 25.0 {
                    w.max(floor) * (-e).exp()
                } else {
                    0.0
                }
            })
            .sum()
    }

    fn random_kernels(rng: &mut StdRng, n: usize, far: &[f64]) -> Vec<Kernel> {
        (0..n)
            .map(|i| {
                let mut p = unit_vector(rng) * 0.05 * rng.random::<f64>();
                if !far.is_empty() && i % 7 == 3 {
                    // A kernel on a far outlier: along a random axis direction.
                    let d = far[rng.random_range(0..far.len())];
                    p += unit_vector(rng) * d;
                }
                let r = UnitQuaternion::from_scaled_axis(unit_vector(rng) * 0.4);
                Kernel {
                    pose: Isometry3::from_parts(p.into(), r),
                    weight: rng.random::<f64>(),
                }
            })
            .collect()
    }

    /// The dense grid this sparse one replaced, rebuilt here as an oracle: a `dims`-sized
    /// array of cells over the kernels' bounds, rows scanned with the same cut-off sphere.
    /// The kernel table must already be in dense-cell order, and the runs over it must give
    /// the bit-identical sum.
    #[test]
    fn sparse_grid_is_bit_identical_to_the_dense_grid() {
        let params = ModelParams::default();
        let mut rng = item_rng(11, 0, 0);
        let kernels = random_kernels(&mut rng, 2500, &[]);
        let reference: Vec<[f64; 3]> = kernels
            .iter()
            .map(|k| k.pose.translation.vector.into())
            .collect();
        let density = QueryDensity::from_kernels(0, 0.0, kernels, &params);
        let sigma_p = params.query_sigma_position;
        let cell = 5.0 * sigma_p / REACH as f64;
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &reference {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let dims: [i64; 3] = std::array::from_fn(|a| ((hi[a] - lo[a]) / cell).floor() as i64 + 1);
        let inv_cell = 1.0 / cell;
        let dense_cell = |p: &[f64; 3]| -> [i64; 3] {
            std::array::from_fn(|a| ((p[a] - lo[a]) * inv_cell).floor() as i64)
        };
        let dense_index = |c: [i64; 3]| ((c[2] * dims[1] + c[1]) * dims[0] + c[0]) as usize;
        // The table order: by dense cell index, then by draw index.
        let mut expected: Vec<(usize, usize)> = reference
            .iter()
            .enumerate()
            .map(|(i, p)| (dense_index(dense_cell(p)), i))
            .collect();
        expected.sort_unstable();
        for (k, (_, i)) in expected.iter().enumerate() {
            assert_eq!(density.kernels.position(k), reference[*i], "kernel {k}");
        }
        let mut starts = vec![0usize; (dims[0] * dims[1] * dims[2]) as usize + 1];
        for (c, _) in &expected {
            starts[c + 1] += 1;
        }
        for c in 0..starts.len() - 1 {
            starts[c + 1] += starts[c];
        }
        for i in 0..400 {
            let base = reference[i * 13 % reference.len()];
            let p = Vector3::from(base) + unit_vector(&mut rng) * 0.03 * rng.random::<f64>();
            let r = UnitQuaternion::from_scaled_axis(unit_vector(&mut rng) * 0.4);
            let q = Isometry3::from_parts(p.into(), r);
            let p = [p.x, p.y, p.z];
            let cut_p = 25.0 * sigma_p * sigma_p;
            let centre = dense_cell(&p);
            let gap = |axis: usize, c: i64| {
                let l = lo[axis] + c as f64 * cell;
                (l - p[axis]).max(p[axis] - l - cell).max(0.0)
            };
            let mut runs = Vec::new();
            for cz in (centre[2] - REACH).max(0)..=(centre[2] + REACH).min(dims[2] - 1) {
                for cy in (centre[1] - REACH).max(0)..=(centre[1] + REACH).min(dims[1] - 1) {
                    let rest = cut_p - gap(2, cz).powi(2) - gap(1, cy).powi(2);
                    if rest <= 0.0 {
                        continue;
                    }
                    let rx = rest.sqrt();
                    let x0 = (((p[0] - rx - lo[0]) * inv_cell).floor() as i64).max(0);
                    let x1 = (((p[0] + rx - lo[0]) * inv_cell).floor() as i64).min(dims[0] - 1);
                    if x0 <= x1 {
                        let row = ((cz * dims[1] + cy) * dims[0]) as usize;
                        runs.push(starts[row + x0 as usize]..starts[row + x1 as usize + 1]);
                    }
                }
            }
            let query = LaneQuery {
                position: p,
                rotation: [q.rotation.w, q.rotation.i, q.rotation.j, q.rotation.k],
                inv_var: 1.0 / (sigma_p * sigma_p),
                kappa: params.query_kappa,
                cut_p,
                cut_q: 25.0 / params.query_kappa,
            };
            let dense = density.kernels.sum(&runs, &query);
            assert_eq!(density.evaluate(&q).to_bits(), dense.to_bits(), "query {i}");
        }
    }

    /// Kernels on far outliers (10 m to 1e300 m, either side) build a grid whose size is the
    /// number of non-empty cells (never the extent), and evaluation near any kernel, near
    /// the far ones and at extreme positions agrees with the brute-force sum.
    #[test]
    fn far_outliers_cost_nothing_and_evaluate_exactly() {
        let params = ModelParams::default();
        let mut rng = item_rng(12, 0, 0);
        let far = [10.0, 1e3, 1e20, -1e20, 1e300, 4e13];
        let kernels = random_kernels(&mut rng, 700, &far);
        let n = kernels.len();
        let floor = 1e-10 / n as f64;
        let reference: Vec<(Isometry3<f64>, f64)> =
            kernels.iter().map(|k| (k.pose, k.weight)).collect();
        let density = QueryDensity::from_kernels(0, 0.0, kernels, &params);
        assert!(density.grid.cell_x.len() <= n);
        assert!(density.grid.rows.len() <= n);
        // The kernels near the object keep their own cells (the origin is not dragged to
        // −1e20): 600 kernels in a 5 cm ball over 12.5 mm cells occupy well over 50.
        assert!(
            density.grid.cell_x.len() > 50,
            "{}",
            density.grid.cell_x.len()
        );
        let mut queries: Vec<Isometry3<f64>> = reference
            .iter()
            .map(|(k, _)| {
                let jitter = Isometry3::from_parts(
                    (unit_vector(&mut rng) * 0.01 * rng.random::<f64>()).into(),
                    UnitQuaternion::from_scaled_axis(unit_vector(&mut rng) * 0.1),
                );
                jitter * k
            })
            .collect();
        for v in [1e20, -1e20, 1e300, f64::MAX, -f64::MAX] {
            queries.push(Isometry3::translation(v, v, -v));
        }
        for q in &queries {
            let got = density.evaluate(q);
            let want = brute_force(&reference, q, floor);
            assert!(
                (got - want).abs() <= 1e-12 * want.max(1.0),
                "{got} vs {want} at {:?}",
                q.translation
            );
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
        /// Random clouds of kernels with far outliers at random distances: the sparse lookup
        /// equals the brute-force scan at random queries near random kernels.
        #[test]
        fn sparse_lookup_equals_brute_force(
            seed in 0u64..1_000_000,
            n in 1usize..400,
            far_exponent in 0.0f64..25.0,
        ) {
            let params = ModelParams::default();
            let mut rng = item_rng(seed, 1, 0);
            let far = [10f64.powf(far_exponent), -(10f64.powf(far_exponent / 2.0))];
            let kernels = random_kernels(&mut rng, n, &far);
            let floor = 1e-10 / n as f64;
            let reference: Vec<(Isometry3<f64>, f64)> =
                kernels.iter().map(|k| (k.pose, k.weight)).collect();
            let density = QueryDensity::from_kernels(0, 0.0, kernels, &params);
            for _ in 0..40 {
                let (k, _) = reference[rng.random_range(0..n)];
                let jitter = Isometry3::from_parts(
                    (unit_vector(&mut rng) * 0.03 * rng.random::<f64>()).into(),
                    UnitQuaternion::from_scaled_axis(unit_vector(&mut rng) * 0.2),
                );
                let q = jitter * k;
                let got = density.evaluate(&q);
                let want = brute_force(&reference, &q, floor);
                proptest::prop_assert!((got - want).abs() <= 1e-12 * want.max(1.0), "{} vs {}", got, want);
            }
        }
    }
}
