//! Four Levenberg–Marquardt runs at once, one per vector lane: the restarts of a search
//! advance together, so that their 6 × 6 factorisations (chains of square roots and divisions
//! whose latency bounds a single run) and their forward kinematics overlap.
//!
//! A lane performs exactly the IEEE operations of [`Kernel::run`] on its own attempt, in the
//! same order (see [`super::simd`]): its iterates, its end and its spent evaluations are
//! bit-identical to a run of that attempt alone. [`run_in_order`] runs a sequence of attempts
//! speculatively in the lanes and hands their ends to the caller in sequence order, charging a
//! shared evaluation budget as a one-at-a-time search would; an attempt that the budget would
//! have cut short is handed back to be run alone. A lane can also go on from where its last
//! run ended towards a target of its own ([`Lanes::load`], [`Lanes::resume`]), as trajectory
//! tracking does from one sample to the next: four branches, of one trajectory or of a batch,
//! are tracked at once.
//!
//! Frames and units as in [`super::kernel`]: base frame, m, rad.

// Lanes and joints read best with explicit indices.
#![allow(clippy::needless_range_loop)]

use super::kernel::{
    damped_step, Kernel, Patience, Residual, RunEnd, State, Strategy, Target, DAMPING_FLOOR,
};
use super::simd::{Mask4, Real, F4};
use crate::robot::chain::MAX_JOINTS;
use nalgebra::{Matrix3, Vector3};
use std::collections::VecDeque;
use std::ops::ControlFlow;

/// An attempt: where it starts, how joint limits enter its steps, its evaluation cap.
#[derive(Debug, Clone)]
pub(crate) struct Attempt {
    /// The start configuration (rad / m; the first `dof` values are used).
    pub q: [f64; MAX_JOINTS],
    pub strategy: Strategy,
    /// The run's own cap on evaluations (`max_evaluations` of [`Kernel::run`]).
    pub cap: usize,
}

/// How a lane's run ended and its best state: as [`super::attempt::run_attempt`] would leave
/// them for a started attempt, as [`Kernel::run`] would for a resumed run.
#[derive(Debug, Clone)]
pub(crate) struct AttemptEnd {
    pub end: RunEnd,
    /// Budget evaluations spent, the start's evaluation included when the run evaluated its
    /// start (a started attempt; a resumed run does not).
    pub spent: usize,
    /// The best configuration (rad / m, one value per joint).
    pub q: Vec<f64>,
    pub position_error: f64,
    pub rotation_error: f64,
    pub cost: f64,
}

/// What [`run_in_order`] hands over for each attempt, in sequence order.
#[derive(Debug, Clone)]
pub(crate) enum Handed {
    /// The attempt ran within the budget left for it; its evaluations are to be charged.
    Ended(AttemptEnd),
    /// The attempt needs more evaluations than the budget left for it: run it alone with that
    /// budget (where it stops for lack of budget).
    Cut,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Idle,
    /// The start configuration is yet to be evaluated.
    Starting,
    Running,
}

/// One lane's run: [`Kernel::run`]'s local state.
#[derive(Debug, Clone, Copy)]
struct Lane {
    phase: Phase,
    /// The caller's name for the run, handed back with its end: the attempt's position in the
    /// sequence, or the tracked branch's.
    tag: usize,
    strategy: Strategy,
    cap: usize,
    /// Evaluations the budget allows this attempt (`usize::MAX` while unknown).
    limit: usize,
    spent: usize,
    used: usize,
    mu: f64,
    window_cost: f64,
    window_steps: usize,
    /// The error of the current (best) configuration.
    current: Residual,
}

impl Lane {
    fn idle() -> Self {
        Self {
            phase: Phase::Idle,
            tag: 0,
            strategy: Strategy::Clamped,
            cap: 0,
            limit: 0,
            spent: 0,
            used: 0,
            mu: 1.0,
            window_cost: f64::INFINITY,
            window_steps: 0,
            current: UNEVALUATED,
        }
    }
}

/// The residual of a configuration not evaluated (an attempt stopped before its start).
const UNEVALUATED: Residual = Residual {
    error: nalgebra::Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    position_error: f64::INFINITY,
    rotation_error: f64::INFINITY,
    cost: f64::INFINITY,
};

/// Configurations and Jacobians of the four lanes, lane by lane: `q[j]` holds joint `j`,
/// `jacobian[6·j + row]` row `row` of column `j` (rows `[v; ω]`, base frame).
#[derive(Debug, Clone)]
struct LaneStates {
    q: Vec<F4>,
    jacobian: Vec<F4>,
}

impl LaneStates {
    fn new(dof: usize) -> Self {
        Self {
            q: vec![F4::default(); dof],
            jacobian: vec![F4::default(); 6 * dof],
        }
    }
}

/// A tip pose in the base frame: position (m) and orientation.
type TipPose = (Vector3<f64>, Matrix3<f64>);

/// Four Levenberg–Marquardt runs, advanced one iteration at a time, each towards its lane's
/// target (one target for all four in a search).
pub(crate) struct Lanes<'k> {
    kernel: Kernel<'k>,
    targets: [Target; 4],
    patience: Patience,
    lanes: [Lane; 4],
    /// Each lane's current (best) configuration, evaluated.
    current: LaneStates,
    /// The tip pose at each lane's current configuration.
    tips: [TipPose; 4],
    /// Each lane's candidate configuration.
    candidate: LaneStates,
    /// Scratch: the joints' weights and the step (one per joint).
    weights: Vec<F4>,
    dq: Vec<F4>,
}

impl<'k> Lanes<'k> {
    pub(crate) fn new(kernel: Kernel<'k>, target: Target, patience: Patience) -> Self {
        let dof = kernel.dof();
        Self {
            kernel,
            targets: [target; 4],
            patience,
            lanes: [Lane::idle(); 4],
            current: LaneStates::new(dof),
            tips: [(Vector3::zeros(), Matrix3::identity()); 4],
            candidate: LaneStates::new(dof),
            weights: vec![F4::default(); dof],
            dq: vec![F4::default(); dof],
        }
    }

    pub(crate) fn free_lane(&self) -> Option<usize> {
        self.lanes.iter().position(|l| l.phase == Phase::Idle)
    }

    pub(crate) fn busy(&self) -> bool {
        self.lanes.iter().any(|l| l.phase != Phase::Idle)
    }

    fn lane_of(&self, tag: usize) -> Option<usize> {
        self.lanes
            .iter()
            .position(|l| l.phase != Phase::Idle && l.tag == tag)
    }

    /// Starts `attempt` in the free lane `lane`, allowed `limit` evaluations.
    fn start(&mut self, lane: usize, tag: usize, attempt: &Attempt, limit: usize) {
        for (j, q) in self.current.q.iter_mut().enumerate() {
            q.0[lane] = attempt.q[j];
        }
        self.lanes[lane] = Lane {
            phase: Phase::Starting,
            tag,
            strategy: attempt.strategy,
            cap: attempt.cap,
            limit,
            ..Lane::idle()
        };
    }

    /// Puts the evaluated `state` (configuration, Jacobian, tip pose) in the idle lane `lane`,
    /// for [`Lanes::resume`] to go on from.
    pub(crate) fn load(&mut self, lane: usize, state: &State) {
        debug_assert_eq!(self.lanes[lane].phase, Phase::Idle);
        for (j, q) in self.current.q.iter_mut().enumerate() {
            q.0[lane] = state.q[j];
        }
        for (k, column) in self.current.jacobian.iter_mut().enumerate() {
            column.0[lane] = state.jacobian[k];
        }
        self.tips[lane] = (state.position, state.rotation);
    }

    /// Starts a run in the idle lane `lane` from its current state (the end of its last run,
    /// or what [`Lanes::load`] put there) towards `target`, allowed `cap` evaluations: what
    /// [`Kernel::run`] does from a state [`Kernel::retarget`]ed to `target`, the start not
    /// evaluated again.
    pub(crate) fn resume(&mut self, lane: usize, tag: usize, target: Target, cap: usize) {
        debug_assert_eq!(self.lanes[lane].phase, Phase::Idle);
        let (position, rotation) = &self.tips[lane];
        let current = Residual::of(&target, position, rotation);
        self.targets[lane] = target;
        self.lanes[lane] = Lane {
            phase: Phase::Running,
            tag,
            strategy: Strategy::Clamped,
            cap,
            limit: cap,
            window_cost: current.cost,
            current,
            ..Lane::idle()
        };
    }

    /// Stops every run.
    fn clear(&mut self) {
        for lane in &mut self.lanes {
            lane.phase = Phase::Idle;
        }
    }

    /// Ends lane `lane`'s run with `end`, appending `(tag, end)` to `ended`.
    fn finish(&mut self, lane: usize, end: RunEnd, ended: &mut Vec<(usize, AttemptEnd)>) {
        let state = &mut self.lanes[lane];
        state.phase = Phase::Idle;
        let q = self.current.q.iter().map(|v| v.0[lane]).collect();
        ended.push((
            state.tag,
            AttemptEnd {
                end,
                spent: state.spent,
                q,
                position_error: state.current.position_error,
                rotation_error: state.current.rotation_error,
                cost: state.current.cost,
            },
        ));
    }

    /// One iteration of every busy lane; the runs that end are appended to `ended`.
    pub(crate) fn advance(&mut self, ended: &mut Vec<(usize, AttemptEnd)>) {
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::has_avx2() {
            // SAFETY: the processor has AVX2, checked just above.
            return unsafe { self.advance_avx2(ended) };
        }
        self.advance_body(ended);
    }

    /// [`Lanes::advance`] compiled for AVX2.
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn advance_avx2(&mut self, ended: &mut Vec<(usize, AttemptEnd)>) {
        self.advance_body(ended);
    }

    /// [`Kernel::run`]'s loop body for every lane, in its order: the convergence and cap
    /// checks, the step, the budget, the clamped move, the evaluation, the acceptance; then
    /// the next iteration's convergence check, so that a converged lane is free at once.
    #[inline(always)]
    fn advance_body(&mut self, ended: &mut Vec<(usize, AttemptEnd)>) {
        let n = self.kernel.dof();
        let mut stepping = [false; 4];
        let mut lambda = F4::default();
        for l in 0..4 {
            let lane = self.lanes[l];
            if lane.phase != Phase::Running {
                continue;
            }
            let current = &lane.current;
            if self
                .kernel
                .within_tolerance(current.position_error, current.rotation_error)
            {
                self.finish(l, RunEnd::Converged, ended);
            } else if lane.used >= lane.cap {
                self.finish(l, RunEnd::Exhausted, ended);
            } else {
                lambda.0[l] = lane.mu * (current.cost + DAMPING_FLOOR);
                stepping[l] = true;
            }
        }
        let mut evaluate = [false; 4];
        let starting = self.lanes.map(|l| l.phase == Phase::Starting);
        if stepping.contains(&true) {
            let error: [F4; 6] =
                std::array::from_fn(|r| F4::from_fn(|l| self.lanes[l].current.error[r]));
            let (kernel, lanes, current) = (&self.kernel, &self.lanes, &self.current);
            let (weights, dq) = (&mut self.weights, &mut self.dq);
            let clamped = Mask4::from_fn(|l| lanes[l].strategy == Strategy::Clamped);
            let solved = damped_step(
                &current.jacobian,
                &error,
                lambda,
                |j, gradient| {
                    joint_weights(
                        clamped,
                        current.q[j],
                        kernel.lower[j],
                        kernel.upper[j],
                        gradient,
                    )
                },
                weights,
                dq,
            );
            // The clamped move of every stepping lane; any other lane's candidate is its
            // current configuration (a start, or finite values that keep the kinematics on its
            // fast path).
            let moving = F4::both(Mask4::from_bools(stepping), solved);
            let mut moved = F4::default();
            for j in 0..n {
                let q = self.current.q[j];
                let (lo, hi) = (
                    F4::splat(self.kernel.lower[j]),
                    F4::splat(self.kernel.upper[j]),
                );
                let v = (q + dq[j]).max(lo).min(hi);
                moved = moved.max((v - q).abs());
                self.candidate.q[j] = F4::select(moving, v, q);
            }
            for l in (0..4).filter(|&l| stepping[l]) {
                if !solved.lane(l) {
                    self.finish(l, RunEnd::Stalled, ended);
                    continue;
                }
                let lane = &mut self.lanes[l];
                if lane.spent >= lane.limit {
                    self.finish(l, RunEnd::OutOfBudget, ended);
                    continue;
                }
                lane.spent += 1;
                lane.used += 1;
                if moved.0[l] < 1e-14 {
                    // Every joint is pinned: nothing more to gain here.
                    self.finish(l, RunEnd::Stalled, ended);
                    continue;
                }
                evaluate[l] = true;
            }
        } else {
            for (candidate, current) in self.candidate.q.iter_mut().zip(&self.current.q) {
                *candidate = *current;
            }
        }
        for l in (0..4).filter(|&l| starting[l]) {
            // The start's evaluation, as `run_attempt` spends it.
            let lane = &mut self.lanes[l];
            if lane.spent >= lane.limit {
                lane.current = UNEVALUATED;
                self.finish(l, RunEnd::OutOfBudget, ended);
                continue;
            }
            lane.spent += 1;
            evaluate[l] = true;
        }
        if !evaluate.contains(&true) {
            return;
        }
        let poses = self.kernel.chain.four_poses_and_jacobians(
            F4::as_arrays(&self.candidate.q),
            F4::as_arrays_mut(&mut self.candidate.jacobian),
        );
        // Each evaluated lane's error; the candidate replaces the current state where it is a
        // start or lowers the cost.
        let mut residuals = [UNEVALUATED; 4];
        let mut take = [false; 4];
        for l in (0..4).filter(|&l| evaluate[l]) {
            let pose = &poses[l];
            residuals[l] = Residual::of(
                &self.targets[l],
                &pose.translation.vector,
                pose.rotation.matrix(),
            );
            take[l] = starting[l] || residuals[l].cost < self.lanes[l].current.cost;
            if take[l] {
                self.tips[l] = (pose.translation.vector, *pose.rotation.matrix());
            }
        }
        let take_mask = Mask4::from_bools(take);
        for (current, candidate) in self.current.q.iter_mut().zip(&self.candidate.q) {
            *current = F4::select(take_mask, *candidate, *current);
        }
        for (current, candidate) in self
            .current
            .jacobian
            .iter_mut()
            .zip(&self.candidate.jacobian)
        {
            *current = F4::select(take_mask, *candidate, *current);
        }
        for l in (0..4).filter(|&l| evaluate[l]) {
            let residual = residuals[l];
            let lane = &mut self.lanes[l];
            if starting[l] {
                lane.phase = Phase::Running;
                lane.current = residual;
                lane.window_cost = residual.cost;
            } else if take[l] {
                lane.current = residual;
                lane.mu = (lane.mu * 0.5).max(1.0);
                lane.window_steps += 1;
                if lane.window_steps == self.patience.window {
                    if lane.current.cost > self.patience.factor * lane.window_cost {
                        self.finish(l, RunEnd::Stalled, ended);
                        continue;
                    }
                    lane.window_cost = lane.current.cost;
                    lane.window_steps = 0;
                }
            } else {
                lane.mu *= 8.0;
                if lane.mu > 1e6 {
                    self.finish(l, RunEnd::Stalled, ended);
                }
                continue;
            }
            // The next iteration's first check, done now so that the lane is free for the
            // caller to refill before it.
            if self
                .kernel
                .within_tolerance(residual.position_error, residual.rotation_error)
            {
                self.finish(l, RunEnd::Converged, ended);
            }
        }
    }
}

/// A joint's weight in each lane's step ([`joint_weight`](super::kernel::joint_weight), lane
/// by lane, bit for bit): the lanes of `clamped` use [`Strategy::Clamped`], the others
/// [`Strategy::LimitWeighted`]. `q` is the joint's value in each lane and `gradient` the
/// descent direction of the cost along it; `lo` and `hi` its limits (rad / m).
#[inline(always)]
fn joint_weights(clamped: Mask4, q: F4, lo: f64, hi: f64, gradient: F4) -> F4 {
    let (zero, one) = (F4::splat(0.0), F4::splat(1.0));
    let (lo4, hi4) = (F4::splat(lo), F4::splat(hi));
    // Clamped: 0 on a limit when pushed outwards.
    let pinned = F4::both(q.le(lo4), gradient.lt(zero)).or(F4::both(hi4.le(q), zero.lt(gradient)));
    let clamped_weight = F4::select(pinned, zero, one);
    if !(lo.is_finite() && hi.is_finite()) {
        return F4::select(clamped, clamped_weight, one);
    }
    // Limit-weighted (Chan & Dubey): the same operations as `limit_weight`, in its order.
    let offset = F4::splat(2.0) * q - hi4 - lo4;
    let away = zero.lt(gradient).differs(zero.lt(offset));
    let (to_hi, to_lo) = (hi4 - q, q - lo4);
    let outside = to_hi.le(zero).or(to_lo.le(zero));
    let range = hi4 - lo4;
    let dh = range * range * offset.abs() / (F4::splat(4.0) * to_hi * to_hi * to_lo * to_lo);
    let weighted = F4::select(away, one, F4::select(outside, zero, one / (one + dh)));
    F4::select(clamped, clamped_weight, weighted)
}

/// Runs every attempt of `attempts` to its end in the lanes of `lanes`, each allowed its own
/// number of evaluations (`attempts[i].1`, [`Budget`](super::kernel::Budget)'s count); returns
/// the ends in the attempts' order.
pub(crate) fn run_each(lanes: &mut Lanes<'_>, attempts: &[(Attempt, usize)]) -> Vec<AttemptEnd> {
    let mut ends: Vec<Option<AttemptEnd>> = vec![None; attempts.len()];
    let mut started = 0;
    let mut ended = Vec::with_capacity(4);
    loop {
        while started < attempts.len() {
            let Some(lane) = lanes.free_lane() else { break };
            let (attempt, limit) = &attempts[started];
            lanes.start(lane, started, attempt, *limit);
            started += 1;
        }
        if !lanes.busy() {
            break;
        }
        lanes.advance(&mut ended);
        for (tag, end) in ended.drain(..) {
            ends[tag] = Some(end);
        }
    }
    ends.into_iter()
        .map(|end| end.expect("every started attempt ends"))
        .collect()
}

/// Where a started attempt stands, while it waits to be handed over.
#[derive(Debug)]
enum Standing {
    Running,
    Ended(AttemptEnd),
    /// It spent more than the budget left for it (found once its turn came).
    Overran,
}

/// Runs the attempts `next(0)`, `next(1)`, … (drawn in that order, `None` when there are no
/// more) in the lanes of `lanes`, and hands each one's end to `hand(i, attempt, handed)` in
/// sequence order, as a search running them one after the other with a shared budget of
/// `budget` evaluations would see them: attempt `i` is allowed what attempts `0..i` left.
/// `hand` returns [`ControlFlow::Break`] when the search stops; it stops after a
/// [`Handed::Cut`] too (the budget is spent). Later attempts are dropped.
///
/// Attempts are started ahead of the one handed next while lanes are free and the budget
/// may still reach them; their ends wait for their turn.
pub(crate) fn run_in_order(
    lanes: &mut Lanes<'_>,
    budget: usize,
    mut next: impl FnMut(usize) -> Option<Attempt>,
    mut hand: impl FnMut(usize, &Attempt, Handed) -> ControlFlow<()>,
) {
    // Attempts started and not yet handed over, from number `handed` on.
    let mut waiting: VecDeque<(Attempt, Standing)> = VecDeque::new();
    let mut handed = 0usize;
    let mut left = budget;
    let mut more = true;
    let mut ended = Vec::with_capacity(4);
    loop {
        // Hand over what has ended, in order.
        while matches!(
            waiting.front(),
            Some((_, Standing::Ended(_) | Standing::Overran))
        ) {
            let (attempt, standing) = waiting.pop_front().expect("the front exists");
            let verdict = match standing {
                Standing::Ended(end) if end.spent <= left => {
                    left -= end.spent;
                    Handed::Ended(end)
                }
                _ => Handed::Cut,
            };
            let cut = matches!(verdict, Handed::Cut);
            if hand(handed, &attempt, verdict).is_break() || cut {
                lanes.clear();
                return;
            }
            handed += 1;
            // The next in order now knows its budget.
            if let Some(lane) = lanes.lane_of(handed) {
                let state = &mut lanes.lanes[lane];
                if state.spent > left {
                    state.phase = Phase::Idle;
                    waiting[0].1 = Standing::Overran;
                } else {
                    state.limit = left;
                }
            }
        }
        // Start attempts in free lanes while the budget may still reach them.
        while more {
            let Some(lane) = lanes.free_lane() else { break };
            let committed = waiting
                .iter()
                .map(|(_, standing)| match standing {
                    Standing::Ended(end) => end.spent,
                    Standing::Running | Standing::Overran => 0,
                })
                .sum::<usize>()
                + lanes
                    .lanes
                    .iter()
                    .filter(|l| l.phase != Phase::Idle)
                    .map(|l| l.spent)
                    .sum::<usize>();
            if committed >= left {
                break;
            }
            let tag = handed + waiting.len();
            let Some(attempt) = next(tag) else {
                more = false;
                break;
            };
            let limit = if waiting.is_empty() { left } else { usize::MAX };
            lanes.start(lane, tag, &attempt, limit);
            waiting.push_back((attempt, Standing::Running));
        }
        if !lanes.busy() {
            // Nothing runs and nothing waits: no attempt is left that the budget reaches.
            return;
        }
        ended.clear();
        lanes.advance(&mut ended);
        for (tag, end) in ended.drain(..) {
            waiting[tag - handed].1 = Standing::Ended(end);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::attempt::run_attempt;
    use super::super::kernel::{Budget, Workspace};
    use super::*;
    use crate::robot::builtin::{baxter, Arm};
    use crate::robot::chain::Chain;
    use nalgebra::Isometry3;
    use rand::rngs::Xoshiro256PlusPlus;
    use rand::{RngExt, SeedableRng};

    /// The four lanes' weights equal the one-run weights bit for bit, for both strategies side
    /// by side, on and beyond the limits, at the midpoint, for zero and signed-zero
    /// directions, NaN, and infinite limits; then on random values.
    #[test]
    fn lane_weights_are_the_scalar_weights_bit_for_bit() {
        use super::super::kernel::joint_weight;
        let limits = [
            (-1.5, 2.0),
            (0.0, 1e-9),
            (f64::NEG_INFINITY, f64::INFINITY),
            (-1.0, f64::INFINITY),
        ];
        let values = [
            -1.5,
            2.0,
            0.25,
            -2.0,
            3.0,
            1e-10,
            0.0,
            -0.0,
            5e-10,
            1.9999999,
            f64::NAN,
        ];
        let gradients = [1.0, -1.0, 0.0, -0.0, 1e-300, -3.5, f64::NAN];
        let check = |strategies: [Strategy; 4], q: F4, lo: f64, hi: f64, gradient: F4| {
            let clamped = Mask4::from_fn(|l| strategies[l] == Strategy::Clamped);
            let lanes = joint_weights(clamped, q, lo, hi, gradient);
            for l in 0..4 {
                let one = joint_weight(strategies[l], q.0[l], lo, hi, gradient.0[l]);
                assert_eq!(
                    lanes.0[l].to_bits(),
                    one.to_bits(),
                    "{:?} q {} in [{lo}, {hi}], gradient {}",
                    strategies[l],
                    q.0[l],
                    gradient.0[l]
                );
            }
        };
        let mixed = [
            Strategy::Clamped,
            Strategy::LimitWeighted,
            Strategy::LimitWeighted,
            Strategy::Clamped,
        ];
        for &(lo, hi) in &limits {
            for (i, &g) in gradients.iter().enumerate() {
                for chunk in values.chunks(4) {
                    let q = F4::from_fn(|l| chunk[l % chunk.len()]);
                    let gradient = F4::from_fn(|l| gradients[(i + l) % gradients.len()] * 0.5 + g);
                    check(mixed, q, lo, hi, gradient);
                    check([Strategy::LimitWeighted; 4], q, lo, hi, F4::splat(g));
                    check([Strategy::Clamped; 4], q, lo, hi, F4::splat(g));
                }
            }
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        for _ in 0..2000 {
            let lo = rng.random_range(-3.0..0.0);
            let hi = lo + rng.random_range(0.0..4.0);
            let q = F4::from_fn(|_| rng.random_range(lo - 0.1..=hi + 0.1));
            let gradient = F4::from_fn(|_| rng.random_range(-1.0..1.0));
            let strategies = std::array::from_fn(|_| {
                if rng.random_range(0..2) == 0 {
                    Strategy::Clamped
                } else {
                    Strategy::LimitWeighted
                }
            });
            check(strategies, q, lo, hi, gradient);
        }
    }

    /// An attempt's end as bits, for exact comparison.
    type Bits = (RunEnd, usize, Vec<u64>, u64, u64, u64);

    fn bits(end: RunEnd, spent: usize, q: &[f64], errors: (f64, f64), cost: f64) -> Bits {
        (
            end,
            spent,
            q.iter().map(|v| v.to_bits()).collect(),
            errors.0.to_bits(),
            errors.1.to_bits(),
            cost.to_bits(),
        )
    }

    /// The attempt run alone by [`run_attempt`] with `budget` evaluations: the oracle.
    fn alone(kernel: &Kernel<'_>, target: &Target, attempt: &Attempt, budget: usize) -> Bits {
        let n = kernel.dof();
        let mut ws = Workspace::new();
        ws.cur_mut().q = attempt.q;
        let mut budget = Budget::new(budget, None);
        let end = run_attempt(
            kernel,
            target,
            &mut ws,
            attempt.strategy,
            attempt.cap,
            Patience::SEARCH,
            &mut budget,
        );
        let state = ws.cur();
        bits(
            end,
            budget.evaluations,
            &state.q[..n],
            (state.position_error, state.rotation_error),
            state.cost,
        )
    }

    /// A target at a random configuration's pose, pushed out of reach one time in four.
    fn random_target(chain: &Chain, kernel: &Kernel<'_>, rng: &mut Xoshiro256PlusPlus) -> Target {
        let mut q = [0.0; 7];
        kernel.random_configuration(rng, &mut q);
        let mut pose: Isometry3<f64> = nalgebra::convert(chain.pose(&q).expect("fk"));
        if rng.random_range(0..4) == 0 {
            pose.translation.vector.x += 1.5;
        }
        Target::new(&pose)
    }

    fn random_attempt(kernel: &Kernel<'_>, rng: &mut Xoshiro256PlusPlus) -> Attempt {
        let mut q = [0.0; MAX_JOINTS];
        kernel.random_configuration(rng, &mut q[..kernel.dof()]);
        Attempt {
            q,
            strategy: if rng.random_range(0..2) == 0 {
                Strategy::Clamped
            } else {
                Strategy::LimitWeighted
            },
            cap: rng.random_range(1..60),
        }
    }

    /// Every lane ends where the attempt run alone ends, bit for bit, with lanes refilled as
    /// they end, with and without joint limits, and with budgets that stop some runs.
    #[test]
    fn each_lane_ends_where_its_attempt_alone_ends_bit_for_bit() {
        let chain = baxter(Arm::Left);
        let limited = Kernel::new(&chain, 1e-5, 1e-5);
        let free = limited.unconstrained();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        for case in 0..60 {
            let kernel = if case % 3 == 2 { free } else { limited };
            let target = random_target(&chain, &limited, &mut rng);
            let attempts: Vec<(Attempt, usize)> = (0..11)
                .map(|_| {
                    let attempt = random_attempt(&limited, &mut rng);
                    let limit = match rng.random_range(0..4) {
                        0 => rng.random_range(0..30),
                        _ => usize::MAX,
                    };
                    (attempt, limit)
                })
                .collect();
            let mut lanes = Lanes::new(kernel, target, Patience::SEARCH);
            let got: Vec<Bits> = run_each(&mut lanes, &attempts)
                .iter()
                .map(|end| {
                    bits(
                        end.end,
                        end.spent,
                        &end.q,
                        (end.position_error, end.rotation_error),
                        end.cost,
                    )
                })
                .collect();
            for (i, (attempt, limit)) in attempts.iter().enumerate() {
                let expected = alone(&kernel, &target, attempt, *limit);
                assert_eq!(got[i], expected, "case {case}, attempt {i}");
            }
        }
    }

    /// [`run_in_order`] hands over exactly what a search running the attempts one after the
    /// other with the shared budget sees, up to where the search stops: budgets that cut an
    /// attempt short, searches that stop on their own, sequences that run dry.
    #[test]
    fn attempts_are_handed_over_as_a_sequential_search_sees_them() {
        let chain = baxter(Arm::Left);
        let kernel = Kernel::new(&chain, 1e-5, 1e-5);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(9);
        for case in 0..80 {
            let target = random_target(&chain, &kernel, &mut rng);
            let sequence: Vec<Attempt> = (0..rng.random_range(1..20))
                .map(|_| random_attempt(&kernel, &mut rng))
                .collect();
            let budget = rng.random_range(1..400);
            // The search stops by itself after this many attempts (if the budget lasts).
            let stop_after = rng.random_range(1..25);
            // The oracle: one attempt after the other, sharing one budget.
            let mut expected = Vec::new();
            let mut shared = Budget::new(budget, None);
            for attempt in &sequence {
                if shared.exhausted() || expected.len() == stop_after {
                    break;
                }
                let before = shared.evaluations;
                let mut ended = alone(&kernel, &target, attempt, shared.evaluations_left);
                shared.charge(ended.1);
                ended.1 = shared.evaluations - before;
                expected.push(ended);
            }
            let mut got = Vec::new();
            let mut lanes = Lanes::new(kernel, target, Patience::SEARCH);
            let mut left = budget;
            run_in_order(
                &mut lanes,
                budget,
                |i| sequence.get(i).cloned(),
                |i, attempt, handed| {
                    assert_eq!(i, got.len(), "handed in order");
                    let ended = match handed {
                        Handed::Ended(end) => bits(
                            end.end,
                            end.spent,
                            &end.q,
                            (end.position_error, end.rotation_error),
                            end.cost,
                        ),
                        Handed::Cut => alone(&kernel, &target, attempt, left),
                    };
                    left -= ended.1;
                    got.push(ended);
                    if left == 0 || got.len() == stop_after {
                        ControlFlow::Break(())
                    } else {
                        ControlFlow::Continue(())
                    }
                },
            );
            assert_eq!(got, expected, "case {case}");
        }
    }
}
