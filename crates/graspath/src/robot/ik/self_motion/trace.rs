//! Tracing the self-motion through a configuration: steps along the null space of the kept
//! rows of the Jacobian, each corrected back onto the target by Gauss–Newton steps, shorter
//! where the curve bends, ending exactly where the curve leaves the joint limits.

use super::{distance, max_difference, KeptRows, SampleValue, SelfMotionOptions, State, Traced};
use crate::robot::chain::Chain;
use nalgebra::{
    Cholesky, DVector, IsometryMatrix3, Matrix6, Matrix6xX, Rotation3, Vector3, Vector6, U6,
};

/// The vertex of the parabola through `(−before, v_before)`, `(0, v)`, `(after, v_after)`
/// when it is a maximum strictly between the outer points.
fn parabola_peak(before: (f64, f64), v: f64, after: (f64, f64)) -> Option<f64> {
    let (d0, v0) = before;
    let (d1, v1) = after;
    let (s0, s1) = ((v0 - v) / d0, (v1 - v) / d1);
    let curvature = (s0 + s1) / (d0 + d1);
    let slope = s1 - curvature * d1;
    let peak = -slope / (2.0 * curvature);
    (curvature < 0.0 && peak > -d0 && peak < d1).then_some(peak)
}

/// The rotation vector (axis × angle, rad) of `r`, accurate to rounding at small angles: up
/// to 120° the angle comes from `atan2(sin, cos)` of the skew-symmetric part and the trace
/// (an angle from the trace alone, as `acos`, loses half the digits near 0 and stalls
/// corrections at ~1e-8 rad); beyond, where the skew part fades, from nalgebra.
fn rotation_vector(r: &Rotation3<f64>) -> Vector3<f64> {
    let m = r.matrix();
    let skew = 0.5
        * Vector3::new(
            m[(2, 1)] - m[(1, 2)],
            m[(0, 2)] - m[(2, 0)],
            m[(1, 0)] - m[(0, 1)],
        );
    let sine = skew.norm();
    let cosine = 0.5 * (m.trace() - 1.0);
    let angle = sine.atan2(cosine);
    if cosine > -0.5 {
        // Near 0, angle / sine → 1 (the ratio is 1 + angle² / 6 + …).
        let ratio = if sine > 0.0 { angle / sine } else { 1.0 };
        skew * ratio
    } else {
        r.scaled_axis()
    }
}

/// Traces the self-motion through a configuration.
pub(super) struct Tracer<'c> {
    pub(super) chain: &'c Chain,
    pub(super) rows: KeptRows,
    pub(super) options: &'c SelfMotionOptions,
    pub(super) jacobian: Matrix6xX<f64>,
}

/// Traced steps on each side of a configuration, at most (`reach` steps of `spacing`, and
/// the shorter ones where the curve bends).
const MAX_TRACED_STEPS: usize = 64;

/// How far (a fraction of the step) the corrections may pull a traced step off its
/// predicted end before the step is halved.
const BEND: f64 = 0.15;

/// The shortest traced step, as a fraction of the spacing.
const FINEST_STEP: f64 = 8.0;

/// Bisections of the last step where a traced curve stops converging (a 32nd of the step).
const BOUNDARY_BISECTIONS: usize = 5;

/// Regula falsi steps, at most, to the point where a traced curve crosses a limit.
const CROSSING_ITERATIONS: usize = 40;

/// How far [`Tracer::correct`] goes.
#[derive(Debug, Clone, Copy)]
pub(super) enum Convergence {
    /// To the position and rotation tolerances.
    Tolerance,
    /// To [`SETTLED`] (or the tolerances after the last correction).
    Settled,
}

/// The error (m and rad together) below which a settled configuration is taken without
/// another correction.
const SETTLED: f64 = 1e-11;

/// Gauss–Newton corrections allowed per traced configuration.
const CORRECTIONS: usize = 8;

/// Damping of the normal equations (m², rad²): keeps rows the arm cannot move (a planar
/// arm's `z`) out of the solve without changing the others.
const DAMPING: f64 = 1e-12;

/// The kept rows of the Jacobian at one configuration and the solve through them.
#[derive(Clone)]
pub(super) struct Kept {
    /// The Jacobian with the rows that are not kept set to zero.
    a: Matrix6xX<f64>,
    /// `A Aᵀ + DAMPING · I`, factored.
    normal: Cholesky<f64, U6>,
    /// The tip's error towards the target on the kept rows (`[v; ω]`, base frame).
    pub(super) error: Vector6<f64>,
}

impl Kept {
    /// The kept rows `a` (the others zero) and the error on them, factored; `None` when
    /// `A Aᵀ + DAMPING · I` is not positive definite (a non-finite Jacobian). Written column
    /// by column: the matrices are 6 × dof, too small for a general product to pay off.
    pub(super) fn new(a: Matrix6xX<f64>, error: Vector6<f64>) -> Option<Self> {
        let mut normal = Matrix6::identity() * DAMPING;
        for column in a.column_iter() {
            let c: Vector6<f64> = column.into_owned();
            normal += c * c.transpose();
        }
        let normal = normal.cholesky()?;
        Some(Self { a, normal, error })
    }

    /// `Aᵀ (A Aᵀ)⁻¹ r`: the smallest joint change that moves the kept rows by `r`.
    pub(super) fn lift(&self, r: &Vector6<f64>) -> DVector<f64> {
        let y = self.normal.solve(r);
        DVector::from_iterator(self.a.ncols(), self.a.column_iter().map(|c| c.dot(&y)))
    }

    /// The part of `h` in the null space of the kept rows.
    pub(super) fn project(&self, h: &DVector<f64>) -> DVector<f64> {
        let mut moved = Vector6::zeros();
        for (column, v) in self.a.column_iter().zip(h.iter()) {
            moved += column * *v;
        }
        h - self.lift(&moved)
    }
}

impl<'c> Tracer<'c> {
    pub(super) fn new(chain: &'c Chain, rows: KeptRows, options: &'c SelfMotionOptions) -> Self {
        Self {
            chain,
            rows,
            options,
            jacobian: Matrix6xX::zeros(chain.dof()),
        }
    }

    /// The Jacobian at `q` into `self.jacobian`; false when the chain refuses `q`.
    pub(super) fn jacobian_at(&mut self, q: &[f64]) -> bool {
        self.chain
            .pose_and_jacobian_into(q, &mut self.jacobian)
            .is_ok()
    }

    /// The kept rows at `q`, towards `target`.
    pub(super) fn kept(&mut self, q: &[f64], target: &IsometryMatrix3<f64>) -> Option<Kept> {
        let pose = self
            .chain
            .pose_and_jacobian_into(q, &mut self.jacobian)
            .ok()?;
        let dp: Vector3<f64> = target.translation.vector - pose.translation.vector;
        let dr = rotation_vector(&(target.rotation * pose.rotation.inverse()));
        let mut error = Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z);
        let mut a = self.jacobian.clone();
        if self.rows == KeptRows::Position {
            a.fixed_rows_mut::<3>(3).fill(0.0);
            error.fixed_rows_mut::<3>(3).fill(0.0);
        }
        Kept::new(a, error)
    }

    pub(super) fn on_target(&self, e: &Vector6<f64>) -> bool {
        e.fixed_rows::<3>(0).norm() <= self.options.position_tolerance
            && e.fixed_rows::<3>(3).norm() <= self.options.rotation_tolerance
    }

    pub(super) fn inside(&self, q: &[f64]) -> bool {
        let (lower, upper) = (self.chain.lower(), self.chain.upper());
        q.iter()
            .enumerate()
            .all(|(j, v)| v.is_finite() && *v >= lower[j] && *v <= upper[j])
    }

    /// The self-motion traced at every target around `path` (one configuration per target),
    /// each curve oriented like the one before it.
    pub(super) fn trace_along(
        &mut self,
        targets: &[IsometryMatrix3<f64>],
        path: &[Vec<f64>],
        value: &SampleValue<'_>,
    ) -> Vec<Traced> {
        let mut traced: Vec<Traced> = Vec::with_capacity(targets.len());
        for (i, (target, q)) in targets.iter().zip(path).enumerate() {
            let previous = traced.last().map(|t| &t.heading);
            let at = self.trace(q, target, &|q, j| value(i, q, j), previous);
            traced.push(at);
        }
        traced
    }

    /// `q` itself and up to `reach` configurations on each side of it along the self-motion,
    /// each on target and inside the limits, with their `value` (of the configuration and
    /// the full Jacobian there), in order along the curve. The curve runs the way that
    /// `previous` (the previous sample's first heading) points, when it is given.
    pub(super) fn trace(
        &mut self,
        q: &[f64],
        target: &IsometryMatrix3<f64>,
        value: &dyn Fn(&[f64], &Matrix6xX<f64>) -> f64,
        previous: Option<&DVector<f64>>,
    ) -> Traced {
        let dof = self.chain.dof();
        let Some(start) = self.kept(q, target) else {
            return Traced {
                states: Vec::new(),
                curve: 0,
                middle: 0,
                heading: DVector::zeros(dof),
            };
        };
        let middle = State {
            q: q.to_vec(),
            value: value(q, &self.jacobian),
        };
        // The projected joint axis of largest norm: the first step's direction, both ways.
        let mut initial = (0..dof)
            .map(|j| start.project(&DVector::from_fn(dof, |r, _| f64::from(r == j))))
            .max_by(|x, y| x.norm().total_cmp(&y.norm()))
            .unwrap_or_else(|| DVector::zeros(dof));
        if previous.is_some_and(|p| p.dot(&initial) < 0.0) {
            initial.neg_mut();
        }
        let mut sides = [Vec::new(), Vec::new()];
        for (side, out) in [1.0, -1.0].into_iter().zip(&mut sides) {
            let mut current = q.to_vec();
            let mut kept = start.clone();
            let mut heading = &initial * side;
            let reach = self.options.spacing * self.options.reach as f64;
            let (mut travelled, mut length) = (0.0, self.options.spacing);
            for _ in 0..MAX_TRACED_STEPS {
                if travelled >= reach * (1.0 - 1e-9) {
                    break;
                }
                let step = length.min(reach - travelled);
                // Continue the previous heading in the null space at `current`.
                let direction = kept.project(&heading);
                let Some((next, at_next)) = self.advance(&current, &direction, step, target) else {
                    // The curve ends inside this step (a joint limit): its last point, so
                    // that where the traced part ends does not depend on the spacing.
                    if let Some(end) = self.last_inside(&current, &direction, step, target, value) {
                        out.push(end);
                    }
                    break;
                };
                // Where the curve bends within the step, the corrections pull the step off
                // its length: shorter steps there keep the traced points' spacing, and so
                // their arc length, true.
                let norm = direction.norm();
                let pulled = next
                    .iter()
                    .zip(&current)
                    .zip(direction.iter())
                    .map(|((n, c), d)| (n - (c + step / norm * d)).powi(2))
                    .sum::<f64>()
                    .sqrt();
                if pulled > BEND * step && step > self.options.spacing / FINEST_STEP {
                    length = 0.5 * step;
                    continue;
                }
                // `self.jacobian` is the full Jacobian at `next` (the last solve).
                travelled += distance(&current, &next);
                out.push(State {
                    value: value(&next, &self.jacobian),
                    q: next.clone(),
                });
                heading = direction;
                kept = at_next;
                current = next;
                length = (2.0 * step).min(self.options.spacing);
            }
        }
        let [forward, backward] = sides;
        let middle_index = backward.len();
        let mut states: Vec<State> = backward.into_iter().rev().collect();
        states.push(middle);
        states.extend(forward);
        let curve = states.len();
        Traced {
            states,
            curve,
            middle: middle_index,
            heading: initial,
        }
    }

    /// The farthest configuration along `direction` from `from` (joint space) within
    /// `spacing` that stays inside the limits, with its value; `None` when none is reached.
    /// Where the curve crosses a limit, the crossing is found by regula falsi on the largest
    /// limit excess (to 1e-12 of the step), so the traced part of the curve ends where the
    /// curve does, not on the spacing's grid; where the corrections stop converging, by
    /// bisection to a 32nd of the spacing.
    pub(super) fn last_inside(
        &mut self,
        from: &[f64],
        direction: &DVector<f64>,
        spacing: f64,
        target: &IsometryMatrix3<f64>,
        value: &dyn Fn(&[f64], &Matrix6xX<f64>) -> f64,
    ) -> Option<State> {
        let mut last = None;
        let Some((far, _)) = self.advance_on_target(from, direction, spacing, target) else {
            let (mut reached, mut missed) = (0.0, spacing);
            for _ in 0..BOUNDARY_BISECTIONS {
                let length = 0.5 * (reached + missed);
                match self.advance(from, direction, length, target) {
                    Some((q, _)) => {
                        reached = length;
                        last = Some(self.state(q, value));
                    }
                    None => missed = length,
                }
            }
            return last;
        };
        // Illinois regula falsi on the excess between `inside` (≤ 0) and `outside` (> 0).
        let (mut inside, mut outside) = ((0.0, self.excess(from)), (spacing, self.excess(&far)));
        if inside.1 >= 0.0 || outside.1 <= 0.0 {
            return None;
        }
        let mut kept_side = 0_i8;
        for _ in 0..CROSSING_ITERATIONS {
            if outside.0 - inside.0 <= 1e-12 * spacing {
                break;
            }
            let length = outside.0 - outside.1 * (outside.0 - inside.0) / (outside.1 - inside.1);
            let Some((q, _)) = self.advance_on_target(from, direction, length, target) else {
                break;
            };
            let excess = self.excess(&q);
            if excess <= 0.0 {
                if self.inside(&q) {
                    last = Some(self.state(q, value));
                }
                inside = (length, excess);
                if kept_side == -1 {
                    outside.1 *= 0.5;
                }
                kept_side = -1;
            } else {
                outside = (length, excess);
                if kept_side == 1 {
                    inside.1 *= 0.5;
                }
                kept_side = 1;
            }
        }
        last
    }

    /// The state at `q` (`self.jacobian` is the Jacobian there).
    pub(super) fn state(
        &self,
        q: Vec<f64>,
        value: &dyn Fn(&[f64], &Matrix6xX<f64>) -> f64,
    ) -> State {
        State {
            value: value(&q, &self.jacobian),
            q,
        }
    }

    /// How far `q` is beyond its nearest limit (rad / m; negative inside).
    pub(super) fn excess(&self, q: &[f64]) -> f64 {
        let (lower, upper) = (self.chain.lower(), self.chain.upper());
        q.iter()
            .enumerate()
            .map(|(j, v)| (lower[j] - v).max(v - upper[j]))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The configuration `length` from `from` along `direction` (joint space), corrected back
    /// onto `target` by Gauss–Newton steps; `None` when it does not converge or leaves the
    /// limits. `self.jacobian` is then the full Jacobian there.
    pub(super) fn advance(
        &mut self,
        from: &[f64],
        direction: &DVector<f64>,
        length: f64,
        target: &IsometryMatrix3<f64>,
    ) -> Option<(Vec<f64>, Kept)> {
        self.advance_on_target(from, direction, length, target)
            .filter(|(q, _)| self.inside(q))
    }

    /// [`Tracer::advance`] without the limits.
    pub(super) fn advance_on_target(
        &mut self,
        from: &[f64],
        direction: &DVector<f64>,
        length: f64,
        target: &IsometryMatrix3<f64>,
    ) -> Option<(Vec<f64>, Kept)> {
        let norm = direction.norm();
        if norm < 1e-9 {
            return None;
        }
        let scale = length / norm;
        let next: Vec<f64> = from
            .iter()
            .zip(direction.iter())
            .map(|(v, d)| v + scale * d)
            .collect();
        self.correct(next, target, Convergence::Tolerance)
    }

    /// `q` moved onto `target` by Gauss–Newton steps (each the smallest joint change that
    /// removes the kept rows' error), the limits aside; `None` when it does not converge.
    /// `self.jacobian` is then the full Jacobian there. [`Convergence::Tolerance`] stops at
    /// the tolerances (the traced states: where they lie on the curve only names it);
    /// [`Convergence::Settled`] goes on far below them (configurations of a motion, which
    /// neighbouring samples must not differ by the tolerances' noise: a spline through a
    /// densely sampled path would turn it into large accelerations).
    pub(super) fn correct(
        &mut self,
        mut q: Vec<f64>,
        target: &IsometryMatrix3<f64>,
        convergence: Convergence,
    ) -> Option<(Vec<f64>, Kept)> {
        for correction in 0..CORRECTIONS {
            let kept = self.kept(&q, target)?;
            let done = match convergence {
                Convergence::Tolerance => self.on_target(&kept.error),
                Convergence::Settled => {
                    kept.error.norm() <= SETTLED
                        || (correction + 1 == CORRECTIONS && self.on_target(&kept.error))
                }
            };
            if done {
                return Some((q, kept));
            }
            let step = kept.lift(&kept.error);
            for (v, d) in q.iter_mut().zip(step.iter()) {
                *v += d;
            }
        }
        None
    }

    /// State `k` of `traced` moved to the peak of the parabola through it and its two
    /// neighbours on the curve, when that is better and still joins `[before, after]`
    /// (the chosen configurations of the neighbouring samples) within the step bound.
    pub(super) fn refine(
        &mut self,
        traced: &Traced,
        k: usize,
        target: &IsometryMatrix3<f64>,
        [before, after]: [Option<&[f64]>; 2],
        value: &dyn Fn(&[f64], &Matrix6xX<f64>) -> f64,
    ) -> Option<State> {
        if k == 0 || k + 1 >= traced.curve {
            return None;
        }
        let [previous, here, next] = [
            &traced.states[k - 1],
            &traced.states[k],
            &traced.states[k + 1],
        ];
        let distance = |a: &State| {
            a.q.iter()
                .zip(&here.q)
                .map(|(x, y)| (x - y).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        let peak = parabola_peak(
            (distance(previous), previous.value),
            here.value,
            (distance(next), next.value),
        )?;
        let towards = if peak > 0.0 { next } else { previous };
        let kept = self.kept(&here.q, target)?;
        let chord = DVector::from_iterator(
            here.q.len(),
            towards.q.iter().zip(&here.q).map(|(a, b)| a - b),
        );
        let (q, _) = self.advance(&here.q, &kept.project(&chord), peak.abs(), target)?;
        let state = State {
            value: value(&q, &self.jacobian),
            q,
        };
        let joins = |other: Option<&[f64]>| {
            other.is_none_or(|o| max_difference(o, &state.q) <= self.options.max_joint_step)
        };
        (state.value > here.value && joins(before) && joins(after)).then_some(state)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rotation vector inverts `Rotation3::from_scaled_axis` to rounding from 1e-12 rad
    /// (where the trace's `acos` alone loses half the digits) to just below π.
    #[test]
    fn the_rotation_vector_is_exact_at_small_and_large_angles() {
        let axis = Vector3::new(0.3, -0.5, 0.8).normalize();
        for angle in [
            1e-12,
            1e-9,
            1e-6,
            1e-3,
            0.5,
            2.0,
            3.0,
            std::f64::consts::PI - 1e-6,
        ] {
            let v = axis * angle;
            let back = rotation_vector(&Rotation3::from_scaled_axis(v));
            // Up to 120°, to rounding; beyond, nalgebra's own accuracy near π.
            let tolerance = if angle < 2.0 {
                1e-15 + 1e-12 * angle
            } else {
                1e-6
            };
            assert!((back - v).norm() <= tolerance, "{angle}: {back:?}");
        }
        assert_eq!(rotation_vector(&Rotation3::identity()), Vector3::zeros());
    }
}
