//! A timed motion sampled in time — what a joint trajectory controller executes — and its
//! layouts: ROS 2 `trajectory_msgs/JointTrajectory` (JSON) and CSV.
//!
//! At time `t` the parameterisation gives `s`, `ṡ` and `s̈` (constant `s̈` between grid
//! points); then `q = q(s)`, `q̇ = q'(s) ṡ`, `q̈ = q'(s) s̈ + q''(s) ṡ²` and, with the
//! dynamics, `τ = rnea(q, q̇, q̈)` (payload included).

use super::spline::{JointSpline, PathPoint};
use super::topp::TimedPath;
use super::TimingError;
use crate::robot::{Dynamics, RigidBody};
use serde_json::{json, Value};
use std::fmt::Write as _;

/// One point of a timed trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryPoint {
    /// Time from the start of the motion (s).
    pub time: f64,
    /// Joint positions (rad or m).
    pub positions: Vec<f64>,
    /// Joint velocities (rad/s or m/s).
    pub velocities: Vec<f64>,
    /// Joint accelerations (rad/s² or m/s²).
    pub accelerations: Vec<f64>,
    /// Joint torques (N·m or N), when the dynamics are known.
    pub efforts: Option<Vec<f64>>,
}

/// A timed joint trajectory: its joints' names and points in time order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TimedTrajectory {
    /// The joints, in chain order.
    pub joint_names: Vec<String>,
    /// The points, times increasing.
    pub points: Vec<TrajectoryPoint>,
}

/// What the torques of a sampled motion are computed with: the arm's dynamics and the payload
/// the tool carries (tool frame).
pub type Torques<'a> = (&'a Dynamics, Option<RigidBody>);

impl TimedTrajectory {
    /// The motion `timed` along `spline`, sampled every `period` seconds from `0` (the last
    /// point at the motion's end), or at the grid points when `period` is `None`; torques
    /// with `torques`.
    pub fn sample(
        joint_names: &[String],
        spline: &JointSpline,
        timed: &TimedPath,
        period: Option<f64>,
        torques: Option<Torques<'_>>,
    ) -> Result<Self, TimingError> {
        let dof = spline.dof();
        if joint_names.len() != dof {
            return Err(TimingError::BadPath(format!(
                "{} joint names for a path of {dof} joints",
                joint_names.len()
            )));
        }
        let times: Vec<f64> = match period {
            None => timed.times.clone(),
            Some(p) if p > 0.0 && p.is_finite() => {
                let duration = timed.duration();
                let steps = (duration / p).floor() as usize;
                if steps > MAX_POINTS {
                    return Err(TimingError::BadPath(format!(
                        "sampling {duration:.3} s every {p} s gives more than {MAX_POINTS} points"
                    )));
                }
                let mut t: Vec<f64> = (0..=steps).map(|k| k as f64 * p).collect();
                if duration - t[t.len() - 1] > 1e-12 {
                    t.push(duration);
                }
                t
            }
            Some(p) => {
                return Err(TimingError::BadPath(format!(
                    "the sampling period {p} is not a positive number of seconds"
                )))
            }
        };
        let mut dynamics = match torques {
            Some((model, payload)) => {
                let mut data = model.data();
                data.set_payload(payload)?;
                Some((model, data))
            }
            None => None,
        };
        let (mut dq, mut ddq) = (vec![0.0; dof], vec![0.0; dof]);
        let mut points = Vec::with_capacity(times.len());
        for time in times {
            let (s, sd, sdd) = timed.state_at(time);
            let mut positions = vec![0.0; dof];
            spline.evaluate_into(
                s,
                PathPoint {
                    q: &mut positions,
                    dq: &mut dq,
                    ddq: &mut ddq,
                },
            );
            let velocities: Vec<f64> = dq.iter().map(|d| d * sd).collect();
            let accelerations: Vec<f64> = dq
                .iter()
                .zip(&ddq)
                .map(|(d, dd)| d * sdd + dd * sd * sd)
                .collect();
            let efforts = match dynamics.as_mut() {
                Some((model, data)) => {
                    let mut tau = vec![0.0; dof];
                    model.inverse_dynamics_into(
                        data,
                        &positions,
                        &velocities,
                        &accelerations,
                        &mut tau,
                    )?;
                    Some(tau)
                }
                None => None,
            };
            points.push(TrajectoryPoint {
                time,
                positions,
                velocities,
                accelerations,
                efforts,
            });
        }
        Ok(Self {
            joint_names: joint_names.to_vec(),
            points,
        })
    }

    /// The motion's duration (s): the last point's time.
    pub fn duration(&self) -> f64 {
        self.points.last().map_or(0.0, |p| p.time)
    }

    /// Appends `next` (which starts at rest where this one ends) after this motion, its times
    /// shifted by this motion's duration; the point where they meet is kept once.
    pub fn extend(&mut self, next: TimedTrajectory) {
        let offset = self.duration();
        let skip = usize::from(!self.points.is_empty() && !next.points.is_empty());
        if self.joint_names.is_empty() {
            self.joint_names = next.joint_names;
        }
        self.points
            .extend(next.points.into_iter().skip(skip).map(|mut p| {
                p.time += offset;
                p
            }));
    }

    /// The ROS 2 `trajectory_msgs/JointTrajectory` layout: `joint_names`, and `points` each
    /// with `positions`, `velocities`, `accelerations`, `effort` (empty without dynamics, as
    /// the message allows) and `time_from_start` as `{sec, nanosec}`.
    pub fn to_joint_trajectory(&self) -> Value {
        let points: Vec<Value> = self
            .points
            .iter()
            .map(|p| {
                let (sec, nanosec) = split_seconds(p.time);
                json!({
                    "positions": p.positions,
                    "velocities": p.velocities,
                    "accelerations": p.accelerations,
                    "effort": p.efforts.clone().unwrap_or_default(),
                    "time_from_start": {"sec": sec, "nanosec": nanosec},
                })
            })
            .collect();
        json!({"joint_names": self.joint_names, "points": points})
    }

    /// One row per point: `time`, then each joint's position, velocity, acceleration and
    /// (with dynamics) effort, columns named `<joint>.position` and so on.
    pub fn to_csv(&self) -> String {
        let with_effort = self.points.iter().any(|p| p.efforts.is_some());
        let mut out = String::from("time");
        let quantities: &[&str] = if with_effort {
            &["position", "velocity", "acceleration", "effort"]
        } else {
            &["position", "velocity", "acceleration"]
        };
        for quantity in quantities {
            for name in &self.joint_names {
                let _ = write!(out, ",{name}.{quantity}");
            }
        }
        out.push('\n');
        for p in &self.points {
            let _ = write!(out, "{}", p.time);
            let efforts = p.efforts.as_deref().unwrap_or(&[]);
            let columns: [&[f64]; 4] = [&p.positions, &p.velocities, &p.accelerations, efforts];
            for values in &columns[..quantities.len()] {
                for v in values.iter() {
                    let _ = write!(out, ",{v}");
                }
            }
            out.push('\n');
        }
        out
    }
}

/// The most points a sampled trajectory may have (a 1 ms period over about 2.8 hours).
pub const MAX_POINTS: usize = 10_000_000;

/// `t` seconds as whole seconds and nanoseconds (`builtin_interfaces/Duration`).
fn split_seconds(t: f64) -> (i64, u32) {
    let total = (t * 1e9).round() as i64;
    (
        total.div_euclid(1_000_000_000),
        total.rem_euclid(1_000_000_000) as u32,
    )
}
