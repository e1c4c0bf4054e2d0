//! The task-file loader: a task file (YAML or JSON, `docs/task-file.md`) turned into a
//! [`TaskBuilder`], every value checked with the field it came from. The defaults and the
//! checks shared with the other ways of building a task live in the builder.

use super::builder::TaskBuilder;
use super::error::TaskError;
use super::file::{pose, ArmsFile, LikelihoodFile, PenaltyFile, StepFile, TaskFile, TimingFile};
use super::load_candidates::{setup_candidates, SetUp};
use super::path::{Sampling, Step, TimedStep};
use super::plausibility::TaskWarning;
use super::sealed::Task;
use super::settings::LikelihoodRule;
use super::timing::{TimingRequest, TimingSettings};
use crate::defaults;
use crate::grasp::hand::StockGripper;
use crate::grasp::CandidateSource;
use crate::manipulability::{JacobianRows, RankedIndex};
use crate::robot::builtin::BuiltinRobot;
use crate::robot::{Chain, RobotModel, RobotSource};
use crate::spelling::Spelled;
use nalgebra::{Isometry3, Unit, Vector3};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

impl Task {
    /// Reads and checks a task file (YAML or JSON). Relative paths inside it are relative to
    /// the file.
    pub fn load(path: &Path) -> Result<Self, TaskError> {
        let file = TaskFile::load(path)?;
        let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::from_file(&file, &path.display().to_string(), &base_dir)
    }

    /// Builds a task from a parsed file; relative paths are resolved against `base_dir`.
    pub fn from_file(
        file: &TaskFile,
        source_name: &str,
        base_dir: &Path,
    ) -> Result<Self, TaskError> {
        builder_from_file(file, source_name, base_dir)?.build()
    }

    /// [`from_file`](Self::from_file), except that a candidate family is laid out rather than
    /// generated, and a graspath candidate file (JSON or CSV) is checked and indexed rather
    /// than held ([`Task::candidates`]): their candidates are computed or read again
    /// chunk by chunk when a streamed selection reads them. The same candidates, in the same
    /// order, and the same errors. Generated candidates and the generators' grasp files are
    /// held as with `from_file`.
    pub fn from_file_chunked(
        file: &TaskFile,
        source_name: &str,
        base_dir: &Path,
    ) -> Result<Self, TaskError> {
        builder_with(file, source_name, base_dir, true)?.build()
    }
}

/// The builder a task file describes (robot chains loaded, candidates read or generated).
pub fn builder_from_file(
    file: &TaskFile,
    source_name: &str,
    base_dir: &Path,
) -> Result<TaskBuilder, TaskError> {
    builder_with(file, source_name, base_dir, false)
}

/// [`builder_from_file`], with `lay_out` a candidate family laid out rather than generated
/// and a graspath candidate file indexed rather than read whole.
fn builder_with(
    file: &TaskFile,
    source_name: &str,
    base_dir: &Path,
    lay_out: bool,
) -> Result<TaskBuilder, TaskError> {
    let err = |field: &str, message: String| TaskError::new(source_name, field, message);
    let limits = file.limits.unwrap_or_default();
    let (robot_name, arms, model) = setup_arms(file, source_name, base_dir)?;
    let mut warnings = super::plausibility::file_warnings(file);
    warnings.extend(gripper_at_flange_warnings(file, &arms, &model));
    let mut builder = Task::builder(source_name).limits(limits).warnings(warnings);
    builder = builder.robot_name(robot_name);
    for (name, chain, world_from_base) in arms {
        builder = builder.arm(name, chain, world_from_base);
    }
    let world_from_object = pose(&file.object.pose, source_name, "object.pose")?;
    if let Some(shape) = &file.object.shape {
        builder = builder.shape(shape.clone());
    }
    if let Some(payload) =
        super::payload::object_payload(&file.object).map_err(|(field, m)| err(&field, m))?
    {
        builder = builder.payload(payload);
    }
    let scene = super::load_scene::scene_from_file(file, source_name, base_dir)?;
    let candidates = setup_candidates(
        file,
        source_name,
        base_dir,
        &limits,
        world_from_object,
        scene.as_ref(),
        lay_out,
    )?;
    builder = match candidates {
        SetUp::Family(family) if lay_out => {
            builder.candidate_source(CandidateSource::Family(family))
        }
        SetUp::Family(family) => builder.candidates(family.all()),
        SetUp::File(file) => builder.candidate_source(CandidateSource::File(file)),
        SetUp::List(list) => builder.candidates(list),
    };
    let (steps, sampling) = setup_steps(file, source_name)?;
    builder = builder.object_motion(world_from_object, steps, sampling);
    let rows = JacobianRows::from_mode(
        file.index
            .mode
            .as_deref()
            .unwrap_or(JacobianRows::default().name()),
        file.index.length_scale.unwrap_or(defaults::LENGTH_SCALE),
    )
    .map_err(|m| err("index.mode", m))?;
    if file.index.length_scale.is_some() && !matches!(rows, JacobianRows::Twist { .. }) {
        return Err(err(
            "index.length_scale",
            "only applies to mode 'twist'".into(),
        ));
    }
    let measure = spelled_setting(&file.index.measure, "index.measure", &err)?;
    let joint_limit_penalty = match file.index.joint_limit_penalty {
        None | Some(PenaltyFile::On(false)) => None,
        Some(PenaltyFile::On(true)) => Some(defaults::JOINT_LIMIT_PENALTY_GAIN),
        Some(PenaltyFile::Gain(k)) => Some(k),
    };
    let over = spelled_setting(&file.index.over, "index.over", &err)?;
    let s = &file.selection;
    builder = builder
        .rows(rows)
        .ranked(RankedIndex {
            measure,
            joint_limit_penalty,
            over,
        })
        .norm(spelled_setting(&s.norm, "selection.norm", &err)?)
        .mu0(s.mu0)
        .likelihood(match s.likelihood.unwrap_or_default() {
            LikelihoodFile::Product => LikelihoodRule::Product,
            LikelihoodFile::Ignore => LikelihoodRule::Ignore,
            LikelihoodFile::Weighted { weight } => LikelihoodRule::Weighted { weight },
        });
    if let Some(pairs) = s.pairs {
        builder = builder.pairs(pairs);
    }
    if let Some(d) = s.min_separation {
        builder = builder.min_separation(d);
    }
    if let Some(t) = s.tie_tolerance {
        builder = builder.tie_tolerance(t);
    }
    let ik = &file.ik;
    if let Some(step) = ik.max_joint_step {
        builder = builder.max_joint_step(step);
    }
    if let Some(margin) = ik.limit_margin {
        builder = builder.ik_limit_margin(margin);
    }
    if let Some(branches) = ik.branches {
        builder = builder.ik_branches(branches);
    }
    if let Some(seed) = ik.random_seed {
        builder = builder.ik_random_seed(seed);
    }
    if let Some(tolerance) = ik.tolerance {
        builder = builder.ik_tolerance(tolerance);
    }
    if let Some(iterations) = ik.iterations {
        builder = builder.grasp_ik_iterations(iterations);
    }
    builder = builder.redundancy(spelled_setting(&ik.redundancy, "ik.redundancy", &err)?);
    if let Some(min) = s.min_clearance {
        builder = builder.min_clearance(Some(min));
    }
    if let Some(min) = s.min_torque_margin {
        builder = builder.min_torque_margin(Some(min));
    }
    builder = builder
        .max_duration(s.max_duration)
        .timing(timing_request(file.timing.as_ref()));
    super::load_scene::add_world(builder, file, source_name, base_dir, scene, &model)
}

/// The setting spelled at `field` (its [`Spelled`] table), or its default when the field is
/// absent.
fn spelled_setting<T: Spelled + Default>(
    value: &Option<String>,
    field: &str,
    err: &impl Fn(&str, String) -> TaskError,
) -> Result<T, TaskError> {
    value.as_deref().map_or(Ok(T::default()), |name| {
        T::parse(name).map_err(|m| err(field, m))
    })
}

/// An arm as the file describes it: name, chain, `world_from_base`.
type ArmParts = (String, Chain, Isometry3<f64>);

fn setup_arms(
    file: &TaskFile,
    source: &str,
    base_dir: &Path,
) -> Result<(String, Vec<ArmParts>, RobotModel), TaskError> {
    let err = |field: &str, message: String| TaskError::new(source, field, message);
    let robot = &file.robot;
    let default_tool = robot
        .tool
        .as_ref()
        .map(|t| pose(t, source, "robot.tool"))
        .transpose()?;
    // The one robot-source resolver (shared with the CLI, Python and the hand loader).
    let search_paths: Vec<PathBuf> = robot
        .search_paths
        .iter()
        .map(|p| base_dir.join(p))
        .collect();
    let xacro_args: BTreeMap<String, String> = robot
        .xacro_args
        .iter()
        .map(|(name, value)| (name.clone(), value.text()))
        .collect();
    let named = [
        robot.builtin.is_some(),
        robot.urdf.is_some(),
        robot.mjcf.is_some(),
        robot.file.is_some(),
    ];
    if named.iter().filter(|&&n| n).count() > 1 {
        return Err(err(
            "robot",
            "give one of builtin, urdf, mjcf and file, not several".into(),
        ));
    }
    let (robot_source, source_field) =
        match (&robot.builtin, &robot.urdf, &robot.mjcf, &robot.file) {
            (Some(name), ..) => (RobotSource::builtin(name.as_str()), "robot.builtin"),
            (_, Some(path), ..) => (RobotSource::urdf(base_dir.join(path)), "robot.urdf"),
            (_, _, Some(path), _) => (RobotSource::mjcf(base_dir.join(path)), "robot.mjcf"),
            (_, _, _, Some(path)) => (
                RobotSource::from_path(base_dir.join(path))
                    .map_err(|e| TaskError::caused_by(source, "robot.file", e))?,
                "robot.file",
            ),
            (None, None, None, None) => return Err(err(
                "robot",
                "give builtin: baxter, or urdf: FILE (or mjcf: FILE, or file: FILE) with chains"
                    .into(),
            )),
        };
    let options_field = if robot.search_paths.is_empty() {
        "robot.xacro_args"
    } else {
        "robot.search_paths"
    };
    let robot_source = robot_source
        .with_urdf_options(search_paths, xacro_args)
        .map_err(|e| TaskError::caused_by(source, options_field, e))?;
    let model = robot_source
        .load()
        .map_err(|e| TaskError::caused_by(source, source_field, e))?;
    let default_tool = default_tool.or(stock_gripper_mount(file, source, &model)?);
    let available: Vec<String> = if model.is_builtin() {
        model.chain_names()
    } else {
        robot.chains.keys().cloned().collect()
    };
    if available.is_empty() {
        return Err(err(
            "robot.chains",
            "a URDF or MJCF robot needs at least one chain (name: {base, tip})".into(),
        ));
    }
    let names: Vec<String> = match &file.arms {
        None => vec![available[0].clone()],
        Some(ArmsFile::One(s)) if s == "both" || s == "all" => available.clone(),
        Some(ArmsFile::One(s)) => vec![s.clone()],
        Some(ArmsFile::Many(list)) => list.clone(),
    };
    if names.is_empty() {
        return Err(err("arms", "name at least one arm".into()));
    }
    for name in robot.chains.keys() {
        if !available.contains(name) {
            return Err(err(
                &format!("robot.chains.{name}"),
                format!("unknown arm (arms: {})", available.join(", ")),
            ));
        }
    }
    let mut arms = Vec::new();
    for (k, name) in names.iter().enumerate() {
        if !available.contains(name) {
            return Err(err(
                &format!("arms[{k}]"),
                format!("unknown arm '{name}' (arms: {})", available.join(", ")),
            ));
        }
        if names[..k].contains(name) {
            return Err(err(
                &format!("arms[{k}]"),
                format!("arm '{name}' is listed twice"),
            ));
        }
        let arm_file = robot.chains.get(name);
        let field = format!("robot.chains.{name}");
        let tool = match arm_file.and_then(|a| a.tool.as_ref()) {
            Some(t) => Some(pose(t, source, &format!("{field}.tool"))?),
            None => default_tool,
        };
        let world_from_base = match arm_file.and_then(|a| a.base_pose.as_ref()) {
            Some(p) => pose(p, source, &format!("{field}.base_pose"))?,
            None => Isometry3::identity(),
        };
        let chain = if model.is_builtin() {
            if arm_file.is_some_and(|a| a.base.is_some() || a.tip.is_some()) {
                return Err(err(
                    &field,
                    "the built-in robot's chains are fixed; give only tool or base_pose".into(),
                ));
            }
            model.named_chain(name, tool)
        } else {
            let a = arm_file.expect("URDF arms come from robot.chains");
            let (Some(base), Some(tip)) = (&a.base, &a.tip) else {
                return Err(err(&field, "a URDF chain needs base and tip links".into()));
            };
            model.chain(base, tip, tool)
        }
        .map_err(|e| TaskError::caused_by(source, &field, e))?;
        arms.push((name.clone(), chain, world_from_base));
    }
    narrow_joint_ranges(&mut arms, &robot.joint_limits, source)?;
    Ok((model.name().to_string(), arms, model))
}

/// The tool offset a stock gripper (`gripper.builtin`) implies for a chain without one: the
/// gripper is bolted to the chain's tip, its flange, so the tool frame is its TCP,
/// `Tz(`[`StockGripper::flange_to_tcp`]`)` beyond it. `None` without a stock gripper, and on a
/// built-in robot whose chains already end at that gripper's TCP (Baxter with its gripper, the
/// Panda and the FR3 with the Franka Hand); another gripper on those is an error, since their
/// chains and collision models include their own.
fn stock_gripper_mount(
    file: &TaskFile,
    source: &str,
    model: &RobotModel,
) -> Result<Option<Isometry3<f64>>, TaskError> {
    let Some(name) = file.gripper.as_ref().and_then(|g| g.builtin.as_deref()) else {
        return Ok(None);
    };
    let Some(gripper) = StockGripper::from_name(name) else {
        // gripper_from names the error.
        return Ok(None);
    };
    let own = match model.builtin() {
        Some(BuiltinRobot::Baxter) => Some((StockGripper::Baxter, "{arm}_gripper")),
        Some(BuiltinRobot::Panda) => Some((StockGripper::FrankaHand, "panda_hand_tcp")),
        Some(BuiltinRobot::Fr3) => Some((StockGripper::FrankaHand, "fr3_hand_tcp")),
        _ => None,
    };
    match own {
        Some((own, _)) if own == gripper => Ok(None),
        Some((own, tip)) => Err(TaskError::new(
            source,
            "gripper.builtin",
            format!(
                "the built-in {} ends at its own gripper's TCP ({tip}) and models that \
                 gripper; use builtin: {}, or load the arm from a URDF ending at its flange",
                model.name(),
                own.as_str()
            ),
        )),
        None => Ok(Some(Isometry3::translation(
            0.0,
            0.0,
            gripper.flange_to_tcp(),
        ))),
    }
}

/// A gripper given by its size (`opening`) or as a URDF hand without `tool_from_root`, on an
/// arm whose chain ends at its flange and that has no tool offset: the gripper's frame is then
/// the flange, its finger tips sit on it, and every grasp puts the wrist inside the object.
/// A flange is the tip of a built-in arm without its own gripper (UR, iiwa, xArm, Gen3), or a
/// robot file's tip named like one (`tool0`, `*flange*`, `link_eef`, `end_effector_link`,
/// `*link8`, `ee_link`). Stock grippers mount themselves ([`stock_gripper_mount`]).
fn gripper_at_flange_warnings(
    file: &TaskFile,
    arms: &[ArmParts],
    model: &RobotModel,
) -> Vec<TaskWarning> {
    let Some(gripper) = &file.gripper else {
        return Vec::new();
    };
    if gripper.builtin.is_some() || gripper.tool_from_root.is_some() || file.robot.tool.is_some() {
        return Vec::new();
    }
    let at_flange = |tip: &str| match model.builtin() {
        Some(BuiltinRobot::Baxter | BuiltinRobot::Panda | BuiltinRobot::Fr3) => false,
        Some(_) => true,
        None => {
            let tip = tip.to_ascii_lowercase();
            tip == "tool0"
                || tip.contains("flange")
                || tip.ends_with("link_eef")
                || tip.ends_with("end_effector_link")
                || tip.ends_with("link8")
                || tip.ends_with("ee_link")
        }
    };
    arms.iter()
        .filter(|(name, chain, _)| {
            let own_tool = file
                .robot
                .chains
                .get(name)
                .is_some_and(|a| a.tool.is_some());
            !own_tool && at_flange(chain.tip_link())
        })
        .map(|(name, chain, _)| TaskWarning {
            field: "gripper".into(),
            message: format!(
                "arm '{name}' ends at its flange '{}' and no tool offset is given: the \
                 gripper's finger tips sit on the flange, so every grasp puts the wrist inside \
                 the object; give the flange-to-TCP offset as robot.tool (e.g. {{ xyz: [0, 0, \
                 0.15] }}), or a stock gripper (gripper.builtin: {}), which mounts itself",
                chain.tip_link(),
                StockGripper::spellings()
            ),
        })
        .collect()
}

/// Applies `robot.joint_limits` to every arm whose chain has the joint; a joint on no arm is
/// an error that lists the arms' joints.
fn narrow_joint_ranges(
    arms: &mut [ArmParts],
    ranges: &BTreeMap<String, [f64; 2]>,
    source: &str,
) -> Result<(), TaskError> {
    for (joint, &[lower, upper]) in ranges {
        let field = format!("robot.joint_limits.{joint}");
        let mut found = false;
        for (_, chain, _) in arms.iter_mut() {
            if chain.joint_names().iter().any(|n| n == joint) {
                *chain = chain
                    .with_joint_range(joint, lower, upper)
                    .map_err(|e| TaskError::caused_by(source, &field, e))?;
                found = true;
            }
        }
        if !found {
            let known: Vec<&str> = arms
                .iter()
                .flat_map(|(_, chain, _)| chain.joint_names().iter().map(String::as_str))
                .collect();
            return Err(TaskError::new(
                source,
                &field,
                format!(
                    "no arm of the task has an independent joint '{joint}' (joints: {})",
                    known.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

fn step_of(step: &StepFile, k: usize, source: &str) -> Result<TimedStep, TaskError> {
    let field = format!("trajectory.steps[{k}]");
    let err = |sub: &str, message: String| TaskError::new(source, format!("{field}{sub}"), message);
    let finite = |sub: &str, v: f64| {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(err(sub, "not finite".into()))
        }
    };
    let mut translation = Vector3::zeros();
    let mut parts = Vec::new();
    if let Some(h) = step.lift {
        translation.z += finite(".lift", h)?;
        parts.push("lift");
    }
    if let Some(h) = step.place {
        translation.z -= finite(".place", h)?;
        parts.push("place");
    }
    if let Some(m) = step.translate {
        for v in m {
            finite(".move", v)?;
        }
        translation += Vector3::from(m);
        parts.push("move");
    }
    let (axis, angle) = match &step.rotate {
        Some(r) => {
            let axis = Vector3::from(r.axis.unwrap_or([0.0, 0.0, 1.0]));
            let axis = Unit::try_new(axis, 1e-9)
                .filter(|a| a.iter().all(|v| v.is_finite()))
                .ok_or_else(|| err(".rotate.axis", "must be a finite non-zero vector".into()))?;
            parts.push("rotate");
            (axis, finite(".rotate.angle_deg", r.angle_deg)?.to_radians())
        }
        None => (Vector3::z_axis(), 0.0),
    };
    let motion = match &step.pose {
        Some(p) => {
            if !parts.is_empty() {
                return Err(err(
                    ".pose",
                    "an absolute pose cannot be combined with lift/place/move/rotate".into(),
                ));
            }
            parts.push("pose");
            Step::Pose(pose(p, source, &format!("{field}.pose"))?)
        }
        None => {
            if parts.is_empty() {
                return Err(err(
                    "",
                    "a step needs lift, place, move, rotate or pose".into(),
                ));
            }
            Step::Relative {
                translation,
                axis,
                angle,
            }
        }
    };
    let duration = step.duration.unwrap_or(defaults::STEP_DURATION);
    if !(duration.is_finite() && duration > 0.0) {
        return Err(err(
            ".duration",
            "must be a positive number of seconds".into(),
        ));
    }
    Ok(TimedStep {
        label: step.label.clone().unwrap_or_else(|| parts.join("+")),
        step: motion,
        duration,
    })
}

/// The file's steps and sampling; the path is sampled by the builder once the sample count
/// has been checked against the limits.
fn setup_steps(file: &TaskFile, source: &str) -> Result<(Vec<TimedStep>, Sampling), TaskError> {
    let t = &file.trajectory;
    if t.steps.is_empty() {
        return Err(TaskError::new(
            source,
            "trajectory.steps",
            "give at least one step",
        ));
    }
    let steps = t
        .steps
        .iter()
        .enumerate()
        .map(|(k, s)| step_of(s, k, source))
        .collect::<Result<Vec<_>, _>>()?;
    let sampling = match (t.samples_per_step, t.samples, &t.spacing) {
        (None, None, None) => Sampling::PerStep(defaults::SAMPLES_PER_STEP),
        (Some(n), None, None) => Sampling::PerStep(n),
        (None, Some(n), None) => Sampling::Total(n),
        (None, None, Some(s)) => Sampling::Spacing {
            translation: s.translation,
            rotation: s.rotation_deg.to_radians(),
        },
        _ => {
            return Err(TaskError::new(
                source,
                "trajectory",
                "give one of samples_per_step, samples, spacing",
            ))
        }
    };
    Ok((steps, sampling))
}

/// The task file's `timing:` as a request (absent: [`TimingRequest::Auto`]).
fn timing_request(timing: Option<&TimingFile>) -> TimingRequest {
    let defaults = TimingSettings::default();
    match timing {
        None => TimingRequest::Auto,
        Some(TimingFile::Switch(false)) => TimingRequest::Off,
        Some(TimingFile::Switch(true)) => TimingRequest::On(defaults),
        Some(TimingFile::Settings(t)) => TimingRequest::On(TimingSettings {
            stops: t.stops.unwrap_or(defaults.stops),
            subdivisions: t.subdivisions.unwrap_or(defaults.subdivisions),
            velocity_scale: t.velocity_scale.unwrap_or(defaults.velocity_scale),
            acceleration_scale: t.acceleration_scale.unwrap_or(defaults.acceleration_scale),
            max_acceleration: t.max_acceleration.or(defaults.max_acceleration),
            acceleration_time: t.acceleration_time.unwrap_or(defaults.acceleration_time),
            torque_limits: t.torque_limits.unwrap_or(defaults.torque_limits),
            object_speed: t.object_speed,
            object_turn_rate: t.object_turn_rate,
            object_acceleration: t.object_acceleration,
            object_angular_acceleration: t.object_angular_acceleration,
        }),
    }
}
