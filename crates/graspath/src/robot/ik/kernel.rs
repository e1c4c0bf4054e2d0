//! The numerical core shared by single-pose and trajectory IK: the pose error, one damped
//! least-squares step with joint-limit handling, and a Levenberg–Marquardt run. Nothing here
//! allocates; every buffer is a fixed-size array on the stack.
//!
//! Frames and units: the target, the tip pose, the error and the Jacobian are all in the
//! chain base frame; the error is `[p_target − p; log(R_target·Rᵀ)]` (m, rad).
//!
//! One file on purpose (about 650 lines, a quarter tests): the hot solver loop and its
//! fixed-size workspace are written together so that nothing allocates.

// Dense 6 × 6 linear algebra reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

use super::simd::Real;
use crate::geometry::so3_log;
use crate::robot::chain::{Chain, MAX_JOINTS};
use nalgebra::{Isometry3, Matrix3, Rotation3, Vector3, Vector6};
use rand::{Rng, RngExt};
use std::time::Instant;

/// A target pose, stored as the matrices the error needs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Target {
    /// Target tip position in the base frame (m).
    pub position: Vector3<f64>,
    /// Target tip orientation in the base frame.
    pub rotation: Matrix3<f64>,
}

impl Target {
    pub(crate) fn new(base_from_target: &Isometry3<f64>) -> Self {
        Self {
            position: base_from_target.translation.vector,
            rotation: base_from_target.rotation.to_rotation_matrix().into_inner(),
        }
    }
}

/// One evaluated configuration: tip pose, Jacobian and error with respect to a target.
#[derive(Debug, Clone)]
pub(crate) struct State {
    pub q: [f64; MAX_JOINTS],
    /// Column-major 6 × n geometric Jacobian, rows `[v; ω]`, base frame.
    pub jacobian: [f64; 6 * MAX_JOINTS],
    pub position: Vector3<f64>,
    pub rotation: Matrix3<f64>,
    /// `[p_target − p; log(R_target·Rᵀ)]`, base frame (m, rad).
    pub error: Vector6<f64>,
    pub position_error: f64,
    pub rotation_error: f64,
    /// `½ (|e_p|² + ρ² |e_r|²)`, the weighted cost the solver decreases (m²).
    pub cost: f64,
}

impl State {
    pub(crate) fn new() -> Self {
        Self {
            q: [0.0; MAX_JOINTS],
            jacobian: [0.0; 6 * MAX_JOINTS],
            position: Vector3::zeros(),
            rotation: Matrix3::identity(),
            error: Vector6::zeros(),
            position_error: f64::INFINITY,
            rotation_error: f64::INFINITY,
            cost: f64::INFINITY,
        }
    }
}

/// Two states: the current iterate and a candidate, swapped by index (no copies).
#[derive(Debug, Clone)]
pub(crate) struct Workspace {
    states: [State; 2],
    current: usize,
}

impl Workspace {
    pub(crate) fn new() -> Self {
        Self {
            states: [State::new(), State::new()],
            current: 0,
        }
    }
    pub(crate) fn cur(&self) -> &State {
        &self.states[self.current]
    }
    pub(crate) fn cur_mut(&mut self) -> &mut State {
        &mut self.states[self.current]
    }
    /// The current state (read) and the candidate (write).
    fn pair(&mut self) -> (&State, &mut State) {
        let (a, b) = self.states.split_at_mut(1);
        if self.current == 0 {
            (&a[0], &mut b[0])
        } else {
            (&b[0], &mut a[0])
        }
    }
    fn accept(&mut self) {
        self.current ^= 1;
    }
}

/// How joint limits enter a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Strategy {
    /// Damped least squares with Sugihara's error-dependent damping; a joint resting on a limit
    /// whose descent direction points outwards is removed from the step (active set), and the
    /// step is clamped to the limits.
    Clamped,
    /// The same damping with Chan & Dubey's weighted least norm: a joint moving towards its
    /// nearer limit is slowed by `1 / (1 + |∂H/∂q|)` of the limit-distance penalty `H`, so it
    /// approaches a limit smoothly instead of sticking to it. Also clamped.
    LimitWeighted,
}

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RunEnd {
    Converged,
    /// No more progress (local minimum, stuck on a limit, or repeated rejections).
    Stalled,
    /// The run's own evaluation cap was reached.
    Exhausted,
    /// The shared budget (iterations or time) is spent.
    OutOfBudget,
}

/// When a run gives up: the cost must fall below `factor` times its value at the start of
/// every window of `window` accepted steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Patience {
    pub window: usize,
    pub factor: f64,
}

impl Patience {
    /// For searches with restarts: give up early on slow progress and restart elsewhere.
    pub(crate) const SEARCH: Self = Self {
        window: 4,
        factor: 0.7,
    };
    /// For warm-started tracking, where giving up is costly.
    pub(crate) const TRACKING: Self = Self {
        window: 12,
        factor: 0.5,
    };
}

/// The shared budget of one solve: evaluations left and an optional deadline.
#[derive(Debug, Clone)]
pub(crate) struct Budget {
    pub evaluations_left: usize,
    pub deadline: Option<Instant>,
    pub evaluations: usize,
    pub timed_out: bool,
}

impl Budget {
    pub(crate) fn new(evaluations: usize, deadline: Option<Instant>) -> Self {
        Self {
            evaluations_left: evaluations,
            deadline,
            evaluations: 0,
            timed_out: false,
        }
    }

    /// Spends one evaluation; `false` when nothing is left.
    #[inline]
    pub(crate) fn spend(&mut self) -> bool {
        if self.evaluations_left == 0 || self.timed_out {
            return false;
        }
        // Reading the clock costs ~20 ns: look every 16 evaluations only.
        if self.evaluations.is_multiple_of(16) {
            if let Some(deadline) = self.deadline {
                if Instant::now() >= deadline {
                    self.timed_out = true;
                    return false;
                }
            }
        }
        self.evaluations_left -= 1;
        self.evaluations += 1;
        true
    }

    /// Charges `evaluations` already spent elsewhere (by an attempt run in a vector lane, see
    /// [`super::lanes`]) as that many calls of [`Budget::spend`] would. Only for budgets
    /// without a deadline, and never more than is left.
    pub(crate) fn charge(&mut self, evaluations: usize) {
        debug_assert!(self.deadline.is_none() && evaluations <= self.evaluations_left);
        self.evaluations_left -= evaluations;
        self.evaluations += evaluations;
    }

    pub(crate) fn exhausted(&self) -> bool {
        self.evaluations_left == 0 || self.timed_out
    }
}

/// Weight of the rotation error against the position error: a length (m). The cost is
/// `½ (|e_p|² + ρ²|e_r|²)`.
const ROTATION_LENGTH: f64 = 0.35;
/// Sugihara's constant damping term λ̄ (m²).
pub(crate) const DAMPING_FLOOR: f64 = 1e-6;

/// The problem: a chain, box limits (possibly infinite), tolerances.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Kernel<'a> {
    pub chain: &'a Chain,
    pub lower: &'a [f64],
    pub upper: &'a [f64],
    pub position_tolerance: f64,
    pub rotation_tolerance: f64,
}

/// `[-∞; MAX_JOINTS]` and `[+∞; MAX_JOINTS]`: limits of an unconstrained solve.
pub(crate) static NO_LOWER: [f64; MAX_JOINTS] = [f64::NEG_INFINITY; MAX_JOINTS];
/// See [`NO_LOWER`].
pub(crate) static NO_UPPER: [f64; MAX_JOINTS] = [f64::INFINITY; MAX_JOINTS];

impl<'a> Kernel<'a> {
    pub(crate) fn new(chain: &'a Chain, position_tolerance: f64, rotation_tolerance: f64) -> Self {
        Self {
            chain,
            lower: chain.lower(),
            upper: chain.upper(),
            position_tolerance,
            rotation_tolerance,
        }
    }

    /// The same problem without joint limits.
    pub(crate) fn unconstrained(&self) -> Self {
        let n = self.chain.dof();
        Self {
            lower: &NO_LOWER[..n],
            upper: &NO_UPPER[..n],
            ..*self
        }
    }

    #[inline]
    pub(crate) fn dof(&self) -> usize {
        self.chain.dof()
    }

    /// Clamps `q` into the limits in place.
    #[inline]
    pub(crate) fn clamp(&self, q: &mut [f64]) {
        for ((v, &lo), &hi) in q.iter_mut().zip(self.lower).zip(self.upper) {
            *v = v.max(lo).min(hi);
        }
    }

    /// Forward kinematics, Jacobian and error of `state.q` against `target`.
    #[inline(always)]
    pub(crate) fn evaluate(&self, target: &Target, state: &mut State) {
        let n = self.dof();
        let pose = self
            .chain
            .pose_and_jacobian_unchecked(&state.q[..n], &mut state.jacobian[..6 * n]);
        state.position = pose.translation.vector;
        state.rotation = *pose.rotation.matrix();
        self.retarget(target, state);
    }

    /// Recomputes the error of an evaluated state against a new target (no kinematics).
    #[inline(always)]
    pub(crate) fn retarget(&self, target: &Target, state: &mut State) {
        let residual = Residual::of(target, &state.position, &state.rotation);
        state.error = residual.error;
        state.position_error = residual.position_error;
        state.rotation_error = residual.rotation_error;
        state.cost = residual.cost;
    }

    #[inline]
    pub(crate) fn converged(&self, state: &State) -> bool {
        self.within_tolerance(state.position_error, state.rotation_error)
    }

    /// Whether a position error (m) and a rotation error (rad) are within tolerance.
    #[inline(always)]
    pub(crate) fn within_tolerance(&self, position_error: f64, rotation_error: f64) -> bool {
        position_error <= self.position_tolerance && rotation_error <= self.rotation_tolerance
    }

    /// One damped least-squares step `dq` (written to `dq[..n]`) from `state` with damping
    /// `lambda` (m²). Returns `false` when the system could not be solved (never for
    /// `lambda > 0` and finite input).
    #[inline(always)]
    pub(crate) fn step(
        &self,
        state: &State,
        lambda: f64,
        strategy: Strategy,
        dq: &mut [f64; MAX_JOINTS],
    ) -> bool {
        let n = self.dof();
        let e = state.error;
        let mut weights = [0.0; MAX_JOINTS];
        damped_step(
            &state.jacobian[..6 * n],
            &[e[0], e[1], e[2], e[3], e[4], e[5]],
            lambda,
            |j, gradient| {
                joint_weight(strategy, state.q[j], self.lower[j], self.upper[j], gradient)
            },
            &mut weights[..n],
            &mut dq[..n],
        )
    }

    /// Levenberg–Marquardt from the workspace's current (evaluated) state towards `target`,
    /// for at most `max_evaluations` kinematics evaluations. The current state is always the
    /// best one found (steps are only accepted when they lower the cost).
    ///
    /// On processors with AVX2 (checked at run time) the loop runs compiled for AVX2: the
    /// same IEEE operations in the same order (Rust never fuses a multiply and an add on its
    /// own), so the results are bit-identical to the baseline build's, in fewer cycles.
    pub(crate) fn run(
        &self,
        target: &Target,
        ws: &mut Workspace,
        strategy: Strategy,
        max_evaluations: usize,
        patience: Patience,
        budget: &mut Budget,
    ) -> RunEnd {
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::has_avx2() {
            // SAFETY: the processor has AVX2, checked just above.
            return unsafe {
                self.run_avx2(target, ws, strategy, max_evaluations, patience, budget)
            };
        }
        self.run_loop(target, ws, strategy, max_evaluations, patience, budget)
    }

    /// [`Kernel::run`]'s loop compiled for AVX2.
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn run_avx2(
        &self,
        target: &Target,
        ws: &mut Workspace,
        strategy: Strategy,
        max_evaluations: usize,
        patience: Patience,
        budget: &mut Budget,
    ) -> RunEnd {
        self.run_loop(target, ws, strategy, max_evaluations, patience, budget)
    }

    /// The body of [`Kernel::run`], inlined into each compiled form.
    #[inline(always)]
    fn run_loop(
        &self,
        target: &Target,
        ws: &mut Workspace,
        strategy: Strategy,
        max_evaluations: usize,
        patience: Patience,
        budget: &mut Budget,
    ) -> RunEnd {
        let n = self.dof();
        let mut dq = [0.0f64; MAX_JOINTS];
        let mut mu = 1.0f64;
        let mut used = 0usize;
        // Progress check: the cost must fall by a factor over every window of accepted steps.
        let mut window_cost = ws.cur().cost;
        let mut window_steps = 0usize;
        loop {
            if self.converged(ws.cur()) {
                return RunEnd::Converged;
            }
            if used >= max_evaluations {
                return RunEnd::Exhausted;
            }
            let lambda = mu * (ws.cur().cost + DAMPING_FLOOR);
            if !self.step(ws.cur(), lambda, strategy, &mut dq) {
                return RunEnd::Stalled;
            }
            if !budget.spend() {
                return RunEnd::OutOfBudget;
            }
            used += 1;
            let (cur, cand) = ws.pair();
            let mut moved = 0.0f64;
            for j in 0..n {
                let v = (cur.q[j] + dq[j]).max(self.lower[j]).min(self.upper[j]);
                moved = moved.max((v - cur.q[j]).abs());
                cand.q[j] = v;
            }
            if moved < 1e-14 {
                // Every joint is pinned: nothing more to gain here.
                return RunEnd::Stalled;
            }
            self.evaluate(target, cand);
            if cand.cost < cur.cost {
                ws.accept();
                mu = (mu * 0.5).max(1.0);
                window_steps += 1;
                if window_steps == patience.window {
                    if ws.cur().cost > patience.factor * window_cost {
                        return RunEnd::Stalled;
                    }
                    window_cost = ws.cur().cost;
                    window_steps = 0;
                }
            } else {
                mu *= 8.0;
                if mu > 1e6 {
                    return RunEnd::Stalled;
                }
            }
        }
    }

    /// Writes a configuration drawn uniformly within the limits (±π for unbounded joints).
    pub(crate) fn random_configuration<R: Rng>(&self, rng: &mut R, q: &mut [f64]) {
        for (j, v) in q.iter_mut().enumerate().take(self.dof()) {
            let (lo, hi) = (self.chain.lower()[j], self.chain.upper()[j]);
            *v = if lo.is_finite() && hi.is_finite() {
                if hi > lo {
                    rng.random_range(lo..=hi)
                } else {
                    lo
                }
            } else {
                let (lo, hi) = (lo.max(-std::f64::consts::PI), hi.min(std::f64::consts::PI));
                rng.random_range(lo..=hi)
            };
        }
    }
}

/// The weight of a joint in the weighted-least-norm step: `1/(1 + |∂H/∂q|)` when the descent
/// direction moves the joint towards its nearer limit, 1 otherwise (Chan & Dubey 1995),
/// with `H = Σ (hi − lo)² / (4 (hi − q)(q − lo))`. 0 on a limit when pushed outwards.
#[inline]
fn limit_weight(q: f64, lo: f64, hi: f64, gradient: f64) -> f64 {
    if !(lo.is_finite() && hi.is_finite()) {
        return 1.0;
    }
    let towards_upper = 2.0 * q - hi - lo > 0.0;
    if (gradient > 0.0) != towards_upper {
        return 1.0;
    }
    let (to_hi, to_lo) = (hi - q, q - lo);
    if to_hi <= 0.0 || to_lo <= 0.0 {
        return 0.0;
    }
    let range = hi - lo;
    let dh = range * range * (2.0 * q - hi - lo).abs() / (4.0 * to_hi * to_hi * to_lo * to_lo);
    1.0 / (1.0 + dh)
}

/// A joint's weight in the step for `strategy`, given the descent direction `gradient` of the
/// cost along the joint: 0 removes it, 1 keeps it whole.
#[inline(always)]
pub(crate) fn joint_weight(strategy: Strategy, q: f64, lo: f64, hi: f64, gradient: f64) -> f64 {
    match strategy {
        Strategy::Clamped => {
            if (q <= lo && gradient < 0.0) || (q >= hi && gradient > 0.0) {
                0.0
            } else {
                1.0
            }
        }
        Strategy::LimitWeighted => limit_weight(q, lo, hi, gradient),
    }
}

/// The damped least-squares step of one run (`T = f64`) or of four runs, one per lane
/// (`T = F4`): `dq = W Jᵀ (J W Jᵀ + λI)⁻¹ e` with the rotation rows weighted by ρ.
///
/// `jacobian` is the column-major 6 × n Jacobian (rows `[v; ω]`, base frame), `error` the
/// pose error `[e_p; e_r]` (m, rad), `lambda` the damping (m²); `weight(j, gradient)` gives
/// joint `j`'s weight from its descent direction. Writes `dq[..n]` (rad / m) and returns, per
/// lane, whether the system was solved. `weights` (as long as `dq`) is scratch space: it
/// receives the joints' weights.
#[inline(always)]
pub(crate) fn damped_step<T: Real>(
    jacobian: &[T],
    error: &[T; 6],
    lambda: T,
    mut weight: impl FnMut(usize, T) -> T,
    weights: &mut [T],
    dq: &mut [T],
) -> T::Mask {
    let rho = T::splat(ROTATION_LENGTH);
    let e = [
        error[0],
        error[1],
        error[2],
        rho * error[3],
        rho * error[4],
        rho * error[5],
    ];
    let weighted = |j: usize| {
        let col = &jacobian[6 * j..6 * j + 6];
        [
            col[0],
            col[1],
            col[2],
            rho * col[3],
            rho * col[4],
            rho * col[5],
        ]
    };
    // A = Σ_j w_j c_j c_jᵀ + λI (lower triangle), c_j the weighted column; a joint of weight 0
    // adds nothing.
    let zero = T::splat(0.0);
    let mut a = [[zero; 6]; 6];
    for (r, row) in a.iter_mut().enumerate() {
        row[r] = lambda;
    }
    for (j, w_j) in weights.iter_mut().enumerate() {
        let c = weighted(j);
        let w = weight(j, dot6(&c, &e));
        *w_j = w;
        let kept = w.is_zero();
        for r in 0..6 {
            let wc = w * c[r];
            for (k, &ck) in c.iter().enumerate().take(r + 1) {
                a[r][k] = T::select(kept, a[r][k], a[r][k] + wc * ck);
            }
        }
    }
    let (y, solved) = cholesky_solve6(&mut a, &e);
    for (j, step) in dq.iter_mut().enumerate() {
        let w = weights[j];
        *step = T::select(w.is_zero(), zero, w * dot6(&weighted(j), &y));
    }
    solved
}

/// `a · b` over six rows, summed in row order.
#[inline(always)]
fn dot6<T: Real>(a: &[T; 6], b: &[T; 6]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4] + a[5] * b[5]
}

/// Solves `A y = b` for a symmetric positive definite 6 × 6 `A` given by its lower triangle
/// (overwritten by its Cholesky factor), for one system or four (one per lane). The mask tells
/// per lane whether `A` was positive definite; where it was not, `y` is meaningless.
#[inline(always)]
pub(crate) fn cholesky_solve6<T: Real>(a: &mut [[T; 6]; 6], b: &[T; 6]) -> ([T; 6], T::Mask) {
    let mut solved = T::splat(1.0).positive_finite();
    for j in 0..6 {
        let mut d = a[j][j];
        for k in 0..j {
            d = d - a[j][k] * a[j][k];
        }
        solved = T::both(solved, d.positive_finite());
        let d = d.sqrt();
        a[j][j] = d;
        let inv = T::splat(1.0) / d;
        for i in j + 1..6 {
            let mut s = a[i][j];
            for k in 0..j {
                s = s - a[i][k] * a[j][k];
            }
            a[i][j] = s * inv;
        }
    }
    let mut y = *b;
    for i in 0..6 {
        let mut s = y[i];
        for k in 0..i {
            s = s - a[i][k] * y[k];
        }
        y[i] = s / a[i][i];
    }
    for i in (0..6).rev() {
        let mut s = y[i];
        for k in i + 1..6 {
            s = s - a[k][i] * y[k];
        }
        y[i] = s / a[i][i];
    }
    (y, solved)
}

/// The error of a tip pose against a target.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Residual {
    /// `[p_target − p; log(R_target·Rᵀ)]`, base frame (m, rad).
    pub error: Vector6<f64>,
    pub position_error: f64,
    pub rotation_error: f64,
    /// `½ (|e_p|² + ρ² |e_r|²)`, the weighted cost the solver decreases (m²).
    pub cost: f64,
}

impl Residual {
    /// The error of the tip at `position` (m) with orientation `rotation`, base frame.
    #[inline(always)]
    pub(crate) fn of(target: &Target, position: &Vector3<f64>, rotation: &Matrix3<f64>) -> Self {
        let dp = target.position - position;
        let dr = rotation_log(&(target.rotation * rotation.transpose()));
        Self {
            error: Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z),
            position_error: dp.norm(),
            rotation_error: dr.norm(),
            cost: 0.5 * (dp.norm_squared() + ROTATION_LENGTH * ROTATION_LENGTH * dr.norm_squared()),
        }
    }
}

/// The rotation vector of a rotation matrix (rad), fast away from a half turn.
#[inline(always)]
pub(crate) fn rotation_log(m: &Matrix3<f64>) -> Vector3<f64> {
    let v = 0.5
        * Vector3::new(
            m[(2, 1)] - m[(1, 2)],
            m[(0, 2)] - m[(2, 0)],
            m[(1, 0)] - m[(0, 1)],
        );
    let cos = 0.5 * (m[(0, 0)] + m[(1, 1)] + m[(2, 2)] - 1.0);
    if cos > -0.9 {
        let sin = v.norm();
        if sin < 1e-12 {
            return v;
        }
        let angle = sin.atan2(cos);
        v * (angle / sin)
    } else {
        so3_log(&Rotation3::from_matrix_unchecked(*m))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix6, UnitQuaternion};

    #[test]
    fn cholesky_matches_nalgebra() {
        let m = Matrix6::from_fn(|i, j| ((i * 7 + j * 3) % 5) as f64 - 2.0 + (i == j) as u8 as f64);
        let spd = m * m.transpose() + Matrix6::identity() * 0.1;
        let b = [1.0, -2.0, 0.5, 3.0, 0.0, -1.0];
        let mut a = [[0.0; 6]; 6];
        for i in 0..6 {
            for j in 0..6 {
                a[i][j] = spd[(i, j)];
            }
        }
        let (y, solved) = cholesky_solve6(&mut a, &b);
        assert!(solved, "positive definite");
        let expected = spd
            .cholesky()
            .expect("spd")
            .solve(&Vector6::from_row_slice(&b));
        for i in 0..6 {
            assert!(
                (y[i] - expected[i]).abs() < 1e-10,
                "{i}: {} vs {}",
                y[i],
                expected[i]
            );
        }
        let mut singular = [[0.0; 6]; 6];
        assert!(!cholesky_solve6(&mut singular, &b).1);
    }

    #[test]
    fn rotation_log_matches_so3_log_everywhere() {
        for k in 0..200 {
            let t = k as f64 / 200.0;
            let axis = Vector3::new((7.0 * t).sin(), (3.0 * t).cos(), 0.3 + t);
            let angle = t * std::f64::consts::PI * 0.999_999;
            let r = UnitQuaternion::from_scaled_axis(axis.normalize() * angle).to_rotation_matrix();
            let fast = rotation_log(r.matrix());
            let reference = so3_log(&r);
            assert!(
                (fast - reference).norm() < 1e-9,
                "angle {angle}: {fast} vs {reference}"
            );
        }
    }

    /// The 6 × 6 task-space step equals the joint-space Levenberg–Marquardt step
    /// `(JᵀWJ + λI)⁻¹ JᵀW e` (with `W = diag(1, 1, 1, ρ², ρ², ρ²)`), solved densely by nalgebra.
    #[test]
    fn task_space_step_equals_the_joint_space_step() {
        use crate::robot::builtin::{baxter, Arm};
        use nalgebra::{DMatrix, DVector};
        let chain = baxter(Arm::Left);
        let kernel = Kernel::new(&chain, 1e-5, 1e-5);
        let target = Target::new(&Isometry3::from_parts(
            nalgebra::Translation3::new(0.7, 0.3, 0.1),
            UnitQuaternion::from_euler_angles(0.3, 1.2, -0.4),
        ));
        let mut state = State::new();
        state.q[..7].copy_from_slice(&[0.1, -0.2, 0.3, 1.0, -0.4, 0.6, 0.2]);
        kernel.evaluate(&target, &mut state);
        let lambda = 0.01;
        let mut dq = [0.0; MAX_JOINTS];
        assert!(kernel.step(&state, lambda, Strategy::Clamped, &mut dq));
        let rho2 = ROTATION_LENGTH * ROTATION_LENGTH;
        let w = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 1.0, 1.0, rho2, rho2, rho2]));
        let j = DMatrix::from_column_slice(6, 7, &state.jacobian[..42]);
        let e = DVector::from_column_slice(state.error.as_slice());
        let normal = j.transpose() * &w * &j + DMatrix::identity(7, 7) * lambda;
        let expected = normal
            .lu()
            .solve(&(j.transpose() * &w * e))
            .expect("invertible");
        for k in 0..7 {
            assert!(
                (dq[k] - expected[k]).abs() < 1e-10,
                "{k}: {} vs {}",
                dq[k],
                expected[k]
            );
        }
    }

    /// The error moves as `−J·dq` near the target: finite differences of the error against
    /// the Jacobian (the linearisation every step relies on).
    #[test]
    fn error_changes_by_minus_jacobian_times_step() {
        use crate::robot::builtin::{baxter, Arm};
        let chain = baxter(Arm::Left);
        let kernel = Kernel::new(&chain, 1e-5, 1e-5);
        let q = [0.1, -0.2, 0.3, 1.0, -0.4, 0.6, 0.2];
        let at_q: Isometry3<f64> = nalgebra::convert(chain.pose(&q).expect("fk"));
        let target = Target::new(&at_q);
        let mut state = State::new();
        state.q[..7].copy_from_slice(&q);
        kernel.evaluate(&target, &mut state);
        assert!(state.error.norm() < 1e-12);
        let direction = [0.3, -0.1, 0.5, 0.2, -0.7, 0.4, 0.9];
        let h = 1e-6;
        let mut moved = State::new();
        for k in 0..7 {
            moved.q[k] = q[k] + h * direction[k];
        }
        kernel.evaluate(&target, &mut moved);
        for r in 0..6 {
            let predicted: f64 = (0..7)
                .map(|k| -state.jacobian[6 * k + r] * direction[k])
                .sum();
            let measured = moved.error[r] / h;
            assert!(
                (measured - predicted).abs() < 1e-5,
                "row {r}: {measured} vs {predicted}"
            );
        }
    }

    /// The run compiled for AVX2 (what [`Kernel::run`] picks on this processor, when it has
    /// AVX2) ends where the baseline build of the same loop ends, bit for bit: same end, same
    /// evaluations, same configuration and cost, for both strategies, with and without limits,
    /// on reachable targets and on targets out of reach.
    #[test]
    fn run_compiled_for_avx2_equals_the_baseline_bit_for_bit() {
        use crate::robot::builtin::{baxter, Arm};
        use rand::SeedableRng;
        let chain = baxter(Arm::Left);
        let limited = Kernel::new(&chain, 1e-5, 1e-5);
        let free = limited.unconstrained();
        let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(7);
        for case in 0..200 {
            let mut q_goal = [0.0; 7];
            limited.random_configuration(&mut rng, &mut q_goal);
            let mut pose: Isometry3<f64> = nalgebra::convert(chain.pose(&q_goal).expect("fk"));
            if case % 4 == 3 {
                // Out of reach along x: every run stalls or exhausts its cap.
                pose.translation.vector.x += 1.5;
            }
            let target = Target::new(&pose);
            let kernel = if case % 3 == 2 { &free } else { &limited };
            let strategy = if case % 2 == 0 {
                Strategy::Clamped
            } else {
                Strategy::LimitWeighted
            };
            let mut start = State::new();
            limited.random_configuration(&mut rng, &mut start.q[..7]);
            kernel.evaluate(&target, &mut start);
            let outcome = |dispatched: bool| {
                let mut ws = Workspace::new();
                *ws.cur_mut() = start.clone();
                let mut budget = Budget::new(60, None);
                // Caps of 3 to 22 evaluations, so that some runs end on their cap.
                let cap = 3 + case % 20;
                let patience = if case % 5 < 2 {
                    Patience::TRACKING
                } else {
                    Patience::SEARCH
                };
                let end = if dispatched {
                    kernel.run(&target, &mut ws, strategy, cap, patience, &mut budget)
                } else {
                    kernel.run_loop(&target, &mut ws, strategy, cap, patience, &mut budget)
                };
                let q: Vec<u64> = ws.cur().q[..7].iter().map(|v| v.to_bits()).collect();
                (end, budget.evaluations, q, ws.cur().cost.to_bits())
            };
            assert_eq!(outcome(true), outcome(false), "case {case}");
        }
    }

    #[test]
    fn limit_weight_blocks_outward_motion_on_a_limit() {
        assert_eq!(limit_weight(1.0, -1.0, 1.0, 0.5), 0.0);
        assert_eq!(limit_weight(1.0, -1.0, 1.0, -0.5), 1.0);
        assert_eq!(limit_weight(0.0, -1.0, 1.0, 0.5), 1.0);
        let near = limit_weight(0.9, -1.0, 1.0, 0.5);
        assert!(near > 0.0 && near < 1.0);
        assert_eq!(
            limit_weight(5.0, f64::NEG_INFINITY, f64::INFINITY, 1.0),
            1.0
        );
    }
}
