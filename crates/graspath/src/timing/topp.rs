//! Time-optimal path parameterisation by reachability analysis (TOPP-RA: Pham & Pham, IEEE
//! T-RO 34(3), 2018).
//!
//! Along a path `q(s)`, `s ∈ [s_0, s_N]`, the motion is set by `ṡ(t)`. With `x = ṡ²` and
//! `u = s̈`, every constraint this crate uses is linear in `(u, x)` at a grid point `s_i`:
//! joint velocities `q'(s) ṡ` bound `x` alone; joint accelerations `q' u + q'' x` and joint
//! torques `a(s) u + b(s) x + c(s)` are rows `lo ≤ a u + b x ≤ hi`. Between grid points `u` is
//! constant, so `x_{i+1} = x_i + 2 Δ_i u_i`. The constraints are imposed at the grid points
//! (toppra's *collocation* discretisation) or, by default, at both ends of each stage with
//! the stage's `u` (its *interpolation* discretisation; see [`Discretization`]).
//!
//! The backward pass computes each grid point's *controllable set* `K_i`: the `x_i` from
//! which some admissible `u_i` reaches `K_{i+1}` (`K_N = {x_end}`), the projection on `x` of a
//! two-variable polygon. The forward pass starts at `x_0` and takes at each point the largest
//! admissible `u_i` that stays controllable. Both are exact for the discretised problem; the
//! projection is found by Newton steps on the concave piecewise-linear slack
//! `min_upper(x) − max_lower(x)` (each step lands on a vertex of the polygon), which needs
//! no general LP solver. The time of interval `i` at constant `u_i` is
//! `2 Δ_i / (ṡ_i + ṡ_{i+1})`.

use super::TimingError;
use crate::spelling::spelled;

/// One linear constraint `lo ≤ a u + b x ≤ hi` at a grid point, with what it limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// The coefficient of `u = s̈`.
    pub a: f64,
    /// The coefficient of `x = ṡ²`.
    pub b: f64,
    /// The lower bound.
    pub lo: f64,
    /// The upper bound.
    pub hi: f64,
    /// What the row limits (for the failure message).
    pub limit: Limit,
}

/// The quantity a constraint limits: a joint's velocity, acceleration or torque, or the carried
/// object's speed or acceleration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// Joint `j`'s velocity.
    Velocity(usize),
    /// Joint `j`'s acceleration.
    Acceleration(usize),
    /// Joint `j`'s torque (or force).
    Torque(usize),
    /// The carried object's linear speed.
    ObjectSpeed,
    /// The carried object's angular speed.
    ObjectTurnRate,
    /// The carried object's linear acceleration.
    ObjectAcceleration,
    /// The carried object's angular acceleration.
    ObjectAngularAcceleration,
}

/// Where a stage's constraints are imposed (toppra's `DiscretizationType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Discretization {
    /// At the stage's start only: `(u_i, x_i)` satisfies grid point `i`'s rows.
    Collocation,
    /// At both ends of the stage with its one `u_i`: grid point `i`'s rows at `(u_i, x_i)`
    /// and grid point `i+1`'s at `(u_i, x_i + 2Δ_i u_i)`, the path acceleration the motion
    /// actually keeps up to the next grid point. The limits then hold at both ends of every
    /// interval of the timed motion, not only where each interval starts (the default).
    #[default]
    Interpolation,
}

spelled!(Discretization {
    Interpolation => "interpolation",
    Collocation => "collocation",
});

/// The constraints of a path on a grid: at each grid point an upper bound on `x` and the
/// same number of rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraints {
    /// Where each stage's constraints are imposed.
    pub discretization: Discretization,
    /// The grid, strictly increasing.
    pub grid: Vec<f64>,
    /// The largest `x = ṡ²` at each grid point (`+∞` when unbounded), with what bounds it.
    pub x_max: Vec<(f64, Option<Limit>)>,
    /// Rows per grid point.
    pub rows_per_point: usize,
    /// The rows of grid point `i` at `[i * rows_per_point..(i + 1) * rows_per_point]`.
    pub rows: Vec<Row>,
}

impl Limit {
    /// The joint this limit is on, when it is on one.
    pub fn joint(self) -> Option<usize> {
        match self {
            Limit::Velocity(j) | Limit::Acceleration(j) | Limit::Torque(j) => Some(j),
            _ => None,
        }
    }

    /// This limit on joint `joint` instead (the object's limits, on none, unchanged).
    fn on_joint(self, joint: usize) -> Self {
        match self {
            Limit::Velocity(_) => Limit::Velocity(joint),
            Limit::Acceleration(_) => Limit::Acceleration(joint),
            Limit::Torque(_) => Limit::Torque(joint),
            other => other,
        }
    }

    /// This limit with its joint index moved by `offset` (the object's limits unchanged).
    fn shifted(self, offset: usize) -> Self {
        self.joint().map_or(self, |j| self.on_joint(j + offset))
    }

    /// This limit of a stacked path ([`Constraints::stacked`]) as `(part, limit)`: the part
    /// whose joint it is on, with the joint's index there (the object's limits, on no
    /// joint, as the first part's).
    pub fn in_part(self, dofs: &[usize]) -> (usize, Self) {
        let Some(mut joint) = self.joint() else {
            return (0, self);
        };
        for (part, &dof) in dofs.iter().enumerate() {
            if joint < dof {
                return (part, self.on_joint(joint));
            }
            joint -= dof;
        }
        (0, self)
    }
}

impl Constraints {
    /// The constraints of one path whose joints are those of `parts`' paths one after the
    /// other, all on one grid (arms that carry one object, timed by one path parameter): at
    /// each grid point the smallest bound on `x` and every part's rows. Part `k`'s joint
    /// indices move by the joint counts `dofs` of the parts before it
    /// ([`Limit::in_part`] moves them back).
    pub fn stacked(parts: Vec<Constraints>, dofs: &[usize]) -> Result<Self, TimingError> {
        if parts.len() != dofs.len() {
            return Err(TimingError::BadPath(format!(
                "{} paths to stack with {} joint counts",
                parts.len(),
                dofs.len()
            )));
        }
        let mut parts = parts.into_iter();
        let Some(first) = parts.next() else {
            return Err(TimingError::BadPath("no path to stack".into()));
        };
        let mut stacked = first;
        let mut offset = dofs[0];
        for (part, &dof) in parts.zip(&dofs[1..]) {
            if part.grid != stacked.grid || part.discretization != stacked.discretization {
                return Err(TimingError::BadPath(
                    "the stacked paths are not on one grid".into(),
                ));
            }
            let (m, n) = (stacked.rows_per_point, part.rows_per_point);
            let mut rows = Vec::with_capacity(stacked.grid.len() * (m + n));
            for i in 0..stacked.grid.len() {
                rows.extend_from_slice(&stacked.rows[i * m..(i + 1) * m]);
                rows.extend(part.rows[i * n..(i + 1) * n].iter().map(|row| Row {
                    limit: row.limit.shifted(offset),
                    ..*row
                }));
                let (x, limit) = part.x_max[i];
                if x < stacked.x_max[i].0 {
                    stacked.x_max[i] = (x, limit.map(|l| l.shifted(offset)));
                }
            }
            stacked.rows = rows;
            stacked.rows_per_point = m + n;
            offset += dof;
        }
        Ok(stacked)
    }
}

/// A time-optimal parameterisation: `ṡ²` at every grid point and the times.
#[derive(Debug, Clone, PartialEq)]
pub struct TimedPath {
    /// The grid (path parameter).
    pub grid: Vec<f64>,
    /// `x_i = ṡ²` at each grid point.
    pub sd_squared: Vec<f64>,
    /// The time at each grid point (s), from `0`.
    pub times: Vec<f64>,
}

impl TimedPath {
    /// The motion's duration (s).
    pub fn duration(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// The same motion `factor` (≥ 1) times slower: every time multiplied by it, `ṡ`
    /// divided by it. Velocities scale by `1/factor` and accelerations by `1/factor²`, and
    /// each torque `g + (τ − g)/factor²` lies between the original one and the static `g(q)`:
    /// every limit that held, with the path's static torques within theirs, still holds.
    pub fn slowed(&self, factor: f64) -> Self {
        Self {
            grid: self.grid.clone(),
            sd_squared: self
                .sd_squared
                .iter()
                .map(|x| x / (factor * factor))
                .collect(),
            times: self.times.iter().map(|t| t * factor).collect(),
        }
    }

    /// The path parameter, `ṡ` and `s̈` at time `t` (clamped to `[0, duration]`).
    pub fn state_at(&self, t: f64) -> (f64, f64, f64) {
        let t = t.clamp(0.0, self.duration());
        let n = self.grid.len();
        if n < 2 {
            return (self.grid.first().copied().unwrap_or(0.0), 0.0, 0.0);
        }
        let i = self.times.partition_point(|&ti| ti <= t).clamp(1, n - 1) - 1;
        let delta = self.grid[i + 1] - self.grid[i];
        let u = (self.sd_squared[i + 1] - self.sd_squared[i]) / (2.0 * delta);
        let tau = t - self.times[i];
        let sd0 = self.sd_squared[i].sqrt();
        let s = (self.grid[i] + sd0 * tau + 0.5 * u * tau * tau).min(self.grid[i + 1]);
        (s, (sd0 + u * tau).max(0.0), u)
    }

    /// The time (s, from `0`) at which the motion passes path parameter `s` (clamped to the
    /// grid's range): the inverse of [`TimedPath::state_at`]. At a grid point it is that
    /// point's time exactly; between grid points, at constant `s̈ = u` from `ṡ_i`, the
    /// interval's `Δs = s − s_i` takes `2 Δs / (ṡ_i + ṡ(s))` with `ṡ(s)² = ṡ_i² + 2 u Δs`.
    pub fn time_at(&self, s: f64) -> f64 {
        let n = self.grid.len();
        if n < 2 {
            return 0.0;
        }
        let s = s.clamp(self.grid[0], self.grid[n - 1]);
        // The interval [grid[i], grid[i + 1]) that holds `s` (the last one for its end).
        let i = self.grid.partition_point(|&g| g <= s).clamp(1, n - 1) - 1;
        let delta = s - self.grid[i];
        if delta <= 0.0 {
            return self.times[i];
        }
        if s >= self.grid[i + 1] {
            return self.times[i + 1];
        }
        let x0 = self.sd_squared[i];
        let u = (self.sd_squared[i + 1] - x0) / (2.0 * (self.grid[i + 1] - self.grid[i]));
        let speeds = x0.sqrt() + (x0 + 2.0 * u * delta).max(0.0).sqrt();
        (self.times[i] + 2.0 * delta / speeds).min(self.times[i + 1])
    }
}

/// Relative slack accepted on a constraint (rounding in the rows and in the Newton steps).
const TOLERANCE: f64 = 1e-9;

/// Where the search for the largest `x = ṡ²` starts when nothing bounds `x` alone (no
/// velocity limit binds at a grid point): `ṡ = 10⁶` per unit of path, far beyond any arm.
const UNBOUNDED_X: f64 = 1e12;

/// The time-optimal parameterisation of the path under `constraints`, from rest to rest.
///
/// Fails with [`TimingError::Infeasible`] at the first grid point (from the end) whose
/// controllable set is empty, naming the constraint that binds there.
pub fn time_optimal(constraints: &Constraints) -> Result<TimedPath, TimingError> {
    let n = constraints.grid.len();
    if n < 2 {
        return Ok(TimedPath {
            grid: constraints.grid.clone(),
            sd_squared: vec![0.0; n],
            times: vec![0.0; n],
        });
    }
    let controllable = controllable_sets(constraints)?;
    if controllable[0].0 > TOLERANCE {
        return Err(infeasible(constraints, 0));
    }
    // Forward pass: the largest admissible u that stays controllable.
    let mut x = vec![0.0; n];
    let mut times = vec![0.0; n];
    for i in 0..n - 1 {
        let delta = constraints.grid[i + 1] - constraints.grid[i];
        let (k_lo, k_hi) = controllable[i + 1];
        let u = constraints.largest_u(i, x[i], reach_row(delta, k_lo, k_hi));
        x[i + 1] = (x[i] + 2.0 * delta * u).clamp(k_lo, k_hi).max(0.0);
        let speeds = x[i].sqrt() + x[i + 1].sqrt();
        if speeds <= 0.0 {
            return Err(infeasible(constraints, i + 1));
        }
        times[i + 1] = times[i] + 2.0 * delta / speeds;
    }
    Ok(TimedPath {
        grid: constraints.grid.clone(),
        sd_squared: x,
        times,
    })
}

impl Constraints {
    /// The rows of grid point `i`.
    fn rows_of(&self, i: usize) -> &[Row] {
        &self.rows[i * self.rows_per_point..(i + 1) * self.rows_per_point]
    }

    /// The largest `u` that stage `i`'s rows and the reach row allow at `x` (the smallest of
    /// their upper bounds on `u`; rows whose `u` coefficient vanishes bound `x` only, as in
    /// [`Lines::add`]).
    fn largest_u(&self, i: usize, x: f64, reach: [f64; 4]) -> f64 {
        let bound = |a: f64, b: f64, lo: f64, hi: f64| {
            if bounds_u(a, b) {
                (if a > 0.0 { hi } else { lo } - b * x) / a
            } else {
                f64::INFINITY
            }
        };
        let mut u = self
            .rows_of(i)
            .iter()
            .map(|r| bound(r.a, r.b, r.lo, r.hi))
            .fold(f64::INFINITY, |m, v| if v < m { v } else { m });
        if self.discretization == Discretization::Interpolation && i + 1 < self.grid.len() {
            let two_delta = 2.0 * (self.grid[i + 1] - self.grid[i]);
            for r in self.rows_of(i + 1) {
                u = u.min(bound(r.a + two_delta * r.b, r.b, r.lo, r.hi));
            }
        }
        let [a, b, lo, hi] = reach;
        u.min(bound(a, b, lo, hi))
    }

    /// Stage `i`'s constraints on `(u_i, x_i)` as lines, with the reach row, into `lines`
    /// (emptied first; its buffers are reused from stage to stage).
    fn stage_into(&self, i: usize, reach: [f64; 4], lines: &mut Lines) {
        lines.clear();
        for row in self.rows_of(i) {
            lines.add(row.a, row.b, row.lo, row.hi);
        }
        if self.discretization == Discretization::Interpolation && i + 1 < self.grid.len() {
            // a u + b (x + 2Δu) at the next grid point.
            let two_delta = 2.0 * (self.grid[i + 1] - self.grid[i]);
            for row in self.rows_of(i + 1) {
                lines.add(row.a + two_delta * row.b, row.b, row.lo, row.hi);
            }
        }
        let [a, b, lo, hi] = reach;
        lines.add(a, b, lo, hi);
    }
}

/// `K_i` for every grid point, from the end (at rest) backwards.
fn controllable_sets(constraints: &Constraints) -> Result<Vec<(f64, f64)>, TimingError> {
    let n = constraints.grid.len();
    let mut sets = vec![(0.0, 0.0); n];
    let mut lines = Lines::with_capacity(2 * constraints.rows_per_point + 1);
    for i in (0..n - 1).rev() {
        let delta = constraints.grid[i + 1] - constraints.grid[i];
        let (k_lo, k_hi) = sets[i + 1];
        constraints.stage_into(i, reach_row(delta, k_lo, k_hi), &mut lines);
        let x_max = constraints.x_max[i].0;
        sets[i] = lines
            .x_range(x_max)
            .ok_or_else(|| infeasible(constraints, i))?;
    }
    Ok(sets)
}

/// Whether a row `a u + b x` bounds `u` (else it bounds `x` alone): `|a| > 10⁻¹² max(|a|, |b|)`
/// (a NaN `b` ignored), written with plain comparisons.
fn bounds_u(a: f64, b: f64) -> bool {
    let (abs_a, abs_b) = (a.abs(), b.abs());
    abs_a > 0.0 && (abs_b.is_nan() || abs_a > 1e-12 * abs_b)
}

/// The row `k_lo ≤ x + 2 Δ u ≤ k_hi` as `(a, b, lo, hi)`: the next grid point's
/// controllable set.
fn reach_row(delta: f64, k_lo: f64, k_hi: f64) -> [f64; 4] {
    [2.0 * delta, 1.0, k_lo, k_hi]
}

/// The infeasibility at grid point `i`: the constraint most violated at rest (`u = x = 0`,
/// relative to its bound), or else what bounds `x` there.
fn infeasible(constraints: &Constraints, i: usize) -> TimingError {
    let worst = constraints
        .rows_of(i)
        .iter()
        .map(|r| {
            let scale = r.lo.abs().max(r.hi.abs()).max(f64::MIN_POSITIVE);
            ((r.lo.max(0.0) + (-r.hi).max(0.0)) / scale, r.limit)
        })
        .filter(|(violation, _)| *violation > 0.0)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, limit)| limit)
        .or(constraints.x_max[i].1);
    TimingError::Infeasible {
        grid_point: i,
        s: constraints.grid[i],
        limit: worst,
    }
}

/// The rows of one grid point as lines in `x`: for fixed `x`, each row with `a ≠ 0` bounds
/// `u` above or below by an affine function of `x`; rows with `a = 0` bound `x` alone.
struct Lines {
    /// `u ≤ α + β x`.
    upper: Vec<(f64, f64)>,
    /// `u ≥ α + β x`.
    lower: Vec<(f64, f64)>,
    /// The range of `x` the rows with `a = 0` allow (`None` when one of them allows none).
    x_bounds: Option<(f64, f64)>,
}

impl Lines {
    /// No lines yet (room for `rows`), `x ≥ 0`.
    fn with_capacity(rows: usize) -> Self {
        Lines {
            upper: Vec::with_capacity(rows),
            lower: Vec::with_capacity(rows),
            x_bounds: Some((0.0, f64::INFINITY)),
        }
    }

    /// Back to no lines, `x ≥ 0`.
    fn clear(&mut self) {
        self.upper.clear();
        self.lower.clear();
        self.x_bounds = Some((0.0, f64::INFINITY));
    }

    /// Adds the row `lo ≤ a u + b x ≤ hi`.
    fn add(&mut self, a: f64, b: f64, lo: f64, hi: f64) {
        if bounds_u(a, b) {
            let inverse = 1.0 / a;
            let slope = -b * inverse;
            let upper = (hi * inverse, slope);
            let lower = (lo * inverse, slope);
            let (up, down) = if a > 0.0 {
                (upper, lower)
            } else {
                (lower, upper)
            };
            if up.0.is_finite() {
                self.upper.push(up);
            }
            if down.0.is_finite() {
                self.lower.push(down);
            }
        } else if let Some((x_lo, x_hi)) = self.x_bounds {
            // lo ≤ b x ≤ hi (a row with b = 0 too only needs lo ≤ 0 ≤ hi).
            let slack = TOLERANCE * (lo.abs().max(hi.abs()) + 1.0);
            self.x_bounds = if b.abs() <= f64::MIN_POSITIVE {
                (lo <= slack && hi >= -slack).then_some((x_lo, x_hi))
            } else {
                let (first, second) = (lo / b, hi / b);
                let (below, above) = if b > 0.0 {
                    (first, second)
                } else {
                    (second, first)
                };
                Some((x_lo.max(below), x_hi.min(above)))
            };
        }
    }

    /// The range of `x ∈ [0, x_max]` for which some `u` satisfies every row, or `None`.
    fn x_range(&self, x_max: f64) -> Option<(f64, f64)> {
        let (lo, hi) = self.x_bounds?;
        // Without a bound on x alone, the search starts far beyond any physical speed.
        let hi = hi.min(x_max).min(UNBOUNDED_X);
        let slack = TOLERANCE * (1.0 + hi.abs().min(1e12));
        if lo > hi + slack {
            return None;
        }
        let hi = self.pairwise_bound(hi.max(lo)).max(lo);
        let right = self.feasible_end(hi, lo, Side::Left)?;
        let left = self.feasible_end(lo, right, Side::Right)?;
        Some((left.min(right), right))
    }

    /// `hi` lowered to the largest `x` at which the last upper line stays above every lower
    /// line and every upper line above the last lower one. Any pair of lines bounds the
    /// feasible `x` (`α_u + β_u x ≥ α_l + β_l x`), so this is an upper bound of the largest
    /// feasible `x`; with the reach row last (`stage_into`), whose lines are the steepest, it
    /// is usually that `x` itself, and the Newton steps from it end at once.
    fn pairwise_bound(&self, mut hi: f64) -> f64 {
        let (Some(&last_up), Some(&last_down)) = (self.upper.last(), self.lower.last()) else {
            return hi;
        };
        let pairs = self
            .lower
            .iter()
            .map(|&down| (last_up, down))
            .chain(self.upper.iter().map(|&up| (up, last_down)));
        for ((alpha_u, beta_u), (alpha_l, beta_l)) in pairs {
            // (β_u − β_l) x ≥ α_l − α_u bounds x above where β_u < β_l.
            let (slope, gap) = (beta_u - beta_l, alpha_l - alpha_u);
            if slope < 0.0 && gap > hi * slope {
                hi = gap / slope;
            }
        }
        hi
    }

    /// From `start`, Newton steps towards `limit` on the slack `g(x) = min upper − max
    /// lower` (concave, piecewise linear) until `g(x) ≥ 0`: the feasible end of the interval
    /// on the side of `start`, or `None` when there is none before `limit`.
    fn feasible_end(&self, start: f64, limit: f64, side: Side) -> Option<f64> {
        let mut x = start;
        let steps = 2 * (self.upper.len() + self.lower.len()) + 4;
        for _ in 0..steps {
            let up = binding(&self.upper, x, Bound::Upper);
            let down = binding(&self.lower, x, Bound::Lower);
            let gap = up - down;
            let scale = 1.0 + up.abs().min(1e300) + down.abs().min(1e300);
            if gap >= -TOLERANCE * scale || gap.is_nan() {
                return (!gap.is_nan()).then_some(x);
            }
            // g grows towards `limit` only when it falls (Left) or rises (Right) at x.
            let slope = active_slope(&self.upper, x, up, side, Bound::Upper)
                - active_slope(&self.lower, x, down, side, Bound::Lower);
            let next = match side {
                Side::Left if slope < 0.0 => x - gap / slope,
                Side::Right if slope > 0.0 => x - gap / slope,
                _ => return None,
            };
            let past = match side {
                Side::Left => next < limit - TOLERANCE * (1.0 + limit.abs()),
                Side::Right => next > limit + TOLERANCE * (1.0 + limit.abs()),
            };
            if past {
                return None;
            }
            x = match side {
                Side::Left => next.max(limit),
                Side::Right => next.min(limit),
            };
        }
        None
    }
}

/// Which way a Newton step moves.
#[derive(Clone, Copy)]
enum Side {
    /// Towards smaller `x` (looking for the largest feasible `x`).
    Left,
    /// Towards larger `x`.
    Right,
}

/// Whether lines are upper bounds (their minimum binds) or lower bounds (their maximum).
#[derive(Clone, Copy, PartialEq)]
enum Bound {
    Upper,
    Lower,
}

/// The binding value of `lines` at `x`: the smallest upper line's, the largest lower
/// line's (`±∞` without lines).
fn binding(lines: &[(f64, f64)], x: f64, bound: Bound) -> f64 {
    let values = lines.iter().map(|&(alpha, beta)| alpha + beta * x);
    // Plain comparisons (a NaN value never binds), cheaper than `f64::min`'s.
    match bound {
        Bound::Upper => values.fold(f64::INFINITY, |m, v| if v < m { v } else { m }),
        Bound::Lower => values.fold(f64::NEG_INFINITY, |m, v| if v > m { v } else { m }),
    }
}

/// The slope of the line of `lines` that binds just beyond `x` on `side`, `value` being their
/// binding value at `x` ([`binding`]): among the lines through (within rounding of) that
/// value, the one that stays binding on that side (0 without lines).
fn active_slope(lines: &[(f64, f64)], x: f64, value: f64, side: Side, bound: Bound) -> f64 {
    // Just left of x, the upper line with the largest slope is the smallest and the lower
    // line with the smallest slope the largest; mirrored to the right.
    let steepest = matches!(
        (side, bound),
        (Side::Left, Bound::Upper) | (Side::Right, Bound::Lower)
    );
    let through = lines.iter().filter(|&&(alpha, beta)| {
        let at = alpha + beta * x;
        (at - value).abs() <= 1e-14 * (at.abs() + value.abs() + 1.0)
    });
    let slopes = through.map(|&(_, beta)| beta);
    let slope = if steepest {
        slopes.fold(f64::NEG_INFINITY, f64::max)
    } else {
        slopes.fold(f64::INFINITY, f64::min)
    };
    if slope.is_finite() {
        slope
    } else {
        0.0
    }
}

#[cfg(test)]
mod projection_tests {
    use super::*;

    /// The largest x with some u between every lower and upper line, by brute force over the
    /// vertices (pairwise intersections and the bounds).
    fn brute_max(lines: &Lines, x_max: f64) -> Option<f64> {
        let (lo, hi) = lines.x_bounds?;
        let hi = hi.min(x_max).min(UNBOUNDED_X);
        let feasible = |x: f64| {
            let up = lines
                .upper
                .iter()
                .map(|(a, b)| a + b * x)
                .fold(f64::INFINITY, f64::min);
            let down = lines
                .lower
                .iter()
                .map(|(a, b)| a + b * x)
                .fold(f64::NEG_INFINITY, f64::max);
            up - down >= -1e-9 * (1.0 + up.abs() + down.abs())
        };
        let mut candidates = vec![lo, hi];
        for (a1, b1) in &lines.upper {
            for (a2, b2) in &lines.lower {
                if (b1 - b2).abs() > 0.0 {
                    candidates.push((a2 - a1) / (b1 - b2));
                }
            }
        }
        candidates
            .into_iter()
            .filter(|x| *x >= lo - 1e-12 && *x <= hi + 1e-12 && feasible(*x))
            .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x))))
    }

    #[test]
    fn newton_equals_brute_force_on_random_stages() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(5);
        let mut checked = 0;
        for _ in 0..20000 {
            let mut lines = Lines::with_capacity(12);
            for _ in 0..rng.random_range(1..10) {
                let a: f64 = rng.random_range(-2.0..2.0);
                let b: f64 = rng.random_range(-2.0..2.0);
                let w: f64 = rng.random_range(0.1..3.0);
                let c: f64 = rng.random_range(-0.5..0.5);
                lines.add(a, b, c - w, c + w);
            }
            lines.add(0.1, 1.0, 0.0, rng.random_range(0.0..5.0));
            let x_max = rng.random_range(0.5..10.0);
            let ours = lines.x_range(x_max).map(|r| r.1);
            let brute = brute_max(&lines, x_max);
            match (ours, brute) {
                (Some(o), Some(b)) => {
                    assert!((o - b).abs() <= 1e-7 * (1.0 + b.abs()), "{o} vs {b}");
                    checked += 1;
                }
                (None, None) => {}
                other => panic!("{other:?}"),
            }
        }
        assert!(checked > 1000);
    }
}
