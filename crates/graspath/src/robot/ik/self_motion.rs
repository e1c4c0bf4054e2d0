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
//! among the states, so the result is never worse than the best of them. A second, finer pass
//! (`spacing / REFINE`, half as far) around the chosen path refines the optimum.
//!
//! With one redundant degree of freedom (a 7-joint arm keeping a pose, a planar 3R arm keeping
//! a position) the traced curve is the self-motion manifold near the given paths; with more,
//! it is one curve through it, and the optimum is over that curve.

use crate::robot::chain::Chain;
use nalgebra::{
    Cholesky, DVector, Isometry3, IsometryMatrix3, Matrix6, Matrix6xX, Vector3, Vector6, U6,
};

/// How much finer the second pass is than the first.
pub const REFINE: f64 = 8.0;

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
    /// 0.1 rad spacing, 8 steps each side (±0.8 rad), 0.5 rad joint steps, 1e-5 m / rad.
    fn default() -> Self {
        Self {
            spacing: 0.1,
            reach: 8,
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
    let targets: Vec<IsometryMatrix3<f64>> = base_from_targets
        .iter()
        .map(|t| nalgebra::convert(*t))
        .collect();
    let coarse = best_chain(chain, &targets, &paths, rows, value, options)?;
    let fine_options = SelfMotionOptions {
        spacing: options.spacing / REFINE,
        reach: REFINE as usize / 2,
        ..*options
    };
    let fine = best_chain(chain, &targets, &[&coarse.q], rows, value, &fine_options)?;
    Some(if fine.total >= coarse.total {
        SelfMotionPath {
            worst_total: coarse.worst_total.min(fine.worst_total),
            ..fine
        }
    } else {
        coarse
    })
}

/// One state of the programme: a configuration on target and its value.
#[derive(Debug, Clone)]
struct State {
    q: Vec<f64>,
    value: f64,
}

/// The dynamic programme over the states traced around `paths`.
fn best_chain(
    chain: &Chain,
    targets: &[IsometryMatrix3<f64>],
    paths: &[&[Vec<f64>]],
    rows: KeptRows,
    value: &SampleValue<'_>,
    options: &SelfMotionOptions,
) -> Option<SelfMotionPath> {
    let mut tracer = Tracer::new(chain, rows, options);
    let states: Vec<Vec<State>> = targets
        .iter()
        .enumerate()
        .map(|(i, target)| {
            let mut at = tracer.trace(&paths[0][i], target, &|q, j| value(i, q, j));
            // The other paths join as they are.
            for path in &paths[1..] {
                if tracer.jacobian_at(&path[i]) {
                    let v = value(i, &path[i], &tracer.jacobian);
                    at.push(State {
                        q: path[i].clone(),
                        value: v,
                    });
                }
            }
            at
        })
        .collect();
    // best[i][k]: the largest (and smallest) sum over chains ending in state k of sample i,
    // and the state of sample i − 1 it follows.
    let mut best: Vec<Vec<(f64, f64, usize)>> = Vec::with_capacity(states.len());
    for (i, at) in states.iter().enumerate() {
        let row = at
            .iter()
            .map(|s| {
                if i == 0 {
                    return (s.value, s.value, 0);
                }
                let mut found = (f64::NEG_INFINITY, f64::INFINITY, 0);
                for (k, (before, previous)) in states[i - 1].iter().zip(&best[i - 1]).enumerate() {
                    if previous.0 == f64::NEG_INFINITY
                        || max_difference(&before.q, &s.q) > options.max_joint_step
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
    let (mut k, end) = last
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
    let mut q = vec![Vec::new(); states.len()];
    let mut values = vec![0.0; states.len()];
    for i in (0..states.len()).rev() {
        q[i] = states[i][k].q.clone();
        values[i] = states[i][k].value;
        k = best[i][k].2;
    }
    Some(SelfMotionPath {
        q,
        values,
        total: end,
        worst_total,
    })
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Traces the self-motion through a configuration.
struct Tracer<'c> {
    chain: &'c Chain,
    rows: KeptRows,
    options: &'c SelfMotionOptions,
    jacobian: Matrix6xX<f64>,
}

/// Gauss–Newton corrections allowed per traced configuration.
const CORRECTIONS: usize = 8;

/// Damping of the normal equations (m², rad²): keeps rows the arm cannot move (a planar
/// arm's `z`) out of the solve without changing the others.
const DAMPING: f64 = 1e-12;

/// The kept rows of the Jacobian at one configuration and the solve through them.
#[derive(Clone)]
struct Kept {
    /// The Jacobian with the rows that are not kept set to zero.
    a: Matrix6xX<f64>,
    /// `A Aᵀ + DAMPING · I`, factored.
    normal: Cholesky<f64, U6>,
    /// The tip's error towards the target on the kept rows (`[v; ω]`, base frame).
    error: Vector6<f64>,
}

impl Kept {
    /// `Aᵀ (A Aᵀ)⁻¹ r`: the smallest joint change that moves the kept rows by `r`.
    fn lift(&self, r: &Vector6<f64>) -> DVector<f64> {
        self.a.transpose() * self.normal.solve(r)
    }

    /// The part of `h` in the null space of the kept rows.
    fn project(&self, h: &DVector<f64>) -> DVector<f64> {
        h - self.lift(&(&self.a * h))
    }
}

impl<'c> Tracer<'c> {
    fn new(chain: &'c Chain, rows: KeptRows, options: &'c SelfMotionOptions) -> Self {
        Self {
            chain,
            rows,
            options,
            jacobian: Matrix6xX::zeros(chain.dof()),
        }
    }

    /// The Jacobian at `q` into `self.jacobian`; false when the chain refuses `q`.
    fn jacobian_at(&mut self, q: &[f64]) -> bool {
        self.chain
            .pose_and_jacobian_into(q, &mut self.jacobian)
            .is_ok()
    }

    /// The kept rows at `q`, towards `target`.
    fn kept(&mut self, q: &[f64], target: &IsometryMatrix3<f64>) -> Option<Kept> {
        let pose = self
            .chain
            .pose_and_jacobian_into(q, &mut self.jacobian)
            .ok()?;
        let dp: Vector3<f64> = target.translation.vector - pose.translation.vector;
        let dr = (target.rotation * pose.rotation.inverse()).scaled_axis();
        let mut error = Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z);
        let mut a = self.jacobian.clone();
        if self.rows == KeptRows::Position {
            a.fixed_rows_mut::<3>(3).fill(0.0);
            error.fixed_rows_mut::<3>(3).fill(0.0);
        }
        let normal = (&a * a.transpose() + Matrix6::identity() * DAMPING).cholesky()?;
        Some(Kept { a, normal, error })
    }

    fn on_target(&self, e: &Vector6<f64>) -> bool {
        e.fixed_rows::<3>(0).norm() <= self.options.position_tolerance
            && e.fixed_rows::<3>(3).norm() <= self.options.rotation_tolerance
    }

    fn inside(&self, q: &[f64]) -> bool {
        let (lower, upper) = (self.chain.lower(), self.chain.upper());
        q.iter()
            .enumerate()
            .all(|(j, v)| v.is_finite() && *v >= lower[j] && *v <= upper[j])
    }

    /// `q` itself and up to `reach` configurations on each side of it along the self-motion
    /// (nearest first on each side), each on target and inside the limits, with their
    /// `value` (of the configuration and the full Jacobian there).
    fn trace(
        &mut self,
        q: &[f64],
        target: &IsometryMatrix3<f64>,
        value: &dyn Fn(&[f64], &Matrix6xX<f64>) -> f64,
    ) -> Vec<State> {
        let Some(start) = self.kept(q, target) else {
            return Vec::new();
        };
        let mut out = vec![State {
            q: q.to_vec(),
            value: value(q, &self.jacobian),
        }];
        let dof = self.chain.dof();
        for side in [1.0, -1.0] {
            let mut current = q.to_vec();
            let mut heading: Option<DVector<f64>> = None;
            // The solve at `current`, reused for the next step's direction.
            let mut at_current: Option<Kept> = None;
            for _ in 0..self.options.reach {
                let kept = match at_current.take() {
                    Some(k) => k,
                    None => start.clone(),
                };
                // Continue the previous heading; at the start, the projected joint axis of
                // largest norm, turned by `side`.
                let direction = match &heading {
                    Some(h) => kept.project(h),
                    None => (0..dof)
                        .map(|j| kept.project(&DVector::from_fn(dof, |r, _| f64::from(r == j))))
                        .max_by(|x, y| x.norm().total_cmp(&y.norm()))
                        .map_or_else(|| DVector::zeros(dof), |d| d * side),
                };
                let norm = direction.norm();
                if norm < 1e-9 {
                    break;
                }
                let step = direction / norm;
                let mut next: Vec<f64> = current
                    .iter()
                    .zip(step.iter())
                    .map(|(v, d)| v + self.options.spacing * d)
                    .collect();
                let mut converged = None;
                for _ in 0..CORRECTIONS {
                    let Some(kept) = self.kept(&next, target) else {
                        break;
                    };
                    if self.on_target(&kept.error) {
                        converged = Some(kept);
                        break;
                    }
                    let correction = kept.lift(&kept.error);
                    for (v, d) in next.iter_mut().zip(correction.iter()) {
                        *v += d;
                    }
                }
                let Some(kept) = converged.filter(|_| self.inside(&next)) else {
                    break;
                };
                // `self.jacobian` is the full Jacobian at `next` (the last solve).
                out.push(State {
                    value: value(&next, &self.jacobian),
                    q: next.clone(),
                });
                at_current = Some(kept);
                heading = Some(step);
                current = next;
            }
        }
        out
    }
}
