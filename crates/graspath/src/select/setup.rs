//! Turning a task file into a runnable [`Task`]: robot chains, candidates, the sampled object
//! path and the index and selection settings, every value checked with the field it came from.

use super::rank::{LikelihoodRule, Norm, SelectionOptions};
use crate::cloud::load_cloud_argument;
use crate::geometry::{pose_from_rows, quaternion_xyzw};
use crate::grasp::model::{generate, GenerateOptions, GraspModel};
use crate::grasp::{edge_family, face_family, read_candidates, yaw_family, Candidate};
use crate::manipulability::IndexMode;
use crate::robot::builtin::{baxter_spec, Arm};
use crate::robot::{Chain, TrajectoryIkOptions, UrdfRobot};
use crate::task::{
    ArmsFile, FamilyFile, GenerateFile, LikelihoodFile, NormFile, ObjectPath, ObjectShape,
    PoseFile, Sampling, StepFile, TaskError, TaskFile,
};
use crate::task::{Step, TimedStep};
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use std::path::{Path, PathBuf};

/// The default IK iteration budget of a candidate's grasp sample (over all restarts).
pub const DEFAULT_GRASP_ITERATIONS: usize = 200;

/// One arm taking part in the task.
#[derive(Debug, Clone)]
pub struct ArmSetup {
    /// The arm's name (`left`, `right`, or the key in `robot.chains`).
    pub name: String,
    /// Its kinematic chain (poses and Jacobians in the chain's base frame).
    pub chain: Chain,
    /// Where the chain's base is in the task's world frame, `world_from_base`.
    pub world_from_base: Isometry3<f64>,
}

/// A task ready to score: who, what, where to grasp, and how the object must move.
#[derive(Debug, Clone)]
pub struct Task {
    /// The task file, for messages and reports.
    pub source_name: String,
    /// The robot's name (`baxter` or the URDF robot's name).
    pub robot_name: String,
    /// The arms used, in the order given.
    pub arms: Vec<ArmSetup>,
    /// The object's shape, when given.
    pub shape: Option<ObjectShape>,
    /// The grasp candidates (wrist poses in the object frame).
    pub candidates: Vec<Candidate>,
    /// The sampled object trajectory in the world frame; its first pose is the grasp pose.
    pub path: ObjectPath,
    /// How the task-relevant index is computed.
    pub mode: IndexMode,
    /// How candidates are ranked.
    pub selection: SelectionOptions,
    /// Trajectory IK settings.
    pub ik: TrajectoryIkOptions,
    /// Track every IK branch and keep the best (else the first feasible branch is scored).
    pub compare_branches: bool,
}

impl Task {
    /// Reads and checks a task file (YAML or JSON).
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
        let err = |field: &str, message: String| TaskError::new(source_name, field, message);
        let (robot_name, arms) = setup_arms(file, source_name, base_dir)?;
        let world_from_object = pose(&file.object.pose, source_name, "object.pose")?;
        let shape = file
            .object
            .shape
            .as_ref()
            .map(checked_shape)
            .transpose()
            .map_err(|m| err("object.shape", m))?;
        let candidates = setup_candidates(file, source_name, base_dir, shape.as_ref())?;
        let path = setup_path(file, source_name, world_from_object)?;
        let mode = match file.index.mode.as_deref().unwrap_or("twist") {
            "twist" => {
                let length_scale = file.index.length_scale.unwrap_or(1.0);
                if !(length_scale.is_finite() && length_scale > 0.0) {
                    return Err(err(
                        "index.length_scale",
                        "must be a positive length in metres".into(),
                    ));
                }
                IndexMode::Twist { length_scale }
            }
            "translation" => IndexMode::Translation,
            "rotation" => IndexMode::Rotation,
            other => {
                return Err(err(
                    "index.mode",
                    format!("'{other}' is not one of twist, translation, rotation"),
                ))
            }
        };
        if file.index.length_scale.is_some() && !matches!(mode, IndexMode::Twist { .. }) {
            return Err(err(
                "index.length_scale",
                "only applies to mode 'twist'".into(),
            ));
        }
        let s = &file.selection;
        let mu0 = s.mu0;
        if let Some(mu0) = mu0 {
            if mu0.is_nan() || mu0 <= 0.0 {
                return Err(err("selection.mu0", "must be a positive number".into()));
            }
        }
        let likelihood = match s.likelihood.unwrap_or_default() {
            LikelihoodFile::Product => LikelihoodRule::Product,
            LikelihoodFile::Ignore => LikelihoodRule::Ignore,
            LikelihoodFile::Weighted { weight } => {
                if !(weight.is_finite() && weight >= 0.0) {
                    return Err(err(
                        "selection.likelihood.weighted.weight",
                        "must be a number ≥ 0".into(),
                    ));
                }
                LikelihoodRule::Weighted { weight }
            }
        };
        let min_separation = s.min_separation.unwrap_or(0.08);
        if !(min_separation.is_finite() && min_separation >= 0.0) {
            return Err(err(
                "selection.min_separation",
                "must be a distance ≥ 0 in metres".into(),
            ));
        }
        let selection = SelectionOptions {
            norm: match s.norm.unwrap_or_default() {
                NormFile::L2 => Norm::L2,
                NormFile::L1 => Norm::L1,
            },
            mu0,
            likelihood,
            pairs: s.pairs.unwrap_or(10),
            min_separation,
        };
        let mut ik = TrajectoryIkOptions::default();
        if let Some(step) = file.ik.max_joint_step {
            if !(step.is_finite() && step > 0.0) {
                return Err(err(
                    "ik.max_joint_step",
                    "must be a positive angle in radians".into(),
                ));
            }
            ik.max_joint_step = step;
        }
        if let Some(branches) = file.ik.branches {
            if branches == 0 {
                return Err(err("ik.branches", "must be at least 1".into()));
            }
            ik.branches = branches;
        }
        ik.ik.max_iterations = file.ik.iterations.unwrap_or(DEFAULT_GRASP_ITERATIONS);
        if ik.ik.max_iterations == 0 {
            return Err(err("ik.iterations", "must be at least 1".into()));
        }
        if let Some(seed) = file.ik.seed {
            ik.ik.random_seed = seed;
        }
        if let Some(tolerance) = file.ik.tolerance {
            if !(tolerance.is_finite() && tolerance > 0.0) {
                return Err(err("ik.tolerance", "must be positive".into()));
            }
            ik.ik.position_tolerance = tolerance;
            ik.ik.rotation_tolerance = tolerance;
        }
        Ok(Self {
            source_name: source_name.to_string(),
            robot_name,
            arms,
            shape,
            candidates,
            path,
            mode,
            selection,
            ik,
            compare_branches: file.ik.compare_branches.unwrap_or(false),
        })
    }

    /// The same task seen from another world frame: the object path and every arm base moved by
    /// `new_world_from_world`. Scores and rankings must not change.
    pub fn in_world_frame(&self, new_world_from_world: &Isometry3<f64>) -> Self {
        let mut moved = self.clone();
        moved.path = self.path.transformed(new_world_from_world);
        for arm in &mut moved.arms {
            arm.world_from_base = new_world_from_world * arm.world_from_base;
        }
        moved
    }
}

/// A pose from its file form; `field` names it in errors.
pub fn pose(p: &PoseFile, file: &str, field: &str) -> Result<Isometry3<f64>, TaskError> {
    let err = |sub: &str, message: String| TaskError::new(file, format!("{field}.{sub}"), message);
    if let Some(rows) = p.matrix {
        if p.xyz.is_some() || p.rpy.is_some() || p.rpy_deg.is_some() || p.quaternion.is_some() {
            return Err(err(
                "matrix",
                "give a matrix alone, or xyz with rpy / rpy_deg / quaternion".into(),
            ));
        }
        return pose_from_rows(&rows).map_err(|e| err("matrix", e.to_string()));
    }
    let xyz = p.xyz.unwrap_or([0.0; 3]);
    if xyz.iter().any(|v| !v.is_finite()) {
        return Err(err("xyz", format!("not finite: {xyz:?}")));
    }
    let rotations = [p.rpy.is_some(), p.rpy_deg.is_some(), p.quaternion.is_some()];
    if rotations.iter().filter(|&&b| b).count() > 1 {
        return Err(err(
            "rpy",
            "give at most one of rpy, rpy_deg, quaternion".into(),
        ));
    }
    let rotation = if let Some(rpy) = p.rpy {
        if rpy.iter().any(|v| !v.is_finite()) {
            return Err(err("rpy", format!("not finite: {rpy:?}")));
        }
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2])
    } else if let Some(deg) = p.rpy_deg {
        if deg.iter().any(|v| !v.is_finite()) {
            return Err(err("rpy_deg", format!("not finite: {deg:?}")));
        }
        UnitQuaternion::from_euler_angles(
            deg[0].to_radians(),
            deg[1].to_radians(),
            deg[2].to_radians(),
        )
    } else if let Some(q) = p.quaternion {
        quaternion_xyzw(q).ok_or_else(|| {
            err(
                "quaternion",
                "must be a finite, non-zero [x, y, z, w]".into(),
            )
        })?
    } else {
        UnitQuaternion::identity()
    };
    Ok(Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        rotation,
    ))
}

/// The shape, when every dimension is a positive length.
fn checked_shape(shape: &ObjectShape) -> Result<ObjectShape, String> {
    if shape.is_valid() {
        Ok(*shape)
    } else {
        Err("every dimension must be a positive length in metres".into())
    }
}

fn setup_arms(
    file: &TaskFile,
    source: &str,
    base_dir: &Path,
) -> Result<(String, Vec<ArmSetup>), TaskError> {
    let err = |field: &str, message: String| TaskError::new(source, field, message);
    let robot = &file.robot;
    let default_tool = robot
        .tool
        .as_ref()
        .map(|t| pose(t, source, "robot.tool"))
        .transpose()?;
    let available: Vec<String> = match (&robot.builtin, &robot.urdf) {
        (Some(name), None) if name == "baxter" => vec!["left".into(), "right".into()],
        (Some(name), None) => {
            return Err(err(
                "robot.builtin",
                format!("unknown built-in robot '{name}' (built in: baxter)"),
            ))
        }
        (None, Some(_)) => robot.chains.keys().cloned().collect(),
        (Some(_), Some(_)) => {
            return Err(err("robot", "give either builtin or urdf, not both".into()))
        }
        (None, None) => {
            return Err(err(
                "robot",
                "give builtin: baxter, or urdf: FILE with chains".into(),
            ))
        }
    };
    if available.is_empty() {
        return Err(err(
            "robot.chains",
            "a URDF robot needs at least one chain (name: {base, tip})".into(),
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
    let urdf = match &robot.urdf {
        Some(p) => {
            let full: PathBuf = base_dir.join(p);
            Some(UrdfRobot::from_file(&full).map_err(|e| err("robot.urdf", e.to_string()))?)
        }
        None => None,
    };
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
        let chain = match &urdf {
            Some(robot) => {
                let a = arm_file.expect("URDF arms come from robot.chains");
                let (Some(base), Some(tip)) = (&a.base, &a.tip) else {
                    return Err(err(&field, "a URDF chain needs base and tip links".into()));
                };
                robot
                    .chain(base, tip, tool)
                    .map_err(|e| err(&field, e.to_string()))?
            }
            None => {
                if arm_file.is_some_and(|a| a.base.is_some() || a.tip.is_some()) {
                    return Err(err(
                        &field,
                        "the built-in Baxter's chains are fixed; give only tool or base_pose"
                            .into(),
                    ));
                }
                let arm: Arm = name
                    .parse()
                    .map_err(|e: String| err(&format!("arms[{k}]"), e))?;
                let mut spec = baxter_spec(arm);
                spec.tip_from_tool = tool;
                Chain::from_spec(&spec).map_err(|e| err(&field, e.to_string()))?
            }
        };
        arms.push(ArmSetup {
            name: name.clone(),
            chain,
            world_from_base,
        });
    }
    let robot_name = urdf
        .as_ref()
        .map(|u| u.name().to_string())
        .unwrap_or_else(|| "baxter".into());
    Ok((robot_name, arms))
}

fn setup_candidates(
    file: &TaskFile,
    source: &str,
    base_dir: &Path,
    shape: Option<&ObjectShape>,
) -> Result<Vec<Candidate>, TaskError> {
    let err = |field: &str, message: String| TaskError::new(source, field, message);
    let positive = |field: &str, value: Option<f64>, default: f64| -> Result<f64, TaskError> {
        let v = value.unwrap_or(default);
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(err(field, "must be a length ≥ 0 in metres".into()))
        }
    };
    if let Some(generate) = &file.candidates.generate {
        if file.candidates.file.is_some() || file.candidates.family.is_some() {
            return Err(err(
                "candidates",
                "give one of file, family, generate".into(),
            ));
        }
        return generated_candidates(generate, source, base_dir);
    }
    match (&file.candidates.file, &file.candidates.family) {
        (Some(path), None) => {
            read_candidates(&base_dir.join(path)).map_err(|e| err("candidates.file", e.to_string()))
        }
        (None, Some(family)) => {
            let shape = shape.ok_or_else(|| {
                err(
                    "object.shape",
                    "a candidate family needs the object's shape".into(),
                )
            })?;
            let field = "candidates.family";
            match family {
                FamilyFile::Edge {
                    count,
                    depth,
                    margin,
                } => edge_family(
                    shape,
                    *count,
                    positive("candidates.family.edge.depth", *depth, 0.02)?,
                    positive("candidates.family.edge.margin", *margin, 0.02)?,
                ),
                FamilyFile::Yaw {
                    count,
                    step_deg,
                    start_deg,
                    depth,
                } => {
                    if !step_deg.is_finite() || !start_deg.unwrap_or(0.0).is_finite() {
                        return Err(err(
                            "candidates.family.yaw.step_deg",
                            "must be finite".into(),
                        ));
                    }
                    yaw_family(
                        shape,
                        *count,
                        start_deg.unwrap_or(0.0).to_radians(),
                        step_deg.to_radians(),
                        positive("candidates.family.yaw.depth", *depth, 0.02)?,
                    )
                }
                FamilyFile::Faces {
                    count,
                    exclude,
                    depth,
                } => face_family(
                    shape,
                    *count,
                    exclude,
                    positive("candidates.family.faces.depth", *depth, 0.02)?,
                ),
            }
            .map_err(|m| err(field, m))
        }
        (Some(_), Some(_)) => Err(err(
            "candidates",
            "give either file or family, not both".into(),
        )),
        (None, None) => Err(err(
            "candidates",
            "give file: PATH, family: {...} or generate: {model, cloud}".into(),
        )),
    }
}

/// Candidates from the learned grasp model, best first, with their log-likelihoods.
fn generated_candidates(
    g: &GenerateFile,
    source: &str,
    base_dir: &Path,
) -> Result<Vec<Candidate>, TaskError> {
    let err = |field: &str, message: String| TaskError::new(source, field, message);
    let model = GraspModel::read(&base_dir.join(&g.model))
        .map_err(|e| err("candidates.generate.model", e.to_string()))?;
    let cloud_path = base_dir.join(&g.cloud);
    let cloud = load_cloud_argument(&cloud_path)
        .map_err(|e| err("candidates.generate.cloud", e.to_string()))?;
    let defaults = GenerateOptions::default();
    let options = GenerateOptions {
        seed: g.seed.unwrap_or(0),
        seeds: g.seeds.unwrap_or(defaults.seeds),
        steps: g.steps.unwrap_or(defaults.steps),
        query_kernels: g.query_kernels.unwrap_or(defaults.query_kernels),
        ..defaults
    };
    let mut generated = generate(
        &model,
        &cloud,
        &options,
        &cloud_path.display().to_string(),
        &|_| {},
    )
    .map_err(|e| err("candidates.generate", e.to_string()))?;
    if let Some(n) = g.max_candidates {
        generated.truncate(n);
    }
    if generated.is_empty() {
        return Err(err(
            "candidates.generate",
            "the model generated no candidate on this cloud".into(),
        ));
    }
    Ok(generated
        .into_iter()
        .enumerate()
        .map(|(id, c)| Candidate {
            id,
            label: format!("{} #{id}", model.label),
            object_from_wrist: c.object_from_wrist,
            log_likelihood: c.log_likelihood,
            contact: c.contact,
            hand_joints: c.hand_joints,
        })
        .collect())
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
    let duration = step.duration.unwrap_or(1.0);
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

fn setup_path(
    file: &TaskFile,
    source: &str,
    world_from_object: Isometry3<f64>,
) -> Result<ObjectPath, TaskError> {
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
        (None, None, None) => Sampling::PerStep(10),
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
    ObjectPath::sample(world_from_object, &steps, sampling)
        .map_err(|m| TaskError::new(source, "trajectory", m))
}
