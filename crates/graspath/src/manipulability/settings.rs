//! The index vocabulary: which rows of `J` and of the path tangent enter `M_T`
//! ([`JacobianRows`]), what is measured at each sample ([`IndexMeasure`]) and ranked
//! ([`RankedIndex`]), over which samples ([`NormSamples`]) and by which norm ([`Norm`]). Tasks
//! carry them; the index and norm computations here read them. Every name a task file, Python
//! or the command line reads is in one [`Spelled`](crate::spelling::Spelled) table per enum.

use crate::spelling::spelled;

/// Which rows of the Jacobian `J` (and of the path tangent `u`) enter the task-relevant index
/// `M_T = ‖J'ᵀ u‖²`. In a task file: `index: { mode: twist | translation | rotation,
/// length_scale }`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JacobianRows {
    /// All six rows: the linear velocity of the wrist origin and the angular velocity, the
    /// angular rows of `J` and of the tangent scaled by a characteristic length (m). A length of
    /// 1 m reproduces the paper's raw `J`.
    Twist {
        /// Characteristic length L (m), > 0.
        length_scale: f64,
    },
    /// The three linear rows `Jv` and the linear part of the tangent.
    Translation,
    /// The three angular rows `Jω` and the angular part of the tangent.
    Rotation,
}

impl Default for JacobianRows {
    /// The paper's choice: the full twist with L = [`crate::defaults::LENGTH_SCALE`].
    fn default() -> Self {
        JacobianRows::Twist {
            length_scale: crate::defaults::LENGTH_SCALE,
        }
    }
}

impl JacobianRows {
    /// The spellings of the rows (`index.mode`), in the order the docs list them.
    pub const MODES: [&'static str; 3] = ["twist", "translation", "rotation"];

    /// The task-file spelling: `twist`, `translation` or `rotation`.
    pub fn name(&self) -> &'static str {
        match self {
            JacobianRows::Twist { .. } => Self::MODES[0],
            JacobianRows::Translation => Self::MODES[1],
            JacobianRows::Rotation => Self::MODES[2],
        }
    }

    /// The rows spelled `mode`, with `length_scale` (m) for `twist`; else a message listing
    /// the spellings.
    pub fn from_mode(mode: &str, length_scale: f64) -> Result<Self, String> {
        match Self::MODES.iter().position(|m| *m == mode) {
            Some(0) => Ok(JacobianRows::Twist { length_scale }),
            Some(1) => Ok(JacobianRows::Translation),
            Some(2) => Ok(JacobianRows::Rotation),
            _ => Err(format!("'{mode}' is not one of {}", Self::MODES.join(", "))),
        }
    }
}

/// What is measured at each sample and ranked by its norms over the path (`index.measure`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IndexMeasure {
    /// The paper's task-relevant manipulability `M_T = uᵀ J' J'ᵀ u` (eq. 13).
    #[default]
    TaskRelevant,
    /// The velocity transmission ratio along the tangent, `1 / √(uᵀ (J' J'ᵀ)⁻¹ u)`: the speed
    /// along `u` a unit joint velocity reaches (0 where `u` is a singular direction). Not the
    /// paper's index: it weighs the directions the arm is slow in, not the fast ones.
    VelocityRatio,
    /// The time the whole motion takes, fastest within the joints' limits (smaller is better:
    /// candidates are ranked by its inverse, the task's rate); needs timing. The per-sample
    /// series is `M_T`, as with [`IndexMeasure::TaskRelevant`].
    Duration,
    /// The dynamic task-relevant manipulability `M_D = ‖H M⁻¹ J'ᵀ u‖²`: the square of the
    /// largest acceleration along `u` the joints' torques can still produce, each within its
    /// effort limit less what gravity takes (the arm and, while held, the object; see
    /// [`crate::manipulability::DynamicManipulability`]). Needs the arm's inertial data and
    /// every joint's effort limit. Not the paper's index.
    Dynamic,
}

spelled!(IndexMeasure {
    TaskRelevant => "task_relevant",
    VelocityRatio => "velocity_ratio",
    Duration => "duration",
    Dynamic => "dynamic",
});

/// Which path samples the norms are taken over (`index.over`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NormSamples {
    /// Every sample of the path.
    #[default]
    All,
    /// The paper's reading of a task (eq. 15 over its waypoints): the initial pose and the
    /// last sample of each step (initial / pick / move / place for a three-step task). The path
    /// is still sampled densely for the IK, the continuity and the collision checks; `M_T` at a
    /// waypoint is measured along the motion leaving it (the last one: arriving at it).
    Waypoints,
}

spelled!(NormSamples { All => "samples", Waypoints => "waypoints" });

/// The per-sample index that is ranked: the measure, optionally multiplied by a joint-limit
/// penalty, and the samples its norms are taken over (`index: { measure,
/// joint_limit_penalty, over }`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RankedIndex {
    /// What is measured at each sample.
    pub measure: IndexMeasure,
    /// With `Some(k)`, each sample's value is multiplied by Tsai's joint-limit penalty
    /// `P(q) = 1 − exp(−k Π_i (q_i − l_i)(u_i − q_i) / (u_i − l_i)²)` (the product over the
    /// joints with limits; see [`crate::manipulability::joint_limit_penalty`]); `k > 0`.
    pub joint_limit_penalty: Option<f64>,
    /// Which samples the norms are taken over.
    pub over: NormSamples,
}

impl RankedIndex {
    /// Whether the ranked value is the paper's `M_T` itself.
    pub fn is_task_relevant(&self) -> bool {
        self.measure == IndexMeasure::TaskRelevant && self.joint_limit_penalty.is_none()
    }

    /// Whether the per-sample series is `M_T` itself (the paper's index, or the duration,
    /// which is ranked on the whole motion and keeps `M_T` per sample).
    pub fn series_is_m_t(&self) -> bool {
        matches!(
            self.measure,
            IndexMeasure::TaskRelevant | IndexMeasure::Duration
        ) && self.joint_limit_penalty.is_none()
    }
}

/// The norm of the ranked index along the path that is maximised (each path's value:
/// [`PathNorms::value`](crate::manipulability::PathNorms::value)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Norm {
    /// `μ_rms`, the root mean square over the path's time (the default): the continuous
    /// counterpart of the paper's `μ_l2`, independent of how densely the path is sampled, so
    /// scores compare across tasks and rankings hold when the sampling is refined.
    #[default]
    Rms,
    /// `μ_l2 = ‖M‖₂` over the samples (the paper's choice, eq. 15): it grows with the square
    /// root of the sample count.
    L2,
    /// `μ_l1`, the time integral of `M_T`.
    L1,
}

impl Norm {
    /// The name of its column in the candidate records: `mu_rms`, `mu_l2`, `mu_l1`.
    pub fn field(self) -> &'static str {
        match self {
            Norm::Rms => "mu_rms",
            Norm::L2 => "mu_l2",
            Norm::L1 => "mu_l1",
        }
    }
}

spelled!(Norm { Rms => "rms", L2 => "l2", L1 => "l1" });
