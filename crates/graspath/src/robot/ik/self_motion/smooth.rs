//! The smooth self-motion search: where a redundant arm sits in its self-motion as a smooth
//! function of the motion's time.
//!
//! **Why.** The discrete search ([`optimize_self_motion`](super::optimize_self_motion)) picks
//! one traced configuration per sample, and consecutive samples may sit up to the joint-step
//! bound apart along the self-motion: its joint paths jump from sample to sample, and the
//! densest sampling gives the roughest path. A controller cannot follow such a path quickly,
//! and its gain depends on the sampling.
//!
//! **How.** The self-motion is traced at every sample around a seed path (one configuration
//! per target), each curve oriented like the one before it. A configuration on sample `i`'s
//! curve is named by its signed joint-space arc length `α` from the seed's configuration
//! (rad / m), and the search chooses `α` as a clamped uniform cubic B-spline of the motion's
//! normalised time `τ ∈ [0, 1]` with a fixed number of control points: `α(τ)` is twice
//! continuously differentiable and means the same thing at any sampling. Each sample's curve
//! ends where it leaves the joint limits (found to 1e-12 of a step) or after `reach` steps,
//! and `α` must stay within every sample's traced part. The objective `Σ wᵢ vᵢ(α(τᵢ))`
//! interpolates each sample's values linearly between its traced states; it is maximised by
//! coordinate ascent with halving steps, from the seed itself (`α ≡ 0`) and from the
//! least-squares fit of the discrete search's optimum (scaled towards 0 until it is inside).
//! The chosen `α` is then traced to
//! exactly at every sample, and the path is kept when it collects more than the seed and no
//! joint moves more than the step bound between samples; otherwise the seed is returned.

use super::trace::{Convergence, Tracer};
use super::{
    best_chain, distance, max_difference, rotation_matrix_poses, KeptRows, SampleValue,
    SelfMotionOptions, SelfMotionPath, State, Traced,
};
use crate::robot::chain::Chain;
use nalgebra::{DMatrix, DVector, Isometry3, IsometryMatrix3};

/// What the smooth search needs beyond the traced curve's settings.
#[derive(Debug, Clone, Copy)]
pub struct SmoothSelfMotion<'a> {
    /// Each target's time (s, non-decreasing): `α` is a function of it. Targets before the
    /// object's path (an approach) take the path's first time, those after it its last, so
    /// the arm keeps its place in the self-motion while the tool approaches and retreats.
    pub times: &'a [f64],
    /// Each target's weight in the objective (e.g. its share of the path's duration, for a
    /// root mean square over time; 1 for a sum over samples; 0 for targets that do not count).
    pub weights: &'a [f64],
    /// Control points of `α`'s B-spline (at least 4): the number of independent bends the
    /// self-motion may take over the motion.
    pub control_points: usize,
}

/// Control points of the default smooth search: enough for the arm to move through its
/// self-motion and back twice over a motion, few enough that `α` cannot follow one sample.
const DEFAULT_CONTROL_POINTS: usize = 8;

impl<'a> SmoothSelfMotion<'a> {
    /// The smooth search over `times` with `weights` and 8 control points.
    pub fn new(times: &'a [f64], weights: &'a [f64]) -> Self {
        Self {
            times,
            weights,
            control_points: DEFAULT_CONTROL_POINTS,
        }
    }
}

/// The joint path through `base_from_targets` (tip poses, chain base frame) that keeps the tip
/// on its targets, places the arm in its self-motion around `seed` (one configuration per
/// target, on target and inside the limits) as a smooth function of time, and maximises
/// `Σ wᵢ value(i, qᵢ, J(qᵢ))` (see the module docs); never below the seed's own sum. The
/// result's `values` are the unweighted values, `total` their sum, and `worst_total` /
/// `best_total` the smallest and largest unweighted sums of any chain of traced states under
/// the joint-step bound (the self-motion's range). `None` when the lengths differ, there is
/// no target, or the seed is off its targets.
pub fn optimize_smooth_self_motion(
    chain: &Chain,
    base_from_targets: &[Isometry3<f64>],
    seed: &[Vec<f64>],
    rows: KeptRows,
    value: &SampleValue<'_>,
    options: &SelfMotionOptions,
    smooth: &SmoothSelfMotion<'_>,
) -> Option<SelfMotionPath> {
    let n = base_from_targets.len();
    if n == 0
        || seed.len() != n
        || smooth.times.len() != n
        || smooth.weights.len() != n
        || smooth.control_points < 4
    {
        return None;
    }
    let targets = rotation_matrix_poses(base_from_targets);
    let mut tracer = Tracer::new(chain, rows, options);
    let traced = tracer.trace_along(&targets, seed, value);
    if traced.iter().any(|t| t.curve == 0) {
        return None;
    }
    let chosen = best_chain(&traced, options.max_joint_step)?;
    let curves: Vec<Curve> = traced.iter().map(Curve::new).collect();
    let basis = Basis::new(smooth.times, smooth.control_points);
    let objective = Objective {
        curves: &curves,
        basis: &basis,
        weights: smooth.weights,
    };
    let seed_values: Vec<f64> = traced.iter().map(|t| t.states[t.middle].value).collect();
    let seed_path = || SelfMotionPath {
        q: seed.to_vec(),
        total: seed_values.iter().sum(),
        values: seed_values.clone(),
        worst_total: chosen.worst_total,
        best_total: chosen.best_total,
    };
    // The discrete optimum's places along the curves, fitted by the spline.
    let discrete: Vec<f64> = chosen
        .states
        .iter()
        .zip(&curves)
        .map(|(&k, curve)| curve.alpha[k])
        .collect();
    let starts = [
        DVector::zeros(smooth.control_points),
        objective.inside_towards(basis.fit(&discrete, smooth.weights)),
    ];
    let mut best: Option<(DVector<f64>, f64)> = None;
    for start in starts {
        let climbed = objective.climb(start);
        if best.as_ref().is_none_or(|(_, f)| climbed.1 > *f) {
            best = Some(climbed);
        }
    }
    let (control, found) = best?;
    let at_seed = objective.value(&DVector::zeros(smooth.control_points))?;
    if found <= at_seed {
        return Some(seed_path());
    }
    // Traced to exactly; where the curves do not follow one another there, with `α` scaled
    // towards the seed.
    let weighted =
        |values: &[f64]| -> f64 { values.iter().zip(smooth.weights).map(|(v, w)| v * w).sum() };
    let realization = Realization {
        traced: &traced,
        curves: &curves,
        basis: &basis,
        targets: &targets,
        seed,
        max_joint_step: options.max_joint_step,
    };
    let mut scale = 1.0;
    for _ in 0..SCALINGS {
        if let Some((q, values)) = realization.realize(&mut tracer, &(&control * scale), value) {
            if weighted(&values) > weighted(&seed_values) {
                return Some(SelfMotionPath {
                    total: values.iter().sum(),
                    q,
                    values,
                    worst_total: chosen.worst_total,
                    best_total: chosen.best_total,
                });
            }
        }
        scale *= 0.5;
    }
    Some(seed_path())
}

/// Halvings of `α` tried, at most, when the traced curves do not follow one another.
const SCALINGS: usize = 4;

/// How much farther than the seed a configuration at one `α` may move from one sample to the
/// next: a larger move means the two samples' curves were traced onto different parts of the
/// self-motion (near a singularity), and `α` does not name the same configuration on both.
const FOLLOWING: f64 = 5.0;

/// The joint path at the places a spline of `α` names.
struct Realization<'a> {
    traced: &'a [Traced],
    curves: &'a [Curve],
    basis: &'a Basis,
    targets: &'a [IsometryMatrix3<f64>],
    seed: &'a [Vec<f64>],
    max_joint_step: f64,
}

impl Realization<'_> {
    /// The configurations and values at `α(τᵢ)` for `control`; `None` when one is not
    /// reached, a joint steps farther than the bound, or a sample's configuration at its `α`
    /// is farther from the previous sample's at the same `α` than [`FOLLOWING`] times the
    /// seed's own step.
    fn realize(
        &self,
        tracer: &mut Tracer<'_>,
        control: &DVector<f64>,
        value: &SampleValue<'_>,
    ) -> Option<(Vec<Vec<f64>>, Vec<f64>)> {
        let n = self.traced.len();
        let mut q: Vec<Vec<f64>> = Vec::with_capacity(n);
        let mut values = Vec::with_capacity(n);
        for i in 0..n {
            let (at, curve) = (&self.traced[i], &self.curves[i]);
            let alpha = curve.clamp(self.basis.alpha(i, control));
            let state =
                tracer.trace_to(at, curve, alpha, &self.targets[i], &|q, j| value(i, q, j))?;
            if let Some(previous) = q.last() {
                if max_difference(previous, &state.q) > self.max_joint_step {
                    return None;
                }
                let before = &self.curves[i - 1];
                let same = before.clamp(alpha);
                let there = tracer.trace_to(
                    &self.traced[i - 1],
                    before,
                    same,
                    &self.targets[i - 1],
                    &|_, _| 0.0,
                )?;
                let seed_step = distance(&self.seed[i - 1], &self.seed[i]);
                let moved = distance(&there.q, &state.q) - (alpha - same).abs();
                if moved > FOLLOWING * seed_step + 1e-9 {
                    return None;
                }
            }
            q.push(state.q);
            values.push(state.value);
        }
        Some((q, values))
    }
}

/// One sample's traced curve by arc length: each state's `α` (rad / m, 0 at the seed's
/// configuration, increasing along the curve).
struct Curve {
    alpha: Vec<f64>,
    value: Vec<f64>,
}

impl Curve {
    fn new(traced: &Traced) -> Self {
        let states = &traced.states[..traced.curve];
        let mut alpha = vec![0.0; states.len()];
        for k in traced.middle + 1..states.len() {
            alpha[k] = alpha[k - 1] + distance(&states[k - 1].q, &states[k].q);
        }
        for k in (0..traced.middle).rev() {
            alpha[k] = alpha[k + 1] - distance(&states[k + 1].q, &states[k].q);
        }
        Self {
            alpha,
            value: states.iter().map(|s| s.value).collect(),
        }
    }

    /// `alpha` moved into the traced part of the curve (against rounding).
    fn clamp(&self, alpha: f64) -> f64 {
        alpha.clamp(self.alpha[0], self.alpha[self.alpha.len() - 1])
    }

    /// The value at `alpha`, linear between traced states; `None` outside the traced part.
    fn value_at(&self, alpha: f64) -> Option<f64> {
        let (first, last) = (self.alpha[0], self.alpha[self.alpha.len() - 1]);
        if !(first..=last).contains(&alpha) {
            return None;
        }
        let k = self.segment(alpha);
        if k + 1 == self.alpha.len() {
            return Some(self.value[k]);
        }
        let (a0, a1) = (self.alpha[k], self.alpha[k + 1]);
        let t = if a1 > a0 {
            (alpha - a0) / (a1 - a0)
        } else {
            0.0
        };
        Some(self.value[k] + t * (self.value[k + 1] - self.value[k]))
    }

    /// The last state at or before `alpha` (the first state when `alpha` is before it).
    fn segment(&self, alpha: f64) -> usize {
        self.alpha
            .partition_point(|a| *a <= alpha)
            .saturating_sub(1)
    }
}

/// A clamped uniform cubic B-spline basis evaluated at every target's normalised time: `α` at
/// target `i` is `Σₖ weights[i][k] · control[first[i] + k]`.
struct Basis {
    first: Vec<usize>,
    weights: Vec<[f64; 4]>,
    control_points: usize,
}

impl Basis {
    fn new(times: &[f64], control_points: usize) -> Self {
        let (start, end) = (
            times.first().copied().unwrap_or(0.0),
            times.last().copied().unwrap_or(0.0),
        );
        let span = end - start;
        let segments = control_points - 3;
        let mut first = Vec::with_capacity(times.len());
        let mut weights = Vec::with_capacity(times.len());
        for &t in times {
            let tau = if span > 0.0 {
                ((t - start) / span).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let (k, w) = clamped_cubic(tau, segments);
            first.push(k);
            weights.push(w);
        }
        Self {
            first,
            weights,
            control_points,
        }
    }

    fn alpha(&self, i: usize, control: &DVector<f64>) -> f64 {
        let k = self.first[i];
        self.weights[i]
            .iter()
            .enumerate()
            .map(|(m, w)| w * control[k + m])
            .sum()
    }

    /// The control points whose spline is closest to `alpha` in the `weights`-weighted least
    /// squares sense (a small ridge keeps control points that no weighted target sees at 0).
    fn fit(&self, alpha: &[f64], weights: &[f64]) -> DVector<f64> {
        let size = self.control_points;
        let total: f64 = weights.iter().sum();
        let ridge = 1e-9 * total.max(1e-300);
        let mut normal = DMatrix::identity(size, size) * ridge;
        let mut right = DVector::zeros(size);
        for (i, (&a, &w)) in alpha.iter().zip(weights).enumerate() {
            let k = self.first[i];
            for (m, bm) in self.weights[i].iter().enumerate() {
                right[k + m] += w * bm * a;
                for (l, bl) in self.weights[i].iter().enumerate() {
                    normal[(k + m, k + l)] += w * bm * bl;
                }
            }
        }
        normal
            .cholesky()
            .map_or_else(|| DVector::zeros(size), |c| c.solve(&right))
    }
}

/// The four non-zero cubic B-spline weights at `tau ∈ [0, 1]` on a clamped uniform knot
/// vector of `segments` spans, and the first control point they weigh.
fn clamped_cubic(tau: f64, segments: usize) -> (usize, [f64; 4]) {
    let p = 3;
    // Knots: p + 1 zeros, the interior knots j / segments, p + 1 ones.
    let knot = |j: usize| -> f64 {
        if j <= p {
            0.0
        } else if j >= segments + p {
            1.0
        } else {
            (j - p) as f64 / segments as f64
        }
    };
    let span = ((tau * segments as f64).floor() as usize).min(segments - 1) + p;
    // De Boor–Cox: the basis functions of degree 0..=3 that are non-zero on `span`.
    let mut n = [0.0; 4];
    n[0] = 1.0;
    let mut left = [0.0; 4];
    let mut right = [0.0; 4];
    for d in 1..=p {
        left[d] = tau - knot(span + 1 - d);
        right[d] = knot(span + d) - tau;
        let mut saved = 0.0;
        for r in 0..d {
            let denominator = right[r + 1] + left[d - r];
            let temp = if denominator > 0.0 {
                n[r] / denominator
            } else {
                0.0
            };
            n[r] = saved + right[r + 1] * temp;
            saved = left[d - r] * temp;
        }
        n[d] = saved;
    }
    (span - p, n)
}

/// The search's objective over the control points.
struct Objective<'a> {
    curves: &'a [Curve],
    basis: &'a Basis,
    weights: &'a [f64],
}

/// Coordinate-ascent step lengths (rad / m): from two traced spacings down to a sixteenth of
/// one.
const STEPS: [f64; 6] = [0.4, 0.2, 0.1, 0.05, 0.025, 0.0125];

/// Sweeps over the control points per step length, at most.
const SWEEPS: usize = 20;

/// The relative gain a coordinate step must bring to be taken: far above rounding, so the
/// same task in another world frame climbs the same way.
const GAIN: f64 = 1e-9;

impl Objective<'_> {
    /// `Σ wᵢ vᵢ(α(τᵢ))`; `None` when `α` leaves the traced part of some curve.
    fn value(&self, control: &DVector<f64>) -> Option<f64> {
        let mut sum = 0.0;
        for (i, curve) in self.curves.iter().enumerate() {
            sum += self.weights[i] * curve.value_at(self.basis.alpha(i, control))?;
        }
        Some(sum)
    }

    /// `control` scaled towards 0 (the seed, always inside) until every `α` is inside the
    /// traced part of its curve.
    fn inside_towards(&self, control: DVector<f64>) -> DVector<f64> {
        let mut scale = 1.0;
        for _ in 0..20 {
            let scaled = &control * scale;
            if self.value(&scaled).is_some() {
                return scaled;
            }
            scale *= 0.5;
        }
        DVector::zeros(control.len())
    }

    /// Coordinate ascent from `start` (inside): each control point moved by ± each step
    /// length while that keeps every `α` inside and improves the objective. Returns the point
    /// reached and its value.
    fn climb(&self, start: DVector<f64>) -> (DVector<f64>, f64) {
        let mut control = start;
        let mut best = self.value(&control).unwrap_or(f64::NEG_INFINITY);
        for step in STEPS {
            for _ in 0..SWEEPS {
                let mut improved = false;
                for k in 0..control.len() {
                    for direction in [step, -step] {
                        let before = control[k];
                        control[k] = before + direction;
                        match self.value(&control) {
                            Some(v) if v > best + GAIN * best.abs() => {
                                best = v;
                                improved = true;
                            }
                            _ => control[k] = before,
                        }
                    }
                }
                if !improved {
                    break;
                }
            }
        }
        (control, best)
    }
}

impl Tracer<'_> {
    /// The configuration at `alpha` on a sample's traced curve, on target and inside the
    /// limits: the cubic Hermite interpolation of the traced states in `α` (tangents by
    /// finite differences), corrected onto the target. It is a traced state at that state's
    /// `α` and continuously differentiable in `α` between, so a smooth `α(τ)` gives a smooth
    /// joint path. `None` when the correction does not converge or leaves the limits.
    fn trace_to(
        &mut self,
        traced: &Traced,
        curve: &Curve,
        alpha: f64,
        target: &IsometryMatrix3<f64>,
        value: &dyn Fn(&[f64], &nalgebra::Matrix6xX<f64>) -> f64,
    ) -> Option<State> {
        let states = &traced.states[..curve.alpha.len()];
        let k = curve.segment(alpha);
        if alpha <= curve.alpha[k] || k + 1 >= states.len() {
            return Some(states[k].clone());
        }
        let (a0, a1) = (curve.alpha[k], curve.alpha[k + 1]);
        let h = a1 - a0;
        let t = (alpha - a0) / h;
        // Tangents dq/dα at the two states: central differences inside, one-sided at the ends.
        let tangent = |m: usize, j: usize| -> f64 {
            let (lo, hi) = (m.saturating_sub(1), (m + 1).min(states.len() - 1));
            (states[hi].q[j] - states[lo].q[j]) / (curve.alpha[hi] - curve.alpha[lo])
        };
        let (h00, h10, h01, h11) = (
            (1.0 + 2.0 * t) * (1.0 - t) * (1.0 - t),
            t * (1.0 - t) * (1.0 - t),
            t * t * (3.0 - 2.0 * t),
            t * t * (t - 1.0),
        );
        let guess: Vec<f64> = (0..states[k].q.len())
            .map(|j| {
                h00 * states[k].q[j]
                    + h10 * h * tangent(k, j)
                    + h01 * states[k + 1].q[j]
                    + h11 * h * tangent(k + 1, j)
            })
            .collect();
        let (mut q, _) = self.correct(guess, target, Convergence::Settled)?;
        if !self.inside(&q) {
            // A joint that rides its limit along the curve may come out beyond it by the
            // interpolation's error: back onto the limit, when the tip stays on target.
            if self.excess(&q) > self.options.position_tolerance {
                return None;
            }
            let (lower, upper) = (self.chain.lower(), self.chain.upper());
            for (j, v) in q.iter_mut().enumerate() {
                *v = v.clamp(lower[j], upper[j]);
            }
            let kept = self.kept(&q, target)?;
            if !self.on_target(&kept.error) {
                return None;
            }
        }
        Some(State {
            value: value(&q, &self.jacobian),
            q,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The clamped basis is a partition of unity, interpolates its end control points and
    /// equals a brute-force Cox–de Boor recursion over the whole knot vector.
    #[test]
    fn the_clamped_cubic_basis_matches_the_recursion() {
        fn recursive(j: usize, d: usize, tau: f64, knots: &[f64]) -> f64 {
            if d == 0 {
                let last = knots[knots.len() - 1];
                let inside = knots[j] <= tau && tau < knots[j + 1];
                let at_end = tau == last && knots[j] < knots[j + 1] && knots[j + 1] == last;
                return f64::from(inside || at_end);
            }
            let term =
                |num: f64, den: f64, rest: f64| if den > 0.0 { num / den * rest } else { 0.0 };
            term(
                tau - knots[j],
                knots[j + d] - knots[j],
                recursive(j, d - 1, tau, knots),
            ) + term(
                knots[j + d + 1] - tau,
                knots[j + d + 1] - knots[j + 1],
                recursive(j + 1, d - 1, tau, knots),
            )
        }
        for segments in [1, 2, 5] {
            let mut knots = vec![0.0; 4];
            knots.extend((1..segments).map(|j| j as f64 / segments as f64));
            knots.extend([1.0; 4]);
            for step in 0..=200 {
                let tau = step as f64 / 200.0;
                let (first, w) = clamped_cubic(tau, segments);
                assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
                for j in 0..segments + 3 {
                    let expected = recursive(j, 3, tau, &knots);
                    let got = if (first..first + 4).contains(&j) {
                        w[j - first]
                    } else {
                        0.0
                    };
                    assert!((expected - got).abs() < 1e-12, "{segments} {tau} {j}");
                }
            }
            assert_eq!(clamped_cubic(0.0, segments), (0, [1.0, 0.0, 0.0, 0.0]));
            let (last, w) = clamped_cubic(1.0, segments);
            assert_eq!(last + 3, segments + 2);
            assert!((w[3] - 1.0).abs() < 1e-12);
        }
    }

    /// The least-squares fit reproduces a spline of the basis exactly.
    #[test]
    fn the_fit_recovers_a_spline_of_its_basis() {
        let times: Vec<f64> = (0..50).map(|i| f64::from(i) * 0.1).collect();
        let basis = Basis::new(&times, 6);
        let control = DVector::from_vec(vec![0.3, -0.2, 0.5, 0.1, -0.4, 0.2]);
        let alpha: Vec<f64> = (0..times.len()).map(|i| basis.alpha(i, &control)).collect();
        let fitted = basis.fit(&alpha, &vec![1.0; times.len()]);
        assert!((fitted - control).amax() < 1e-6);
    }

    /// Linear interpolation between traced states, nothing outside them.
    #[test]
    fn curve_values_are_interpolated_inside_the_traced_part_only() {
        let curve = Curve {
            alpha: vec![-0.2, 0.0, 0.2, 0.4],
            value: vec![1.0, 2.0, 4.0, 3.0],
        };
        assert_eq!(curve.value_at(0.1), Some(3.0));
        assert_eq!(curve.value_at(0.4), Some(3.0));
        assert_eq!(curve.value_at(-0.2), Some(1.0));
        assert_eq!(curve.value_at(0.41), None);
        assert_eq!(curve.value_at(-0.3), None);
        assert_eq!(curve.clamp(0.7), 0.4);
        assert_eq!(curve.segment(0.2), 2);
    }
}
