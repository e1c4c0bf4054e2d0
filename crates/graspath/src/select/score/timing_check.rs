//! The time a branch's whole motion takes: its joint samples as cubic splines, timed by
//! TOPP-RA under the joints' velocity and acceleration limits and, with the object's mass, the
//! torque limits with the arm carrying it ([`crate::timing`]). With `timing.stops` (the
//! default) the approach, the carry and the retreat are three motions from rest to rest (the
//! gripper closes at the grasp and opens at the place); otherwise one motion through all.
//! A motion no timing can keep within the limits is refused (`timing_infeasible`); the
//! smoothing never refuses a branch that IK found (its departures are reported). Arms that
//! carry the object together are timed on one path parameter ([`timed_jointly`]).

use super::branch_checks::{BranchCheck, BranchFindings};
use super::Scoring;
use crate::failure::{Failure, FailureReason, Phase};
use crate::robot::{Dynamics, RigidBody};
use crate::task::TimingSettings;
use crate::timing::{
    Constraints, Discretization, JointSpline, Limit, ObjectLimits, PathLimits, TimedPath,
    TimedTrajectory, TimingError, TorqueLimits, TrajectoryPoint,
};
use std::ops::Range;

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
    /// How far (rad or m) the smoothed motion leaves a joint's range between IK samples that
    /// ride a limit (0 when it stays inside); written trajectories are clamped into the range.
    pub limit_excursion: f64,
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
    /// Limits on the carried object's speed and acceleration (while carrying), with the
    /// task's.
    object_limits: Option<ObjectLimits<'a>>,
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
                    .or(l.velocity.map(|v| v / settings.acceleration_time))
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
            object_limits: ObjectLimits {
                chain,
                origin_in_tool: wrist_from_object.translation.vector,
                linear: settings.object_speed,
                angular: settings.object_turn_rate,
                linear_acceleration: settings.object_acceleration,
                angular_acceleration: settings.object_angular_acceleration,
            }
            .any(),
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
            object: self.object_limits.filter(|_| carrying),
            subdivisions: self.settings.subdivisions,
            discretization: Discretization::Interpolation,
        }
    }

    /// The motion through `q[range]` as a spline timed from rest to rest (`None` for fewer
    /// than two samples).
    fn time_segment(
        &self,
        q: &[Vec<f64>],
        range: Range<usize>,
        carrying: bool,
    ) -> Result<Option<TimedSegment>, Failure> {
        if range.len() < 2 {
            return Ok(None);
        }
        let samples = &q[range.clone()];
        let spline = JointSpline::through(samples).map_err(|e| self.failure(range.start, &e))?;
        let parameters = JointSpline::sample_parameters(samples);
        let timed = self
            .limits(carrying)
            .time(&spline)
            .map_err(|e| self.timing_failure(&e, &parameters, range.start))?;
        Ok(Some(TimedSegment {
            spline,
            timed,
            parameters,
            carried: carrying.then_some((0.0, f64::INFINITY)),
            hold: 0.0,
        }))
    }

    /// The constraints of `spline` carrying the object as `load` says.
    fn constraints(&self, spline: &JointSpline, load: Load) -> Result<Constraints, TimingError> {
        match load {
            Load::Empty => self.limits(false).constraints(spline),
            Load::Carried => self.limits(true).constraints(spline),
            Load::Between(grasp, place) => {
                let empty = self.limits(false).constraints(spline)?;
                let loaded = self.limits(true).constraints(spline)?;
                Ok(carried_between(empty, &loaded, grasp, place))
            }
        }
    }

    /// How much slower (`≥ 1`) `timed` along `spline` must run for every limit to hold
    /// between its grid points too ([`PathLimits::slowdown`]), carrying the object as `load`
    /// says.
    fn slowdown(
        &self,
        spline: &JointSpline,
        timed: &TimedPath,
        load: Load,
    ) -> Result<f64, TimingError> {
        match load {
            Load::Empty => self.limits(false).slowdown(spline, timed),
            Load::Carried => self.limits(true).slowdown(spline, timed),
            Load::Between(grasp, place) => {
                let empty = self.limits(false);
                let before = empty.slowdown_between(spline, timed, f64::NEG_INFINITY, grasp)?;
                let after = empty.slowdown_between(spline, timed, place, f64::INFINITY)?;
                let carry = self
                    .limits(true)
                    .slowdown_between(spline, timed, grasp, place)?;
                Ok(before.max(carry).max(after))
            }
        }
    }

    /// The whole motion as one, the payload's torques only on the carry's grid points.
    fn time_whole(&self, q: &[Vec<f64>]) -> Result<TimedSegment, Failure> {
        let spline = JointSpline::through(q).map_err(|e| self.failure(0, &e))?;
        let parameters = JointSpline::sample_parameters(q);
        let (grasp, place) = (parameters[self.carry.start], parameters[self.carry.end - 1]);
        let load = Load::Between(grasp, place);
        let timed = self
            .constraints(&spline, load)
            .and_then(|constraints| crate::timing::time_optimal(&constraints))
            .and_then(|timed| {
                let factor = self.slowdown(&spline, &timed, load)?;
                Ok(if factor > 1.0 {
                    timed.slowed(factor)
                } else {
                    timed
                })
            })
            .map_err(|e| self.timing_failure(&e, &parameters, 0))?;
        let carried = Some((timed.time_at(grasp), timed.time_at(place)));
        Ok(TimedSegment {
            spline,
            timed,
            parameters,
            carried,
            hold: 0.0,
        })
    }

    /// The whole motion `q` timed: its segments in order (three with stops, one without).
    pub(super) fn timed(&self, q: &[Vec<f64>]) -> Result<Vec<TimedSegment>, Failure> {
        if !self.settings.stops {
            return Ok(vec![self.time_whole(q)?]);
        }
        let mut segments = Vec::with_capacity(3);
        for (range, carrying) in [
            (self.approach.clone(), false),
            (self.carry.clone(), true),
            (self.retreat.clone(), false),
        ] {
            segments.extend(self.time_segment(q, range, carrying)?);
        }
        Ok(segments)
    }

    /// A timed motion's segments sampled every `period` seconds (at the grid points with
    /// `None`), one after the other; torques with the arm's dynamics (the object's from the
    /// grasp to the place).
    pub(super) fn sample(
        &self,
        segments: Vec<TimedSegment>,
        period: Option<f64>,
    ) -> Result<TimedMotion, Failure> {
        let names = self.scoring.setup.arm.chain.joint_names();
        let mut trajectory = TimedTrajectory::default();
        let dynamics = self.scoring.setup.arm.dynamics.as_deref();
        // The first and last instants the object is carried (s from the start).
        let mut carry: Option<(f64, f64)> = None;
        let mut sample_times: Vec<f64> = Vec::with_capacity(self.scoring.targets.len());
        for segment in segments {
            let offset = trajectory.duration();
            // A segment's first sample is the previous one's last: it is reached when this
            // segment starts (after the previous one's wait for the other arms, if any).
            sample_times.pop();
            sample_times.extend(
                segment
                    .parameters
                    .iter()
                    .map(|&s| offset + segment.timed.time_at(s)),
            );
            let sample = |payload: Option<RigidBody>| {
                TimedTrajectory::sample(
                    names,
                    &segment.spline,
                    &segment.timed,
                    period,
                    dynamics.map(|d| (d, payload)),
                )
                .map_err(|e| self.failure(0, &e))
            };
            let duration = segment.timed.duration();
            let mut part = match (segment.carried, self.payload) {
                // Carried throughout (a carry between stops): one pass, with the payload.
                (Some((from, to)), Some(_)) if from <= 0.0 && to >= duration => {
                    sample(self.payload)?
                }
                // Carried between the grasp and the place of one whole motion.
                (Some((from, to)), Some(_)) => {
                    let mut part = sample(None)?;
                    let loaded = sample(self.payload)?;
                    for (point, with) in part.points.iter_mut().zip(loaded.points) {
                        if (from..=to).contains(&point.time) {
                            point.efforts = with.efforts;
                        }
                    }
                    part
                }
                _ => sample(None)?,
            };
            // A segment that does not move waits, at rest, for the other arms.
            if segment.hold > part.duration() {
                if let Some(last) = part.points.last().cloned() {
                    part.points.push(TrajectoryPoint {
                        time: segment.hold,
                        ..last
                    });
                }
            }
            if let Some((from, to)) = segment.carried {
                let (grasp, place) = (offset + from.max(0.0), offset + to.min(part.duration()));
                carry = Some(carry.map_or((grasp, place), |(first, _)| (first, place)));
            }
            trajectory.extend(part);
        }
        // A smoothed motion through samples that ride a limit can leave the range by a few
        // milliradians between them (`limit_excursion`): clamped into it.
        let chain = &self.scoring.setup.arm.chain;
        for point in &mut trajectory.points {
            for ((q, lo), hi) in point
                .positions
                .iter_mut()
                .zip(chain.lower())
                .zip(chain.upper())
            {
                *q = q.clamp(*lo, *hi);
            }
        }
        let (grasp_time, place_time) = carry.unwrap_or((0.0, trajectory.duration()));
        if sample_times.is_empty() {
            // A motion of one sample has no segment: it is there from the start.
            sample_times = vec![0.0; self.scoring.targets.len()];
        }
        Ok(TimedMotion {
            trajectory,
            grasp_time,
            place_time,
            sample_times,
        })
    }

    /// A `timing_infeasible` failure for a timing error along samples at path parameters
    /// `parameters` (whose first is whole-motion sample `first`).
    fn timing_failure(&self, error: &TimingError, parameters: &[f64], first: usize) -> Failure {
        let TimingError::Infeasible { s, limit, .. } = error else {
            return self.failure(first, error);
        };
        let names = self.scoring.setup.arm.chain.joint_names();
        let joint = limit.and_then(Limit::joint).map(|j| names[j].clone());
        let what = match limit {
            Some(Limit::Velocity(j)) => format!("joint '{}''s velocity limit", names[*j]),
            Some(Limit::Acceleration(j)) => format!("joint '{}''s acceleration limit", names[*j]),
            Some(Limit::Torque(j)) => format!("joint '{}''s torque limit", names[*j]),
            Some(Limit::ObjectSpeed) => "the object's speed limit".into(),
            Some(Limit::ObjectTurnRate) => "the object's turn-rate limit".into(),
            Some(Limit::ObjectAcceleration) => "the object's acceleration limit".into(),
            Some(Limit::ObjectAngularAcceleration) => {
                "the object's angular acceleration limit".into()
            }
            None => "the limits".into(),
        };
        let sample = first
            + parameters
                .iter()
                .take_while(|&&p| p <= *s)
                .count()
                .saturating_sub(1);
        self.scoring.located(Failure {
            reason: FailureReason::TimingInfeasible,
            phase: Phase::Path,
            sample,
            detail: format!("no timing of the motion near this sample satisfies {what}"),
            bodies: None,
            joint,
        })
    }

    /// A `timing_infeasible` failure at whole-motion sample `sample` for another error.
    fn failure(&self, sample: usize, error: &TimingError) -> Failure {
        self.scoring.located(Failure {
            reason: FailureReason::TimingInfeasible,
            phase: Phase::Path,
            sample,
            detail: crate::fault::Chain(error).to_string(),
            bodies: None,
            joint: None,
        })
    }
}

impl BranchCheck for TimingCheck<'_> {
    fn check(&self, q: &[Vec<f64>], findings: &mut BranchFindings) -> Result<(), Failure> {
        let segments = self.timed(q)?;
        let deviation = segments
            .iter()
            .map(|s| s.spline.deviation_from_chords())
            .fold(0.0, f64::max);
        let chain = &self.scoring.setup.arm.chain;
        let excursion = segments
            .iter()
            .map(|s| s.spline.range_excursion(chain.lower(), chain.upper()))
            .fold(0.0, f64::max);
        let durations = if self.settings.stops {
            // The segments present, in order; an absent approach or retreat takes no time.
            let mut parts = segments.iter().map(|s| s.timed.duration());
            let approach = if self.approach.len() >= 2 {
                parts.next()
            } else {
                None
            };
            let carry = if self.carry.len() >= 2 {
                parts.next()
            } else {
                None
            };
            let retreat = if self.retreat.len() >= 2 {
                parts.next()
            } else {
                None
            };
            MotionDurations {
                approach: approach.unwrap_or(0.0),
                carry: carry.unwrap_or(0.0),
                retreat: retreat.unwrap_or(0.0),
                spline_deviation: deviation,
                limit_excursion: excursion,
            }
        } else {
            let whole = &segments[0];
            let (grasp, place) = whole.carried.unwrap_or((0.0, 0.0));
            MotionDurations {
                approach: grasp,
                carry: place - grasp,
                retreat: whole.timed.duration() - place,
                spline_deviation: deviation,
                limit_excursion: excursion,
            }
        };
        findings.durations = Some(durations);
        Ok(())
    }
}

/// One rest-to-rest motion of a timed branch: its spline, its timing, and the times between
/// which it carries the object (`None`: it does not).
pub(super) struct TimedSegment {
    spline: JointSpline,
    timed: TimedPath,
    /// The path parameter of each of its IK samples (a knot, shared by samples that coincide).
    parameters: Vec<f64>,
    carried: Option<(f64, f64)>,
    /// How long the segment lasts when it does not move (0) while another arm's does (s).
    hold: f64,
}

/// One arm's whole motion, timed, and when it holds the object.
#[derive(Debug, Clone, PartialEq)]
pub struct TimedMotion {
    /// The approach, the carry and the retreat, one after the other.
    pub trajectory: TimedTrajectory,
    /// When the tool reaches the grasp and the carry begins (s from the start): where a
    /// gripper closes.
    pub grasp_time: f64,
    /// When the carry ends at the place (s from the start): where a gripper opens.
    pub place_time: f64,
    /// When the motion reaches each of its IK samples (s from the start): the approach's,
    /// the path's and the retreat's, in order, one per whole-motion sample (the timed
    /// path passes through each at its knot). Samples that coincide share a time; where a
    /// part of an arm's motion waits for another arm, the sample it waits at takes the time
    /// it moves on.
    pub sample_times: Vec<f64>,
}

/// Puts the timed motions of arms that move the object together on one timeline: each
/// segment (by position) takes the slowest arm's time, the faster arms' timings slowed
/// uniformly to it (`ṡ` divided by the factor, so every limit still holds).
pub(super) fn synchronise(motions: &mut [Vec<TimedSegment>]) {
    let parts = motions.iter().map(Vec::len).max().unwrap_or(0);
    for k in 0..parts {
        let slowest = motions
            .iter()
            .filter_map(|m| m.get(k))
            .map(|s| s.timed.duration())
            .fold(0.0, f64::max);
        for segment in motions.iter_mut().filter_map(|m| m.get_mut(k)) {
            let own = segment.timed.duration();
            if own > 0.0 {
                let factor = slowest / own;
                segment.timed = segment.timed.slowed(factor);
                segment.carried = segment.carried.map(|(a, b)| (a * factor, b * factor));
            } else {
                segment.hold = slowest;
            }
        }
    }
}

/// How a timed part of a motion carries the object.
#[derive(Debug, Clone, Copy)]
enum Load {
    /// Not at all (an approach or a retreat).
    Empty,
    /// Throughout (a carry between stops).
    Carried,
    /// Between these two path parameters (a whole motion: the grasp's and the place's).
    Between(f64, f64),
}

/// The whole motions `motions` (per arm of `checks`, in order: the approach's, the path's and
/// the retreat's samples) of arms that carry the object together, timed on one timeline.
///
/// The carry (with stops) or the whole motion (without) is one path through all the arms'
/// joints, timed by one path parameter under every arm's limits ([`Constraints::stacked`]):
/// the arms pass their IK samples of each object pose at the same instant, so the object both
/// hold is at each of its poses at one time, never pulled between two. An approach or a
/// retreat, where the arms do not hold the object together, is timed per arm and the faster
/// arm's timing slowed uniformly to the slower one's ([`synchronise`]).
pub(super) fn timed_jointly(
    checks: &[TimingCheck<'_>],
    motions: &[Vec<Vec<f64>>],
) -> Result<Vec<Vec<TimedSegment>>, Failure> {
    let Some(first) = checks.first() else {
        return Ok(Vec::new());
    };
    let samples = motions.first().map_or(0, Vec::len);
    let aligned = motions.len() == checks.len()
        && checks.iter().zip(motions).all(|(check, q)| {
            q.len() == samples
                && check.approach == first.approach
                && check.carry == first.carry
                && check.retreat == first.retreat
        });
    if !aligned {
        let error = TimingError::BadPath("the arms' motions do not have the same samples".into());
        return Err(first.failure(0, &error));
    }
    let mut timed: Vec<Vec<TimedSegment>> = checks.iter().map(|_| Vec::with_capacity(3)).collect();
    let parts = if first.settings.stops {
        vec![
            (first.approach.clone(), Load::Empty),
            (first.carry.clone(), Load::Carried),
            (first.retreat.clone(), Load::Empty),
        ]
    } else {
        vec![(0..samples, Load::Between(0.0, 0.0))]
    };
    for (range, load) in parts {
        match load {
            Load::Empty => {
                for ((arm, check), q) in timed.iter_mut().zip(checks).zip(motions) {
                    arm.extend(check.time_segment(q, range.clone(), false)?);
                }
            }
            // A carry of one sample does not move (as one arm's, no segment).
            Load::Carried if range.len() < 2 => {}
            _ => {
                let together = time_jointly(checks, motions, range, load)?;
                for (arm, segment) in timed.iter_mut().zip(together) {
                    arm.push(segment);
                }
            }
        }
    }
    synchronise(&mut timed);
    Ok(timed)
}

/// The part `range` of every arm's motion timed as one path of all the arms' joints (see
/// [`timed_jointly`]), carrying the object as `load` says (for a whole motion, between the
/// grasp and the place): one segment per arm, all on one timing.
fn time_jointly(
    checks: &[TimingCheck<'_>],
    motions: &[Vec<Vec<f64>>],
    range: Range<usize>,
    load: Load,
) -> Result<Vec<TimedSegment>, Failure> {
    let first = &checks[0];
    let stacked: Vec<Vec<f64>> = range
        .clone()
        .map(|i| motions.iter().flat_map(|q| q[i].iter().copied()).collect())
        .collect();
    // The arms' samples at one knot each: the chord length of all their joints together
    // (samples where no arm moves share the previous one's knot).
    let parameters = JointSpline::sample_parameters(&stacked);
    let distinct: Vec<usize> = (0..parameters.len())
        .filter(|&k| k == 0 || parameters[k] > parameters[k - 1])
        .collect();
    let knots: Vec<f64> = distinct.iter().map(|&k| parameters[k]).collect();
    let load = match load {
        Load::Between(..) => Load::Between(
            parameters[first.carry.start - range.start],
            parameters[first.carry.end - 1 - range.start],
        ),
        other => other,
    };
    let splines = checks
        .iter()
        .zip(motions)
        .map(|(check, q)| {
            let samples: Vec<Vec<f64>> = distinct
                .iter()
                .map(|&k| q[range.start + k].clone())
                .collect();
            JointSpline::with_knots(&knots, &samples).map_err(|e| check.failure(range.start, &e))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let constraints = checks
        .iter()
        .zip(&splines)
        .map(|(check, spline)| {
            check
                .constraints(spline, load)
                .map_err(|e| check.timing_failure(&e, &parameters, range.start))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let dofs: Vec<usize> = splines.iter().map(JointSpline::dof).collect();
    let stacked =
        Constraints::stacked(constraints, &dofs).map_err(|e| first.failure(range.start, &e))?;
    let mut timed = crate::timing::time_optimal(&stacked).map_err(|error| {
        // The failure is the arm's whose limit binds, named by its own joint.
        let (arm, error) = match error {
            TimingError::Infeasible {
                grid_point,
                s,
                limit: Some(limit),
            } => {
                let (arm, limit) = limit.in_part(&dofs);
                let limit = Some(limit);
                (
                    arm,
                    TimingError::Infeasible {
                        grid_point,
                        s,
                        limit,
                    },
                )
            }
            other => (0, other),
        };
        checks[arm].timing_failure(&error, &parameters, range.start)
    })?;
    // Checked between the grid points as one arm's motion is: the largest slow-down any arm
    // needs.
    let mut factor: f64 = 1.0;
    for (check, spline) in checks.iter().zip(&splines) {
        let own = check
            .slowdown(spline, &timed, load)
            .map_err(|e| check.timing_failure(&e, &parameters, range.start))?;
        factor = factor.max(own);
    }
    if factor > 1.0 {
        timed = timed.slowed(factor);
    }
    let carried = match load {
        Load::Between(grasp, place) => Some((timed.time_at(grasp), timed.time_at(place))),
        _ => Some((0.0, f64::INFINITY)),
    };
    Ok(splines
        .into_iter()
        .map(|spline| TimedSegment {
            spline,
            timed: timed.clone(),
            parameters: parameters.clone(),
            carried,
            hold: 0.0,
        })
        .collect())
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
