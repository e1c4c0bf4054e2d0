//! The time a branch's whole motion takes: its joint samples as cubic splines, timed by
//! TOPP-RA under the joints' velocity and acceleration limits and, with the object's mass, the
//! torque limits with the arm carrying it ([`crate::timing`]). With `timing.stops` (the
//! default) the approach, the carry and the retreat are three motions from rest to rest (the
//! gripper closes at the grasp and opens at the place); otherwise one motion through all.
//! A motion no timing can keep within the limits is refused (`timing_infeasible`), and so is
//! a smoothed motion that leaves a joint's range between samples (`joint_limit`).

use super::branch_checks::{BranchCheck, BranchFindings};
use super::Scoring;
use crate::failure::{Failure, FailureReason, Phase};
use crate::robot::{Dynamics, RigidBody};
use crate::task::TimingSettings;
use crate::timing::{
    Constraints, JointSpline, Limit, PathLimits, PathPoint, TimedPath, TimingError, TorqueLimits,
};
use std::ops::Range;

/// How far (rad or m) a smoothed motion may leave a joint's range between samples: rounding.
pub const SPLINE_LIMIT_TOLERANCE: f64 = 1e-9;

/// How long a candidate's chosen motion takes, and how far its smoothing departs from the
/// IK samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionDurations {
    /// From the pre-grasp pose to the grasp (s; 0 without an approach).
    pub approach: f64,
    /// From the grasp to the place, carrying the object (s).
    pub carry: f64,
    /// From the place back out (s; 0 without a retreat).
    pub retreat: f64,
    /// The largest distance between the smoothed motion and the straight joint-space
    /// segments between its IK samples (rad or m; see
    /// [`JointSpline::deviation_from_chords`]).
    pub spline_deviation: f64,
}

impl MotionDurations {
    /// The whole motion's duration (s).
    pub fn total(&self) -> f64 {
        self.approach + self.carry + self.retreat
    }
}

/// The timing check of one candidate, when its task times motions.
pub(super) struct TimingCheck<'a> {
    scoring: &'a Scoring<'a>,
    settings: &'a TimingSettings,
    velocity: Vec<Option<f64>>,
    acceleration: Vec<Option<f64>>,
    effort: Vec<Option<f64>>,
    /// The arm's dynamics, when the torque limits bind (the task carries a payload).
    dynamics: Option<&'a Dynamics>,
    /// The carried object in the tool frame.
    payload: Option<RigidBody>,
    /// The whole-motion samples of the approach (with the grasp), the carry and the retreat
    /// (with the place).
    approach: Range<usize>,
    carry: Range<usize>,
    retreat: Range<usize>,
}

impl<'a> TimingCheck<'a> {
    /// The check of `scoring`'s candidate, when its task times motions.
    pub(super) fn of(scoring: &'a Scoring<'a>) -> Option<Self> {
        let settings = scoring.setup.timing?;
        let chain = &scoring.setup.arm.chain;
        let limits = chain.motion_limits();
        let velocity = limits
            .iter()
            .map(|l| l.velocity.map(|v| v * settings.velocity_scale))
            .collect();
        let acceleration = limits
            .iter()
            .map(|l| {
                l.acceleration
                    .or(settings.max_acceleration)
                    .map(|a| a * settings.acceleration_scale)
            })
            .collect();
        let payload = scoring.setup.world.payload;
        let dynamics = settings
            .torque_limits
            .then_some(())
            .and(payload)
            .and(scoring.setup.arm.dynamics.as_deref());
        let wrist_from_object = scoring.candidate.object_from_wrist.inverse();
        let before = scoring.plan.approach_samples();
        let n = scoring.setup.path.samples.len();
        let total = scoring.targets.len();
        Some(Self {
            scoring,
            settings,
            velocity,
            acceleration,
            effort: limits.iter().map(|l| l.effort).collect(),
            dynamics,
            payload: payload.map(|p| p.transformed(&wrist_from_object)),
            approach: if before > 0 { 0..before + 1 } else { 0..0 },
            carry: before..before + n,
            retreat: if total > before + n {
                before + n - 1..total
            } else {
                0..0
            },
        })
    }

    /// The limits of a motion, with the payload when it carries the object.
    fn limits(&self, carrying: bool) -> PathLimits<'_> {
        PathLimits {
            velocity: &self.velocity,
            acceleration: &self.acceleration,
            torque: self.dynamics.map(|dynamics| TorqueLimits {
                dynamics,
                effort: &self.effort,
                payload: if carrying { self.payload } else { None },
            }),
            subdivisions: self.settings.subdivisions,
        }
    }

    /// The motion through `q[range]` timed from rest to rest; its duration and the spline's
    /// deviation.
    fn time_segment(
        &self,
        q: &[Vec<f64>],
        range: Range<usize>,
        carrying: bool,
    ) -> Result<(f64, f64), Failure> {
        if range.len() < 2 {
            return Ok((0.0, 0.0));
        }
        let samples = &q[range.clone()];
        let spline = JointSpline::through(samples).map_err(|e| self.failure(range.start, &e))?;
        self.check_range(&spline, samples, range.start)?;
        let timed = self
            .limits(carrying)
            .time(&spline)
            .map_err(|e| self.timing_failure(&e, samples, range.start))?;
        Ok((timed.duration(), spline.deviation_from_chords()))
    }

    /// The whole motion as one, the payload's torques only on the carry's grid points; its
    /// parts' durations at the grasp and the place.
    fn time_whole(&self, q: &[Vec<f64>]) -> Result<MotionDurations, Failure> {
        let spline = JointSpline::through(q).map_err(|e| self.failure(0, &e))?;
        self.check_range(&spline, q, 0)?;
        let at = |sample: usize| parameter_of(q, sample);
        let (grasp, place) = (at(self.carry.start), at(self.carry.end - 1));
        let empty = self.limits(false).constraints(&spline);
        let loaded = self.limits(true).constraints(&spline);
        let constraints = match (empty, loaded) {
            (Ok(empty), Ok(loaded)) => carried_between(empty, &loaded, grasp, place),
            (Err(e), _) | (_, Err(e)) => return Err(self.timing_failure(&e, q, 0)),
        };
        let timed =
            crate::timing::time_optimal(&constraints).map_err(|e| self.timing_failure(&e, q, 0))?;
        let (t_grasp, t_place) = (time_at(&timed, grasp), time_at(&timed, place));
        Ok(MotionDurations {
            approach: t_grasp,
            carry: t_place - t_grasp,
            retreat: timed.duration() - t_place,
            spline_deviation: spline.deviation_from_chords(),
        })
    }

    /// A smoothed motion that leaves a joint's range (beyond [`SPLINE_LIMIT_TOLERANCE`]) at
    /// the middle of an interval or at its quarter points is refused.
    fn check_range(
        &self,
        spline: &JointSpline,
        samples: &[Vec<f64>],
        first: usize,
    ) -> Result<(), Failure> {
        let chain = &self.scoring.setup.arm.chain;
        let (lower, upper) = (chain.lower(), chain.upper());
        let dof = spline.dof();
        let [mut q, mut dq, mut ddq] = std::array::from_fn(|_| vec![0.0; dof]);
        for (i, pair) in spline.knots().windows(2).enumerate() {
            for fraction in [0.25, 0.5, 0.75] {
                let s = pair[0] + fraction * (pair[1] - pair[0]);
                spline.evaluate_into(
                    s,
                    PathPoint {
                        q: &mut q,
                        dq: &mut dq,
                        ddq: &mut ddq,
                    },
                );
                for j in 0..dof {
                    let excess = (lower[j] - q[j]).max(q[j] - upper[j]);
                    if excess > SPLINE_LIMIT_TOLERANCE {
                        let sample = first + sample_at(samples, pair[0]);
                        return Err(self.scoring.located(Failure {
                            reason: FailureReason::JointLimit,
                            phase: Phase::Path,
                            sample,
                            detail: format!(
                                "the smoothed motion leaves joint '{}''s range [{:.4}, {:.4}] by \
                                 {excess:.2e} after this sample (spline interval {i})",
                                chain.joint_names()[j],
                                lower[j],
                                upper[j]
                            ),
                            bodies: None,
                        }));
                    }
                }
            }
        }
        Ok(())
    }

    /// A `timing_infeasible` failure for a timing error along `samples` (whose first is
    /// whole-motion sample `first`).
    fn timing_failure(&self, error: &TimingError, samples: &[Vec<f64>], first: usize) -> Failure {
        let TimingError::Infeasible { s, limit, .. } = error else {
            return self.failure(first, error);
        };
        let names = self.scoring.setup.arm.chain.joint_names();
        let what = match limit {
            Some(Limit::Velocity(j)) => format!("joint '{}''s velocity limit", names[*j]),
            Some(Limit::Acceleration(j)) => format!("joint '{}''s acceleration limit", names[*j]),
            Some(Limit::Torque(j)) => format!("joint '{}''s torque limit", names[*j]),
            None => "the limits".into(),
        };
        let sample = first + sample_at(samples, *s);
        self.scoring.located(Failure {
            reason: FailureReason::TimingInfeasible,
            phase: Phase::Path,
            sample,
            detail: format!("no timing of the motion near this sample satisfies {what}"),
            bodies: None,
        })
    }

    /// A `timing_infeasible` failure at whole-motion sample `sample` for another error.
    fn failure(&self, sample: usize, error: &TimingError) -> Failure {
        self.scoring.located(Failure {
            reason: FailureReason::TimingInfeasible,
            phase: Phase::Path,
            sample,
            detail: error.to_string(),
            bodies: None,
        })
    }
}

impl BranchCheck for TimingCheck<'_> {
    fn check(&self, q: &[Vec<f64>], findings: &mut BranchFindings) -> Result<(), Failure> {
        findings.durations = Some(if self.settings.stops {
            let (approach, a) = self.time_segment(q, self.approach.clone(), false)?;
            let (carry, c) = self.time_segment(q, self.carry.clone(), true)?;
            let (retreat, r) = self.time_segment(q, self.retreat.clone(), false)?;
            MotionDurations {
                approach,
                carry,
                retreat,
                spline_deviation: a.max(c).max(r),
            }
        } else {
            self.time_whole(q)?
        });
        Ok(())
    }
}

/// The chord-length parameter of sample `k` of `samples` (as [`JointSpline::through`] sets it).
fn parameter_of(samples: &[Vec<f64>], k: usize) -> f64 {
    samples[..=k]
        .windows(2)
        .map(|w| {
            w[0].iter()
                .zip(&w[1])
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt()
        })
        .filter(|d| *d > crate::timing::REPEATED_SAMPLE)
        .sum()
}

/// The last sample of `samples` whose chord-length parameter is at most `s`.
fn sample_at(samples: &[Vec<f64>], s: f64) -> usize {
    (0..samples.len())
        .take_while(|&k| parameter_of(samples, k) <= s)
        .last()
        .unwrap_or(0)
}

/// The time at which `timed` passes path parameter `s` (a grid point: a knot).
fn time_at(timed: &TimedPath, s: f64) -> f64 {
    let i = timed
        .grid
        .partition_point(|&g| g < s)
        .min(timed.grid.len() - 1);
    timed.times[i]
}

/// `empty`'s constraints with the rows of `loaded` at the grid points in `[from, to]`.
fn carried_between(
    mut empty: Constraints,
    loaded: &Constraints,
    from: f64,
    to: f64,
) -> Constraints {
    let m = empty.rows_per_point;
    for (i, s) in loaded.grid.iter().enumerate() {
        if (from..=to).contains(s) {
            empty.rows[i * m..(i + 1) * m].copy_from_slice(&loaded.rows[i * m..(i + 1) * m]);
        }
    }
    empty
}
