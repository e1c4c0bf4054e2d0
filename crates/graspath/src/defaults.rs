//! Every default of a task, in one place: the task-file loader, the builder, the Python
//! bindings, the command line and the docs (`docs/task-file.md`) all take them from here.

/// Characteristic length L of the `twist` index (m): the paper's raw `J`.
pub const LENGTH_SCALE: f64 = 1.0;
/// How many best arm pairs are kept.
pub const PAIRS: usize = 10;
/// Two grasps closer than this overlap (m; Baxter's gripper width).
pub const MIN_SEPARATION: f64 = 0.08;
/// Tsai's penalty gain `k` when `index.joint_limit_penalty: true` (Simox's default).
pub const JOINT_LIMIT_PENALTY_GAIN: f64 = 50.0;
/// A joint closer than this to a limit (rad or m) counts as at the limit.
pub const LIMIT_HUG_DISTANCE: f64 = 0.02;
/// A candidate whose path has at least this share of samples with a joint at a limit
/// ([`LIMIT_HUG_DISTANCE`]) hugs the limit (flagged in its results).
pub const LIMIT_HUG_SHARE: f64 = 0.5;
/// Relative score difference under which two candidates are reported as tied (1 = 100 %).
///
/// The IK stops within [`IK_TOLERANCE`] (m and rad) of each wrist pose, so the Jacobians
/// are those of a configuration off by that much: `J` changes by about `ε / ℓ` relative,
/// with `ℓ` the lever arm between the joints and the wrist (≥ 0.2 m on Baxter), and
/// `M_T = ‖Jᵀ u‖²` by twice that, `2 · 1e-5 / 0.2 = 1e-4`. Score differences below it are
/// within what the solver's tolerance alone can produce.
pub const TIE_TOLERANCE: f64 = 1e-4;
/// Samples per step of the object path when no sampling is given.
pub const SAMPLES_PER_STEP: usize = 10;
/// Duration of a step (s).
pub const STEP_DURATION: f64 = 1.0;
/// Largest joint motion between consecutive samples (rad or m); also the separation that
/// makes two IK branches distinct.
pub const MAX_JOINT_STEP: f64 = 0.5;
/// How far inside its limits the IK keeps every revolute joint (rad): MoveIt Servo's
/// default `joint_limit_margins` (5.7°). A motion planned up to a limit leaves the next
/// perception or tracking error no room, and a controller faults on it; with this margin
/// the chosen grasps do not ride the limits (`ik.limit_margin: 0` plans up to them, as the
/// paper does).
pub const IK_LIMIT_MARGIN: f64 = 0.1;
/// Distinct IK branches searched from the grasp pose.
pub const IK_BRANCHES: usize = 4;
/// Random seed of the IK's restarts (task file `ik.random_seed`).
pub const IK_RANDOM_SEED: u64 = 0;
/// Position (m) and rotation (rad) tolerance of IK.
pub const IK_TOLERANCE: f64 = 1e-5;
/// The IK iteration budget of a candidate's grasp sample over all restarts: what an
/// unreachable candidate costs before it is given up.
pub const GRASP_IK_ITERATIONS: usize = 200;
/// Iteration budget of the warm-started solve of one path sample.
pub const PER_SAMPLE_IK_ITERATIONS: usize = 30;
/// How far below the top face (or inside a face) a family's tool point sits (m).
pub const FAMILY_DEPTH: f64 = 0.02;
/// Distance an edge family keeps from each end of the edge (m).
pub const FAMILY_MARGIN: f64 = 0.02;
