//! How a task times each feasible candidate's motion (`timing:` in a task file): the settings
//! the [`crate::timing`] module is run with, and when timing is on.

use crate::robot::Chain;

/// How each feasible candidate's whole motion (approach, the object's path, retreat) is timed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimingSettings {
    /// Stop at the grasp and at the place (the gripper closes and opens there): the approach,
    /// the carry and the retreat are timed as three rest-to-rest motions. `false`: one motion
    /// through the whole.
    pub stops: bool,
    /// Grid intervals per interval between IK samples (the grid the limits are imposed on).
    pub subdivisions: usize,
    /// The fraction of the robot's velocity limits used, in `(0, 1]`.
    pub velocity_scale: f64,
    /// The fraction of the acceleration limits used, in `(0, 1]`.
    pub acceleration_scale: f64,
    /// The acceleration limit (rad/s² or m/s²) of joints whose robot gives none.
    pub max_acceleration: Option<f64>,
    /// For joints with no acceleration limit from the robot or `max_acceleration`: the time
    /// (s) to reach full speed, so that the limit is the velocity limit divided by it. Makers
    /// rarely publish acceleration limits (of the built-in arms only the Panda's are), and a
    /// motion timed without one would jump to full speed; 0.5 s gives 6.3 rad/s² for a UR
    /// joint (Universal Robots' own ROS 2 driver sets 5 rad/s² for MoveIt) and 3 rad/s² for
    /// Baxter's shoulder.
    pub acceleration_time: f64,
    /// Whether the joint torque limits bind (through the arm's dynamics and the carried
    /// object, where the robot gives inertias and effort limits).
    pub torque_limits: bool,
    /// The largest linear speed of the carried object's origin (m/s), while it is carried.
    pub object_speed: Option<f64>,
    /// The largest angular speed of the carried object (rad/s), while it is carried.
    pub object_turn_rate: Option<f64>,
    /// The largest linear acceleration of the carried object's origin (m/s², base frame),
    /// while it is carried.
    pub object_acceleration: Option<f64>,
    /// The largest angular acceleration of the carried object (rad/s²), while it is carried.
    pub object_angular_acceleration: Option<f64>,
}

impl Default for TimingSettings {
    fn default() -> Self {
        Self {
            stops: true,
            subdivisions: 2,
            velocity_scale: 1.0,
            acceleration_scale: 1.0,
            max_acceleration: None,
            acceleration_time: DEFAULT_ACCELERATION_TIME,
            torque_limits: true,
            object_speed: None,
            object_turn_rate: None,
            object_acceleration: None,
            object_angular_acceleration: None,
        }
    }
}

/// The default [`TimingSettings::acceleration_time`] (s).
pub const DEFAULT_ACCELERATION_TIME: f64 = 0.5;

/// Whether a task times its candidates' motions.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum TimingRequest {
    /// When every joint of every arm has a velocity limit (every built-in arm does), with the
    /// default settings; otherwise not.
    #[default]
    Auto,
    /// Never.
    Off,
    /// Always, with these settings: an arm with a joint whose velocity limit is unknown is an
    /// error.
    On(TimingSettings),
}

impl TimingSettings {
    /// The problems with these settings, as `(field, message)`.
    pub(crate) fn check(&self) -> Result<(), (&'static str, String)> {
        if self.subdivisions == 0 || self.subdivisions > 64 {
            return Err((
                "timing.subdivisions",
                format!("must be between 1 and 64, got {}", self.subdivisions),
            ));
        }
        for (field, scale) in [
            ("timing.velocity_scale", self.velocity_scale),
            ("timing.acceleration_scale", self.acceleration_scale),
        ] {
            if !(scale > 0.0 && scale <= 1.0) {
                return Err((field, format!("must be a fraction in (0, 1], got {scale}")));
            }
        }
        if !(self.acceleration_time > 0.0 && self.acceleration_time <= 60.0) {
            return Err((
                "timing.acceleration_time",
                format!(
                    "must be a time to full speed in (0, 60] seconds, got {}",
                    self.acceleration_time
                ),
            ));
        }
        for (field, limit, unit) in [
            ("timing.object_speed", self.object_speed, "m/s"),
            ("timing.object_turn_rate", self.object_turn_rate, "rad/s"),
            (
                "timing.object_acceleration",
                self.object_acceleration,
                "m/s²",
            ),
            (
                "timing.object_angular_acceleration",
                self.object_angular_acceleration,
                "rad/s²",
            ),
        ] {
            if let Some(v) = limit {
                if !(v > 0.0 && v.is_finite()) {
                    return Err((
                        field,
                        format!("must be a positive number in {unit}, got {v}"),
                    ));
                }
            }
        }
        if let Some(a) = self.max_acceleration {
            if !(a > 0.0 && a.is_finite()) {
                return Err((
                    "timing.max_acceleration",
                    format!("must be a positive acceleration in rad/s², got {a}"),
                ));
            }
        }
        Ok(())
    }
}

/// The timing settings a request resolves to for `arms` (each its name and chain): `Auto` is on with the defaults when
/// every joint has a velocity limit; `On` requires one; the settings are checked.
pub(super) fn resolve_timing<'a>(
    request: TimingRequest,
    arms: impl IntoIterator<Item = (&'a str, &'a Chain)>,
) -> Result<Option<TimingSettings>, (&'static str, String)> {
    let unlimited = arms.into_iter().find_map(|(name, chain)| {
        chain
            .motion_limits()
            .iter()
            .zip(chain.joint_names())
            .find(|(l, _)| l.velocity.is_none())
            .map(|(_, joint)| format!("arm '{name}' joint '{joint}'"))
    });
    match request {
        TimingRequest::Off => Ok(None),
        TimingRequest::Auto => Ok(unlimited.is_none().then(TimingSettings::default)),
        TimingRequest::On(settings) => {
            settings.check()?;
            match unlimited {
                Some(joint) => Err((
                    "timing",
                    format!(
                        "{joint} has no velocity limit (the robot file gives none): a motion \
                         cannot be timed without one"
                    ),
                )),
                None => Ok(Some(settings)),
            }
        }
    }
}
