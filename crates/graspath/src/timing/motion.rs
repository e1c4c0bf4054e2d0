//! The constraints of a robot's joint path on a grid, and its time-optimal motion.
//!
//! At a grid point with `q(s)`, `q'(s)`, `q''(s)` from the spline:
//! * a joint velocity limit `|q'_j ṡ| ≤ v_j` bounds `x = ṡ²` by `(v_j / |q'_j|)²`;
//! * a joint acceleration limit is the row `−a_j ≤ q'_j u + q''_j x ≤ a_j`;
//! * a torque limit is the row `−τ_j ≤ a_j u + b_j x + c_j ≤ τ_j`, from the inverse dynamics
//!   `τ = M(q) q̈ + C(q, q̇) q̇ + g(q)` with `q̇ = q' ṡ` and `q̈ = q' u + q'' x`:
//!   `c = g(q) = rnea(q, 0, 0)`, `a = M(q) q' = rnea(q, 0, q') − c`,
//!   `b = M(q) q'' + C(q, q') q' = rnea(q, q', q'') − c` (payload included);
//! * a limit on a carried body's linear or angular speed bounds `x` by
//!   `(v_max / ‖v_body(q, q')‖)²`, its velocity per unit `ṡ` from the Jacobian;
//! * a limit on its linear or angular acceleration `‖w(s) u + w'(s) x‖ ≤ a_max` (`w` the
//!   body's velocity per unit `ṡ`, `w'` its derivative along the path) is a cone, not a row:
//!   it is imposed as rows `|dᵢ · (w u + w' x)| ≤ a_max cos γ` over the 13 directions `dᵢ` of
//!   a cube's faces, edges and corners, whose 26 points (±) cover the sphere within
//!   `γ = 27.57°`. Those rows keep `‖·‖ ≤ a_max` (an inner approximation, up to 11 % below the
//!   limit in the worst direction); the exact norm is checked between grid points.

use super::spline::{JointSpline, PathPoint};
use super::topp::{time_optimal, Constraints, Discretization, Limit, Row, TimedPath};
use super::TimingError;
use crate::robot::{Chain, Dynamics, RigidBody};
use nalgebra::{DVector, Matrix6xX, Vector3};

/// The limits a joint path is timed under. Slices hold one entry per joint of the chain;
/// `None` is unlimited.
#[derive(Debug, Clone, Copy)]
pub struct PathLimits<'a> {
    /// Joint velocity limits (rad/s or m/s).
    pub velocity: &'a [Option<f64>],
    /// Joint acceleration limits (rad/s² or m/s²).
    pub acceleration: &'a [Option<f64>],
    /// Joint torque limits through the arm's dynamics, when they apply.
    pub torque: Option<TorqueLimits<'a>>,
    /// Limits on the carried object's own speed and acceleration, when they apply.
    pub object: Option<ObjectLimits<'a>>,
    /// Grid intervals per spline interval (at least 1): the grid is the spline's knots with
    /// every interval split into this many equal parts.
    pub subdivisions: usize,
    /// Where each stage's constraints are imposed.
    pub discretization: Discretization,
}

/// Joint torque limits and the dynamics that turn a motion into torques.
#[derive(Debug, Clone, Copy)]
pub struct TorqueLimits<'a> {
    /// The arm's dynamics (gravity included).
    pub dynamics: &'a Dynamics,
    /// Joint torque (force) limits (N·m or N).
    pub effort: &'a [Option<f64>],
    /// The body the tool carries, in the tool frame (kg, m, kg·m²), when it carries one.
    pub payload: Option<RigidBody>,
}

/// Limits on the motion of a body carried by the tool (a cup of coffee, a tray of parts): its
/// origin's linear speed and acceleration, and its angular speed and acceleration (base frame),
/// from the chain's kinematics. The body's velocity is `w(s) ṡ` with `w = J(q) q'(s)` (moved to
/// the body's origin), so the speeds bound `x = ṡ²` alone and the accelerations
/// `w(s) u + w'(s) x` are rows in `(u, x)`.
#[derive(Debug, Clone, Copy)]
pub struct ObjectLimits<'a> {
    /// The chain (its tool frame carries the body).
    pub chain: &'a Chain,
    /// The body's origin in the tool frame (m).
    pub origin_in_tool: Vector3<f64>,
    /// The largest linear speed of the body's origin (m/s).
    pub linear: Option<f64>,
    /// The largest angular speed of the body (rad/s).
    pub angular: Option<f64>,
    /// The largest linear acceleration of the body's origin (m/s²).
    pub linear_acceleration: Option<f64>,
    /// The largest angular acceleration of the body (rad/s²).
    pub angular_acceleration: Option<f64>,
}

/// The 13 directions (and their opposites) of a cube's face centres, edge midpoints and
/// corners, unnormalised: the acceleration cone's rows.
const CUBE_DIRECTIONS: [[f64; 3]; 13] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, 1.0, -1.0],
    [1.0, 1.0, 1.0],
    [1.0, 1.0, -1.0],
    [1.0, -1.0, 1.0],
    [1.0, -1.0, -1.0],
];

/// `cos γ`, `γ` the largest angle between a unit vector and the nearest of the 26 points
/// `±CUBE_DIRECTIONS`: the circumradius of the spherical triangle face–edge–corner that tiles
/// the sphere 48 times, `1 / ‖(1, √2 − 1, √3 − √2)‖` (γ = 27.57°; a test recomputes it).
const CUBE_COVER_COS: f64 = 0.886_451_886_282_891_3;

/// The relative step (of the path's parameter span) of the central differences of the
/// body's velocity along the path.
const BODY_RATE_STEP: f64 = 1e-6;

/// A carried body's velocity per unit `ṡ` at a path point and its derivative along the path
/// (base frame): linear `p'`, `p''` of its origin and angular `w`, `w'`.
#[derive(Debug, Clone, Copy)]
struct BodyRates {
    linear: Vector3<f64>,
    linear_rate: Vector3<f64>,
    angular: Vector3<f64>,
    angular_rate: Vector3<f64>,
}

impl BodyRates {
    /// The linear and angular acceleration at path acceleration `u` and `x = ṡ²`.
    fn accelerations(&self, u: f64, x: f64) -> (Vector3<f64>, Vector3<f64>) {
        (
            self.linear * u + self.linear_rate * x,
            self.angular * u + self.angular_rate * x,
        )
    }
}

impl<'a> ObjectLimits<'a> {
    /// These limits, when at least one is set.
    pub fn any(self) -> Option<Self> {
        [
            self.linear,
            self.angular,
            self.linear_acceleration,
            self.angular_acceleration,
        ]
        .iter()
        .any(Option::is_some)
        .then_some(self)
    }

    /// Whether an acceleration limit is set.
    fn limits_acceleration(&self) -> bool {
        self.linear_acceleration.is_some() || self.angular_acceleration.is_some()
    }

    /// The acceleration limits that are set, with what each limits.
    fn acceleration_limits(&self) -> impl Iterator<Item = (f64, Limit, bool)> {
        [
            (self.linear_acceleration, Limit::ObjectAcceleration, true),
            (
                self.angular_acceleration,
                Limit::ObjectAngularAcceleration,
                false,
            ),
        ]
        .into_iter()
        .filter_map(|(limit, which, linear)| limit.map(|l| (l, which, linear)))
    }

    /// The body's linear and angular velocity per unit `ṡ` at `q` moving along `dq`, using
    /// `jacobian` as the workspace.
    fn velocity(
        &self,
        q: &[f64],
        dq: &[f64],
        jacobian: &mut Matrix6xX<f64>,
    ) -> Result<(Vector3<f64>, Vector3<f64>), TimingError> {
        let pose = self.chain.pose_and_jacobian_into(q, jacobian)?;
        let twist = &*jacobian * DVector::from_column_slice(dq);
        let v_tool = Vector3::new(twist[0], twist[1], twist[2]);
        let omega = Vector3::new(twist[3], twist[4], twist[5]);
        let lever = pose.rotation * self.origin_in_tool;
        Ok((v_tool + omega.cross(&lever), omega))
    }

    /// The body's velocity per unit `ṡ` at `s` on `spline` (given: `velocity`, from
    /// [`ObjectLimits::velocity`]) and its derivative along the path, by central differences
    /// of the velocity (one-sided at the path's ends); `scratch` holds the path points.
    fn rates(
        &self,
        spline: &JointSpline,
        s: f64,
        (linear, angular): (Vector3<f64>, Vector3<f64>),
        scratch: &mut PathScratch,
        jacobian: &mut Matrix6xX<f64>,
    ) -> Result<BodyRates, TimingError> {
        let knots = spline.knots();
        let (first, last) = (knots[0], knots[knots.len() - 1]);
        let step = BODY_RATE_STEP * (last - first).max(f64::MIN_POSITIVE);
        let mut velocity_at = |s: f64| {
            spline.evaluate_into(
                s,
                PathPoint {
                    q: &mut scratch.q,
                    dq: &mut scratch.dq,
                    ddq: &mut scratch.ddq,
                },
            );
            self.velocity(&scratch.q, &scratch.dq, jacobian)
        };
        let (before, after) = ((s - step).max(first), (s + step).min(last));
        let (linear_before, angular_before) = velocity_at(before)?;
        let (linear_after, angular_after) = velocity_at(after)?;
        let span = after - before;
        Ok(BodyRates {
            linear,
            linear_rate: (linear_after - linear_before) / span,
            angular,
            angular_rate: (angular_after - angular_before) / span,
        })
    }

    /// The rows of the acceleration limits at `s`, whose body rates are `rates` (see the
    /// module documentation).
    fn acceleration_rows(&self, rates: &BodyRates, rows: &mut Vec<Row>) {
        let directions = CUBE_DIRECTIONS.map(|d| Vector3::from(d).normalize());
        for (limit, which, linear) in self.acceleration_limits() {
            let (w, w_rate) = if linear {
                (rates.linear, rates.linear_rate)
            } else {
                (rates.angular, rates.angular_rate)
            };
            let bound = limit * CUBE_COVER_COS;
            for d in &directions {
                rows.push(Row {
                    a: d.dot(&w),
                    b: d.dot(&w_rate),
                    lo: -bound,
                    hi: bound,
                    limit: which,
                });
            }
        }
    }

    /// The number of rows [`ObjectLimits::acceleration_rows`] adds at a grid point.
    fn acceleration_row_count(&self) -> usize {
        self.acceleration_limits().count() * CUBE_DIRECTIONS.len()
    }

    /// The largest `x` the speed limits allow for the body's velocity per unit `ṡ`
    /// `(linear, angular)`, and which limit sets it.
    fn bound(&self, (linear, angular): (Vector3<f64>, Vector3<f64>)) -> (f64, Option<Limit>) {
        let (linear, angular) = (linear.norm(), angular.norm());
        let mut bound = (f64::INFINITY, None);
        for (limit, speed, which) in [
            (self.linear, linear, Limit::ObjectSpeed),
            (self.angular, angular, Limit::ObjectTurnRate),
        ] {
            if let Some(limit) = limit {
                let x = (limit / speed).powi(2);
                if x < bound.0 {
                    bound = (x, Some(which));
                }
            }
        }
        bound
    }
}

/// The path point buffers (`q`, `q'`, `q''`) of [`ObjectLimits::rates`], allocated once per
/// timing.
struct PathScratch {
    q: Vec<f64>,
    dq: Vec<f64>,
    ddq: Vec<f64>,
}

impl PathScratch {
    fn new(dof: usize) -> Self {
        Self {
            q: vec![0.0; dof],
            dq: vec![0.0; dof],
            ddq: vec![0.0; dof],
        }
    }
}

impl PathLimits<'_> {
    /// The fastest motion along `spline` from rest to rest within these limits: the
    /// reachability analysis on the grid ([`time_optimal`]), then checked between the grid
    /// points ([`PathLimits::slowdown`]) and slowed uniformly where the limits need it.
    pub fn time(&self, spline: &JointSpline) -> Result<TimedPath, TimingError> {
        let timed = time_optimal(&self.constraints(spline)?)?;
        let factor = self.slowdown(spline, &timed)?;
        Ok(if factor > 1.0 {
            timed.slowed(factor)
        } else {
            timed
        })
    }

    /// How much slower (`≥ 1`) `timed` must run for every limit to hold between its grid
    /// points too. The reachability analysis imposes the limits at the grid points; between
    /// them the path acceleration `u` is constant while `q'(s)` and `q''(s)` vary, so a joint
    /// can exceed its limit there by a few per cent on a coarse grid.
    ///
    /// Joint velocities and accelerations are bounded exactly over each grid interval: there
    /// `x = ṡ²` is linear in `s`, `q'` quadratic and `q''` linear (one cubic piece of a C²
    /// spline), so `q̈ = q' u + q'' x` is a quadratic and `q̇² = q'² x` a quintic whose
    /// extrema are closed-form (`quadratic_peak`, `speed_peak`). The carried object's
    /// speeds are checked at the eighth points of every interval, torques at its middle. A
    /// uniform slow-down by `k` divides velocities by `k` and accelerations by `k²`, and moves
    /// each torque to `g + (τ − g)/k²` ([`TimedPath::slowed`]).
    pub fn slowdown(&self, spline: &JointSpline, timed: &TimedPath) -> Result<f64, TimingError> {
        self.slowdown_between(spline, timed, f64::NEG_INFINITY, f64::INFINITY)
    }

    /// [`PathLimits::slowdown`] over the grid intervals that lie in `[from, to]` only (a part
    /// of a motion timed as one, whose other parts have other limits: the carry, with the
    /// object's weight, between the grasp and the place).
    pub fn slowdown_between(
        &self,
        spline: &JointSpline,
        timed: &TimedPath,
        from: f64,
        to: f64,
    ) -> Result<f64, TimingError> {
        let dof = spline.dof();
        let torqued: Vec<(usize, f64)> = self.torque.map_or(Vec::new(), |t| limited(t.effort));
        let mut dynamics = match &self.torque {
            Some(t) if !torqued.is_empty() => {
                let mut data = t.dynamics.data();
                data.set_payload(t.payload)?;
                Some((t.dynamics, data))
            }
            _ => None,
        };
        let [mut q, mut qd, mut qdd, mut tau, mut g, mut a, mut b] =
            std::array::from_fn(|_| vec![0.0; dof]);
        // The path `q'`, `q''` at an interval's start, middle (with `q`) and end.
        let [mut dq0, mut ddq0, mut qm, mut dqm, mut ddqm, mut dq1, mut ddq1] =
            std::array::from_fn(|_| vec![0.0; dof]);
        let mut jacobian = Matrix6xX::zeros(dof);
        let mut scratch = PathScratch::new(dof);
        let evaluate = |s: f64, q: &mut [f64], dq: &mut [f64], ddq: &mut [f64]| {
            spline.evaluate_into(s, PathPoint { q, dq, ddq });
        };
        // The smallest k², from velocities (k² ≥ ratio²), accelerations and torques.
        let mut k2: f64 = 1.0;
        // Where the last interval checked ended (its end's `q'`, `q''` are the next start's).
        let mut previous_end = None;
        for i in 0..timed.grid.len().saturating_sub(1) {
            let (s0, s1) = (timed.grid[i], timed.grid[i + 1]);
            if s0 < from || s1 > to {
                continue;
            }
            let (x0, x1) = (
                timed.sd_squared[i].max(0.0),
                timed.sd_squared[i + 1].max(0.0),
            );
            let u = (x1 - x0) / (2.0 * (s1 - s0));
            if previous_end == Some(s0) {
                std::mem::swap(&mut dq0, &mut dq1);
                std::mem::swap(&mut ddq0, &mut ddq1);
            } else {
                evaluate(s0, &mut q, &mut dq0, &mut ddq0);
            }
            evaluate(s1, &mut q, &mut dq1, &mut ddq1);
            previous_end = Some(s1);
            evaluate(0.5 * (s0 + s1), &mut qm, &mut dqm, &mut ddqm);
            for j in 0..dof {
                if let Some(v) = self.velocity[j] {
                    let peak = speed_peak([dq0[j], dqm[j], dq1[j]], [x0, x1]);
                    k2 = k2.max(peak / (v * v));
                }
                if let Some(a) = self.acceleration[j] {
                    let at = |dq: f64, ddq: f64, x: f64| dq * u + ddq * x;
                    let peak = quadratic_peak([
                        at(dq0[j], ddq0[j], x0),
                        at(dqm[j], ddqm[j], 0.5 * (x0 + x1)),
                        at(dq1[j], ddq1[j], x1),
                    ]);
                    k2 = k2.max(peak / a);
                }
            }
            if let Some(object) = &self.object {
                for k in 1..OBJECT_CHECKS_PER_INTERVAL {
                    let fraction = k as f64 / OBJECT_CHECKS_PER_INTERVAL as f64;
                    let s = s0 + fraction * (s1 - s0);
                    let x = x0 + fraction * (x1 - x0);
                    let sd = x.sqrt();
                    evaluate(s, &mut q, &mut qd, &mut qdd);
                    let velocity = object.velocity(&q, &qd, &mut jacobian)?;
                    for (limit, speed) in [
                        (object.linear, velocity.0.norm()),
                        (object.angular, velocity.1.norm()),
                    ] {
                        if let Some(limit) = limit {
                            k2 = k2.max((speed * sd / limit).powi(2));
                        }
                    }
                    // A uniform slow-down by k divides both `u` and `x`, so the
                    // acceleration, by k².
                    if object.limits_acceleration() {
                        let rates =
                            object.rates(spline, s, velocity, &mut scratch, &mut jacobian)?;
                        let (linear, angular) = rates.accelerations(u, x);
                        for (limit, _, is_linear) in object.acceleration_limits() {
                            let norm = if is_linear { linear } else { angular }.norm();
                            k2 = k2.max(norm / limit);
                        }
                    }
                }
            }
            if let Some((model, data)) = dynamics.as_mut() {
                let x = 0.5 * (x0 + x1);
                // τ = a s̈ + b ṡ² + g with s̈ = u and ṡ² = x.
                model.path_torques_into(data, &qm, &dqm, &ddqm, &mut g, &mut a, &mut b)?;
                for j in 0..dof {
                    tau[j] = a[j] * u + b[j] * x + g[j];
                }
                for &(j, limit) in &torqued {
                    // g + (τ − g)/k² within ±limit, with g itself within it.
                    let bound = if tau[j] > limit {
                        limit
                    } else if tau[j] < -limit {
                        -limit
                    } else {
                        continue;
                    };
                    let room = bound - g[j];
                    if room * bound <= 0.0 {
                        return Err(TimingError::Infeasible {
                            grid_point: i,
                            s: 0.5 * (s0 + s1),
                            limit: Some(Limit::Torque(j)),
                        });
                    }
                    k2 = k2.max((tau[j] - g[j]) / room);
                }
            }
        }
        Ok(k2.sqrt())
    }

    /// The grid of `spline` (see [`PathLimits::subdivisions`]) and the constraints at each of
    /// its points.
    pub fn constraints(&self, spline: &JointSpline) -> Result<Constraints, TimingError> {
        let dof = spline.dof();
        self.check(dof)?;
        let grid = grid(spline.knots(), self.subdivisions.max(1));
        let accelerated: Vec<(usize, f64)> = limited(self.acceleration);
        let torqued: Vec<(usize, f64)> = self.torque.map_or(Vec::new(), |t| limited(t.effort));
        let object_rows = self
            .object
            .as_ref()
            .map_or(0, ObjectLimits::acceleration_row_count);
        let rows_per_point = accelerated.len() + torqued.len() + object_rows;
        let mut rows = Vec::with_capacity(grid.len() * rows_per_point);
        let mut x_max = Vec::with_capacity(grid.len());
        let mut dynamics = match &self.torque {
            Some(t) => {
                let mut data = t.dynamics.data();
                data.set_payload(t.payload)?;
                Some((t.dynamics, data))
            }
            None => None,
        };
        let [mut q, mut dq, mut ddq, mut g, mut a, mut b] = std::array::from_fn(|_| vec![0.0; dof]);
        let mut jacobian = Matrix6xX::zeros(dof);
        let mut scratch = PathScratch::new(dof);
        for &s in &grid {
            spline.evaluate_into(
                s,
                PathPoint {
                    q: &mut q,
                    dq: &mut dq,
                    ddq: &mut ddq,
                },
            );
            let mut bound = velocity_bound(self.velocity, &dq);
            // The carried body's velocity per unit `ṡ`, with the derivative along the path
            // when an acceleration limit needs it.
            let mut rates = None;
            if let Some(object) = &self.object {
                let velocity = object.velocity(&q, &dq, &mut jacobian)?;
                let by_object = object.bound(velocity);
                if by_object.0 < bound.0 {
                    bound = by_object;
                }
                if object.limits_acceleration() {
                    rates = Some(object.rates(spline, s, velocity, &mut scratch, &mut jacobian)?);
                }
            }
            x_max.push(bound);
            for &(j, limit) in &accelerated {
                rows.push(Row {
                    a: dq[j],
                    b: ddq[j],
                    lo: -limit,
                    hi: limit,
                    limit: Limit::Acceleration(j),
                });
            }
            if let Some((model, data)) = dynamics.as_mut() {
                // τ = a s̈ + b ṡ² + g.
                model.path_torques_into(data, &q, &dq, &ddq, &mut g, &mut a, &mut b)?;
                for &(j, limit) in &torqued {
                    rows.push(Row {
                        a: a[j],
                        b: b[j],
                        lo: -limit - g[j],
                        hi: limit - g[j],
                        limit: Limit::Torque(j),
                    });
                }
            }
            if let (Some(object), Some(rates)) = (&self.object, &rates) {
                object.acceleration_rows(rates, &mut rows);
            }
        }
        Ok(Constraints {
            discretization: self.discretization,
            grid,
            x_max,
            rows_per_point,
            rows,
        })
    }

    /// Every slice one entry per joint, every limit a positive number.
    fn check(&self, dof: usize) -> Result<(), TimingError> {
        let mut lists = vec![
            ("velocity", self.velocity),
            ("acceleration", self.acceleration),
        ];
        if let Some(t) = &self.torque {
            lists.push(("torque", t.effort));
            if t.dynamics.dof() != dof {
                return Err(TimingError::BadPath(format!(
                    "the path has {dof} joints, the dynamics {}",
                    t.dynamics.dof()
                )));
            }
        }
        for (what, list) in lists {
            if list.len() != dof {
                return Err(TimingError::BadPath(format!(
                    "{} {what} limits for a path of {dof} joints",
                    list.len()
                )));
            }
            if let Some((joint, value)) = list
                .iter()
                .enumerate()
                .find_map(|(j, v)| v.filter(|v| !(*v > 0.0 && v.is_finite())).map(|v| (j, v)))
            {
                return Err(TimingError::BadLimit { joint, what, value });
            }
        }
        Ok(())
    }
}

/// Equal parts of a grid interval whose inner points check the carried object's speeds: its
/// velocity `J(q) q'(s) ṡ` is not a polynomial in `s`, so it is sampled (at eighths: within
/// 0.2 % of the limit at 500 Hz on the optimised motion of `tests/timing_selection.rs`, where
/// quarters gave 1.9 %).
const OBJECT_CHECKS_PER_INTERVAL: usize = 8;

/// The largest `|p(f)|` over `f ∈ [0, 1]` of the quadratic `p` through `p(0)`, `p(½)` and
/// `p(1)` (the three values): at an end or at the vertex.
fn quadratic_peak([p0, pm, p1]: [f64; 3]) -> f64 {
    let [a, b, c] = quadratic_through([p0, pm, p1]);
    let mut peak = p0.abs().max(p1.abs());
    if a != 0.0 {
        let f = -b / (2.0 * a);
        if f > 0.0 && f < 1.0 {
            peak = peak.max((c + f * (b + f * a)).abs());
        }
    }
    peak
}

/// The coefficients `[a, b, c]` of `p(f) = a f² + b f + c` through `p(0)`, `p(½)`, `p(1)`.
fn quadratic_through([p0, pm, p1]: [f64; 3]) -> [f64; 3] {
    let a = 2.0 * (p0 - 2.0 * pm + p1);
    [a, p1 - p0 - a, p0]
}

/// The largest `q'(f)² x(f)` over `f ∈ [0, 1]`, the squared joint speed over a grid
/// interval, with `q'` the quadratic through `dq` (at `f` = 0, ½, 1) and `x` linear from
/// `x[0]` to `x[1]`. Its interior extrema solve `(q'² x)' = q' (2 q'' x + q' x') = 0`; the
/// roots of `q'` are minima, the others those of the quadratic
/// `5 a d f² + (4 a x₀ + 3 b d) f + 2 b x₀ + c d` (with `q' = a f² + b f + c`, `x = x₀ + d f`).
fn speed_peak(dq: [f64; 3], [x0, x1]: [f64; 2]) -> f64 {
    let [a, b, c] = quadratic_through(dq);
    let d = x1 - x0;
    let at = |f: f64| {
        let v = c + f * (b + f * a);
        v * v * (x0 + d * f)
    };
    let mut peak = at(0.0).max(at(1.0));
    let roots = quadratic_roots(
        5.0 * a * d,
        4.0 * a * x0 + 3.0 * b * d,
        2.0 * b * x0 + c * d,
    );
    for f in roots.into_iter().flatten() {
        if f > 0.0 && f < 1.0 {
            peak = peak.max(at(f));
        }
    }
    peak
}

/// The real roots of `a f² + b f + c` (a linear equation when `a` vanishes against `b`).
fn quadratic_roots(a: f64, b: f64, c: f64) -> [Option<f64>; 2] {
    if a == 0.0 || a.abs() <= 1e-12 * b.abs() {
        return [(b != 0.0).then(|| -c / b), None];
    }
    let discriminant = b * b - 4.0 * a * c;
    if discriminant < 0.0 {
        return [None, None];
    }
    // The numerically stable pair.
    let w = -0.5 * (b + b.signum() * discriminant.sqrt());
    [Some(w / a), (w != 0.0).then(|| c / w)]
}

/// The knots with every interval split into `parts` equal parts.
fn grid(knots: &[f64], parts: usize) -> Vec<f64> {
    let mut grid = Vec::with_capacity((knots.len().saturating_sub(1)) * parts + 1);
    for pair in knots.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        grid.extend((0..parts).map(|k| a + (b - a) * k as f64 / parts as f64));
    }
    grid.extend(knots.last());
    grid
}

/// The joints with a limit, and the limit.
fn limited(limits: &[Option<f64>]) -> Vec<(usize, f64)> {
    limits
        .iter()
        .enumerate()
        .filter_map(|(j, l)| l.map(|l| (j, l)))
        .collect()
}

/// The largest `x = ṡ²` the velocity limits allow where the path's derivative is `dq`, and
/// the joint that sets it.
fn velocity_bound(limits: &[Option<f64>], dq: &[f64]) -> (f64, Option<Limit>) {
    let mut bound = (f64::INFINITY, None);
    for (j, (limit, d)) in limits.iter().zip(dq).enumerate() {
        if let Some(v) = limit {
            let x = (v / d.abs()).powi(2);
            if x < bound.0 {
                bound = (x, Some(Limit::Velocity(j)));
            }
        }
    }
    bound
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, RngExt, SeedableRng};

    /// The largest of `g` over a fine grid of `[0, 1]`: the brute-force oracle.
    fn brute_max(g: impl Fn(f64) -> f64) -> f64 {
        (0..=100_000)
            .map(|k| g(k as f64 / 100_000.0))
            .fold(0.0, f64::max)
    }

    #[test]
    fn the_closed_form_peaks_match_a_brute_force_search() {
        let mut rng = StdRng::seed_from_u64(7);
        for _ in 0..500 {
            let mut r = || rng.random_range(-1.0..1.0);
            let [a, b, c] = [r(), r(), r()];
            let p = |f: f64| a * f * f + b * f + c;
            let (x0, x1) = (r().abs(), r().abs());
            let exact = quadratic_peak([p(0.0), p(0.5), p(1.0)]);
            let brute = brute_max(|f| p(f).abs());
            assert!(
                exact >= brute - 1e-12 && exact <= brute + 1e-9,
                "{exact} {brute}"
            );
            let exact = speed_peak([p(0.0), p(0.5), p(1.0)], [x0, x1]);
            let brute = brute_max(|f| p(f) * p(f) * (x0 + (x1 - x0) * f));
            assert!(
                exact >= brute - 1e-12 && exact <= brute + 1e-9,
                "{exact} {brute}"
            );
        }
    }

    /// The nearest of the 26 points `±CUBE_DIRECTIONS` to `v` (unit): its cosine.
    fn nearest_cos(v: &Vector3<f64>) -> f64 {
        CUBE_DIRECTIONS
            .iter()
            .map(|d| Vector3::from(*d).normalize().dot(v).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn the_cube_directions_cover_the_sphere_within_the_stated_angle() {
        // Closed form: the circumcentre of the spherical triangle face–edge–corner.
        let s = Vector3::new(1.0, 2f64.sqrt() - 1.0, 3f64.sqrt() - 2f64.sqrt());
        assert!((1.0 / s.norm() - CUBE_COVER_COS).abs() < 1e-15);
        // That point is as far as the stated angle from all 26, ...
        assert!((nearest_cos(&s.normalize()) - CUBE_COVER_COS).abs() < 1e-12);
        // ... and no unit vector of a fine grid on the sphere is farther.
        let n = 400;
        for i in 0..=n {
            let polar = std::f64::consts::PI * i as f64 / n as f64;
            for j in 0..2 * n {
                let azimuth = std::f64::consts::PI * j as f64 / n as f64;
                let v = Vector3::new(
                    polar.sin() * azimuth.cos(),
                    polar.sin() * azimuth.sin(),
                    polar.cos(),
                );
                assert!(nearest_cos(&v) >= CUBE_COVER_COS - 1e-12, "{v:?}");
            }
        }
    }
}
