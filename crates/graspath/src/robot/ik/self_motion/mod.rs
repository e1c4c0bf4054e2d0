//! Choosing where a redundant arm sits in its self-motion along a whole path: the joint path
//! that keeps the tip on its targets, moves no joint more than a step bound between samples,
//! and maximises a sum of per-sample values (for the task-relevant index, `Σ M_T²`, the square
//! of `μ_l2`).
//!
//! **How.** At every sample the self-motion through each given joint path is traced: from
//! the sample's configuration, steps of `spacing` (joint-space length, rad / m) along the
//! projection of the previous step onto the null space of the kept Jacobian rows, each
//! followed by Gauss–Newton corrections back onto the target, until a joint limit or
//! `reach` steps on either side. Those configurations are the states of a dynamic programme
//! over the samples: a state follows a state of the previous sample only when no joint moves
//! more than `max_joint_step`, and the best chain of states is kept. The self-motion is traced
//! around the first given path; the others join the states as they are. Every given path is
//! among the states, so the result is never worse than the best of them. Each chosen traced
//! state is then refined between its two neighbours on the curve: the peak of the parabola
//! through their three values is traced to, and kept when it is better and still within the
//! step bound of the neighbouring samples' choices (one more configuration per sample).
//!
//! With one redundant degree of freedom (a 7-joint arm keeping a pose, a planar 3R arm keeping
//! a position) the traced curve is the self-motion manifold near the given paths; with more,
//! it is one curve through it, and the optimum is over that curve.

mod smooth;
mod trace;

pub use smooth::{optimize_smooth_self_motion, SmoothSelfMotion};

use trace::Tracer;

use crate::robot::chain::Chain;
use nalgebra::{DMatrix, DVector, Isometry3, IsometryMatrix3, Matrix6xX};

/// Which rows of the tip pose the path keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum KeptRows {
    /// Position and orientation (6 rows).
    #[default]
    Pose,
    /// Position only (3 rows): the orientation is free.
    Position,
}

/// Settings of [`optimize_self_motion`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfMotionOptions {
    /// Joint-space distance between traced configurations (rad / m).
    pub spacing: f64,
    /// Traced configurations on each side of each given one.
    pub reach: usize,
    /// Largest change of any joint between consecutive samples (rad / m).
    pub max_joint_step: f64,
    /// How close a traced configuration's tip must be to its target (m).
    pub position_tolerance: f64,
    /// How close in orientation, when the pose is kept (rad).
    pub rotation_tolerance: f64,
}

impl Default for SelfMotionOptions {
    /// 0.2 rad spacing, 4 steps each side (±0.8 rad), 0.5 rad joint steps, 1e-5 m / rad.
    fn default() -> Self {
        Self {
            spacing: 0.2,
            reach: 4,
            max_joint_step: 0.5,
            position_tolerance: 1e-5,
            rotation_tolerance: 1e-5,
        }
    }
}

/// A joint path chosen in the self-motion, with the per-sample values it collects.
#[derive(Debug, Clone, PartialEq)]
pub struct SelfMotionPath {
    /// One configuration per target (rad / m).
    pub q: Vec<Vec<f64>>,
    /// The per-sample values along it.
    pub values: Vec<f64>,
    /// Their sum (the maximised objective).
    pub total: f64,
    /// The smallest sum any chain of states reaches (the other end of the self-motion's
    /// range on the traced states).
    pub worst_total: f64,
    /// The largest sum any chain of states reaches (this path's own `total` for the
    /// discrete search; the smooth search's path may collect less).
    pub best_total: f64,
}

/// The per-sample value to maximise: sample index, configuration and the geometric
/// Jacobian there (6 × dof, rows `[v; ω]`, base frame).
pub type SampleValue<'a> = dyn Fn(usize, &[f64], &Matrix6xX<f64>) -> f64 + Sync + 'a;

/// The joint path through `base_from_targets` (tip poses, chain base frame) that maximises
/// `Σ value(i, q_i, J(q_i))` over the self-motion traced around the first of `paths`, the
/// other paths joining as they are (each one configuration per target, feasible: on target,
/// inside the limits, steps within the bound); never worse than any of them.
/// `None` when no path is given or none has the right length.
pub fn optimize_self_motion(
    chain: &Chain,
    base_from_targets: &[Isometry3<f64>],
    paths: &[&[Vec<f64>]],
    rows: KeptRows,
    value: &SampleValue<'_>,
    options: &SelfMotionOptions,
) -> Option<SelfMotionPath> {
    let n = base_from_targets.len();
    let paths: Vec<&[Vec<f64>]> = paths.iter().copied().filter(|p| p.len() == n).collect();
    if paths.is_empty() || n == 0 {
        return None;
    }
    let targets = rotation_matrix_poses(base_from_targets);
    let mut tracer = Tracer::new(chain, rows, options);
    let mut traced = tracer.trace_along(&targets, paths[0], value);
    for (i, at) in traced.iter_mut().enumerate() {
        // The other paths join as they are, off the traced curve.
        for path in &paths[1..] {
            if tracer.jacobian_at(&path[i]) {
                let v = value(i, &path[i], &tracer.jacobian);
                at.states.push(State {
                    q: path[i].clone(),
                    value: v,
                });
            }
        }
    }
    let chosen = best_chain(&traced, options.max_joint_step)?;
    let mut q: Vec<Vec<f64>> = Vec::with_capacity(n);
    let mut values = Vec::with_capacity(n);
    for (i, &k) in chosen.states.iter().enumerate() {
        let next = traced
            .get(i + 1)
            .map(|t| t.states[chosen.states[i + 1]].q.as_slice());
        let refined = tracer.refine(
            &traced[i],
            k,
            &targets[i],
            [q.last().map(Vec::as_slice), next],
            &|q, j| value(i, q, j),
        );
        let state = refined.unwrap_or_else(|| traced[i].states[k].clone());
        q.push(state.q);
        values.push(state.value);
    }
    let total = values.iter().sum();
    Some(SelfMotionPath {
        total,
        q,
        values,
        worst_total: chosen.worst_total,
        best_total: total,
    })
}

/// An orthonormal basis of the joint velocities that leave the kept rows of the tip's twist
/// unchanged — the directions of the self-motion at a configuration — from its geometric
/// Jacobian (6 × dof, rows `[v; ω]`): one column per direction (dof × k, rad/s or m/s per
/// unit). A direction counts when its singular value is at most `relative_tolerance` times
/// the largest. Each column's largest-magnitude entry is positive, so the basis is the same
/// for the same Jacobian; with several directions, the most exactly null comes first.
/// Empty (dof × 0) for a non-finite Jacobian.
pub fn null_space(
    jacobian: &Matrix6xX<f64>,
    rows: KeptRows,
    relative_tolerance: f64,
) -> DMatrix<f64> {
    let dof = jacobian.ncols();
    let kept = match rows {
        KeptRows::Pose => 6,
        KeptRows::Position => 3,
    };
    let a = jacobian.rows(0, kept);
    if !a.iter().all(|v| v.is_finite()) {
        return DMatrix::zeros(dof, 0);
    }
    // The right singular vectors of A padded with zero rows to a square matrix: a thin SVD of
    // the wide A alone would leave its null space out.
    let size = dof.max(kept);
    let padded = DMatrix::from_fn(size, dof, |r, c| if r < kept { a[(r, c)] } else { 0.0 });
    let Some(svd) = padded.try_svd(false, true, f64::EPSILON, 10_000) else {
        return DMatrix::zeros(dof, 0);
    };
    let Some(v_t) = svd.v_t else {
        return DMatrix::zeros(dof, 0);
    };
    let largest = svd.singular_values.iter().copied().fold(0.0, f64::max);
    let threshold = largest * relative_tolerance;
    let mut columns: Vec<(f64, DVector<f64>)> = svd
        .singular_values
        .iter()
        .enumerate()
        .filter(|(_, sigma)| **sigma <= threshold)
        .map(|(k, sigma)| {
            let mut v: DVector<f64> = v_t.row(k).transpose();
            let peak = v
                .iter()
                .copied()
                .fold(0.0, |m: f64, x| if x.abs() > m.abs() { x } else { m });
            if peak < 0.0 {
                v.neg_mut();
            }
            (*sigma, v)
        })
        .collect();
    columns.sort_by(|x, y| x.0.total_cmp(&y.0));
    let vectors: Vec<DVector<f64>> = columns.into_iter().map(|(_, v)| v).collect();
    if vectors.is_empty() {
        DMatrix::zeros(dof, 0)
    } else {
        DMatrix::from_columns(&vectors)
    }
}

/// One state of the programme: a configuration on target and its value.
#[derive(Debug, Clone)]
struct State {
    q: Vec<f64>,
    value: f64,
}

/// The states of one sample: the first `curve` in order along the traced self-motion (each
/// `spacing` from the next, but for an end where the curve leaves the limits within a step),
/// then the given paths' configurations.
struct Traced {
    states: Vec<State>,
    curve: usize,
    /// The state traced from (the given configuration) among the first `curve`.
    middle: usize,
    /// The direction the curve was traced in first (joint space; zero when nothing was
    /// traced): the next sample's curve is oriented the same way.
    heading: DVector<f64>,
}

/// The dynamic programme's answer: the chosen state per sample and the smallest and largest
/// sums any chain of states reaches.
struct Chosen {
    states: Vec<usize>,
    worst_total: f64,
    best_total: f64,
}

/// The best chain of states under the joint-step bound, by dynamic programming.
fn best_chain(traced: &[Traced], max_joint_step: f64) -> Option<Chosen> {
    // best[i][k]: the largest (and smallest) sum over chains ending in state k of sample i,
    // and the state of sample i − 1 it follows.
    let mut best: Vec<Vec<(f64, f64, usize)>> = Vec::with_capacity(traced.len());
    for (i, at) in traced.iter().enumerate() {
        let row = at
            .states
            .iter()
            .map(|s| {
                if i == 0 {
                    return (s.value, s.value, 0);
                }
                let mut found = (f64::NEG_INFINITY, f64::INFINITY, 0);
                for (k, (before, previous)) in
                    traced[i - 1].states.iter().zip(&best[i - 1]).enumerate()
                {
                    if previous.0 == f64::NEG_INFINITY
                        || max_difference(&before.q, &s.q) > max_joint_step
                    {
                        continue;
                    }
                    if previous.0 > found.0 {
                        found.0 = previous.0;
                        found.2 = k;
                    }
                    found.1 = found.1.min(previous.1);
                }
                (found.0 + s.value, found.1 + s.value, found.2)
            })
            .collect();
        best.push(row);
    }
    let last = best.last()?;
    let (mut k, best_total) = last
        .iter()
        .enumerate()
        .filter(|(_, b)| b.0.is_finite())
        .fold(None, |acc: Option<(usize, f64)>, (k, b)| match acc {
            Some((_, v)) if v >= b.0 => acc,
            _ => Some((k, b.0)),
        })?;
    let worst_total = last
        .iter()
        .filter(|b| b.1.is_finite())
        .map(|b| b.1)
        .fold(f64::INFINITY, f64::min);
    let mut states = vec![0; traced.len()];
    for i in (0..traced.len()).rev() {
        states[i] = k;
        k = best[i][k].2;
    }
    Some(Chosen {
        states,
        worst_total,
        best_total,
    })
}

/// The target poses with rotation matrices, as the tracer compares them with the chain's.
fn rotation_matrix_poses(poses: &[Isometry3<f64>]) -> Vec<IsometryMatrix3<f64>> {
    poses.iter().map(|t| nalgebra::convert(*t)).collect()
}

/// The joint-space (Euclidean) distance between two configurations (rad / m).
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}
