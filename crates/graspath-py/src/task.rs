//! `graspath.Task`: a selection task (robot arms, object path, grasp candidates, index and
//! ranking settings) from a task file, task text, a dict, or numpy arrays.

use crate::convert::{
    array, check_shape, error, index_mode, lib_error, poses, push_isometry, single_pose, spelled,
    Buffer, FloatArray,
};
use crate::pose::world_from_object;
use crate::robot::PyRobot;
use graspath::defaults;
use graspath::grasp::Candidate;
use graspath::grasp::{GraspFormat, GraspFrame};
use graspath::manipulability::{IndexMeasure, JacobianPart, JacobianRows, Norm, RankedIndex};
use graspath::robot::Chain;
use graspath::select::wrist_trajectory;
use graspath::spelling::Spelled;
use graspath::task::{
    builder_from_file, ArmSetup, LikelihoodRule, ObjectPath, PathSample, Redundancy, Task,
    TaskBuilder, TaskFile,
};
use graspath::timing::Discretization;
use nalgebra::{Isometry3, Point3};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::path::PathBuf;

/// A task ready for :func:`graspath.select`.
#[pyclass(module = "graspath", name = "Task", frozen)]
pub struct PyTask {
    pub(crate) task: Task,
}

impl PyTask {
    fn arm(&self, name: &str) -> PyResult<&ArmSetup> {
        self.task
            .arms()
            .iter()
            .find(|a| a.name == name)
            .ok_or_else(|| {
                error(format!(
                    "unknown arm '{name}' (arms: {})",
                    self.arm_names().join(", ")
                ))
            })
    }

    fn arm_names(&self) -> Vec<String> {
        self.task.arms().iter().map(|a| a.name.clone()).collect()
    }
}

/// The task defaults that `Task.from_arrays` spells out in its signature (literals, so that
/// Python shows them), keyed by keyword: `graspath.DEFAULTS`, which a test compares with the
/// signature. The values come from the library's `defaults`, defined once.
pub fn defaults_dict(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("length_scale", defaults::LENGTH_SCALE)?;
    dict.set_item("pairs", defaults::PAIRS)?;
    dict.set_item("norm", Norm::default().as_str())?;
    dict.set_item("min_separation", defaults::MIN_SEPARATION)?;
    dict.set_item("max_joint_step", defaults::MAX_JOINT_STEP)?;
    dict.set_item("ik_limit_margin", defaults::IK_LIMIT_MARGIN)?;
    dict.set_item("branches", defaults::IK_BRANCHES)?;
    dict.set_item("ik_tolerance", defaults::IK_TOLERANCE)?;
    dict.set_item("ik_iterations", defaults::GRASP_IK_ITERATIONS)?;
    Ok(dict)
}

/// Every spelling each named setting accepts, keyed by keyword (`norm`, `measure`, `mode`,
/// `redundancy`, `part`, `discretization`, `format`, `frame`): `graspath.SPELLINGS`, from the
/// library's spelling tables; a test compares it with the stub's `Literal` types.
pub fn spellings_dict(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    fn accepted<T: Spelled>() -> Vec<&'static str> {
        let mut names = T::names();
        names.extend(T::ALL.iter().flat_map(|value| value.aliases()));
        names
    }
    let dict = PyDict::new(py);
    dict.set_item("norm", accepted::<Norm>())?;
    dict.set_item("measure", accepted::<IndexMeasure>())?;
    dict.set_item("mode", JacobianRows::MODES.to_vec())?;
    dict.set_item("redundancy", accepted::<Redundancy>())?;
    dict.set_item("part", accepted::<JacobianPart>())?;
    dict.set_item("discretization", accepted::<Discretization>())?;
    dict.set_item("format", accepted::<GraspFormat>())?;
    dict.set_item("frame", accepted::<GraspFrame>())?;
    Ok(dict)
}

/// Parses `likelihood`: `"product"`, `"ignore"` or a float weight (`"weighted"` rule).
fn likelihood_rule(value: &Bound<'_, PyAny>) -> PyResult<LikelihoodRule> {
    if let Ok(text) = value.extract::<String>() {
        return match text.as_str() {
            "product" => Ok(LikelihoodRule::Product),
            "ignore" => Ok(LikelihoodRule::Ignore),
            other => Err(error(format!(
                "likelihood '{other}' is not 'product', 'ignore' or a weight (float >= 0)"
            ))),
        };
    }
    let weight: f64 = value
        .extract()
        .map_err(|_| error("likelihood must be 'product', 'ignore' or a weight (float >= 0)"))?;
    Ok(LikelihoodRule::Weighted { weight })
}

/// An arm of `Task.from_arrays`: a `Robot`, or `(Robot, world_from_base)`.
fn arm_setup(name: &str, value: &Bound<'_, PyAny>) -> PyResult<(Chain, Isometry3<f64>)> {
    let (robot, world_from_base) = if let Ok(robot) = value.cast::<PyRobot>() {
        (robot.clone(), Isometry3::identity())
    } else if let Ok(pair) = value.cast::<PyTuple>() {
        if pair.len() != 2 {
            return Err(error(format!(
                "arm '{name}': give a Robot or a (Robot, world_from_base) pair"
            )));
        }
        let robot = pair.get_item(0)?;
        let robot = robot.cast::<PyRobot>().map_err(|_| {
            error(format!(
                "arm '{name}': the first item must be a graspath.Robot"
            ))
        })?;
        let pose: FloatArray<'_> = pair.get_item(1)?.extract()?;
        (
            robot.clone(),
            single_pose(&pose, &format!("arms['{name}'] world_from_base"))?,
        )
    } else {
        return Err(error(format!(
            "arm '{name}': give a Robot or a (Robot, world_from_base) pair"
        )));
    };
    Ok((robot.get().chain.clone(), world_from_base))
}

#[pymethods]
impl PyTask {
    /// Reads and checks a task file (YAML or JSON; the schema of ``docs/task-file.md``).
    /// Relative paths inside it are relative to the file.
    ///
    /// ``candidates``: a candidate file (graspath JSON/CSV or a grasp generator's file;
    /// relative to the current directory) read instead of the file's ``candidates`` source —
    /// the task file's ``candidates`` options (``format``, ``frame``, ``world_from_camera``,
    /// ``camera_from_object``, ``gripper_from_tool``, ``segment``) apply to it, a ``family`` or
    /// ``generate`` is dropped. One task file then serves many candidate files.
    ///
    /// ``object_pose``: the object's start pose ``world_from_object`` (world frame, m) instead
    /// of the file's ``object.pose``: a dict in the task file's pose syntax (``{"xyz": [x, y,
    /// z]}`` with at most one of ``"rpy"`` (rad), ``"rpy_deg"`` or ``"quaternion"`` ``[x, y,
    /// z, w]``, or a ``"matrix"`` alone; see :func:`pose_matrix`) or a 4×4 array. The
    /// trajectory's relative steps start from it, absolute ``pose`` steps, the robot and the
    /// scene stay, as in :func:`placement_map`: the task is the one a task file with this
    /// ``object.pose`` describes (candidates generated by the learned model in a scene keep the
    /// hand-clearance filtering done at the file's pose). One task file then serves many
    /// placed objects. Errors name the field (``object_pose.quaternion``, …).
    #[staticmethod]
    #[pyo3(signature = (path, *, candidates = None, object_pose = None))]
    fn load(
        path: PathBuf,
        candidates: Option<PathBuf>,
        object_pose: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let name = path.display().to_string();
        let world_from_object = object_pose
            .map(|value| world_from_object(value, &name))
            .transpose()?;
        if candidates.is_none() && world_from_object.is_none() {
            return Ok(Self {
                task: Task::load(&path).map_err(lib_error)?,
            });
        }
        let mut file = TaskFile::load(&path).map_err(lib_error)?;
        if let Some(candidates) = candidates {
            let candidates = std::path::absolute(&candidates)
                .map_err(|e| error(format!("{}: {e}", candidates.display())))?;
            file.candidates.file = Some(candidates);
            file.candidates.family = None;
            file.candidates.generate = None;
        }
        let base_dir = path.parent().map(PathBuf::from).unwrap_or_default();
        let task = match world_from_object {
            None => Task::from_file(&file, &name, &base_dir),
            Some(pose) => builder_from_file(&file, &name, &base_dir)
                .and_then(|builder| builder.with_object_start(pose))
                .and_then(TaskBuilder::build),
        };
        Ok(Self {
            task: task.map_err(lib_error)?,
        })
    }

    /// Parses task text (``format`` ``"yaml"`` or ``"json"``); relative paths in it are
    /// resolved against ``base_dir``; ``name`` names the text in errors and in the summary.
    #[staticmethod]
    #[pyo3(signature = (text, format = "yaml", base_dir = None, name = "<task>"))]
    fn parse(text: &str, format: &str, base_dir: Option<PathBuf>, name: &str) -> PyResult<Self> {
        let file = TaskFile::parse(text, name, format).map_err(lib_error)?;
        let base_dir = base_dir.unwrap_or_else(|| PathBuf::from("."));
        Ok(Self {
            task: Task::from_file(&file, name, &base_dir).map_err(lib_error)?,
        })
    }

    /// A task from a dict with the task file's schema (as ``yaml.safe_load`` would give).
    #[staticmethod]
    #[pyo3(signature = (data, base_dir = None, name = "<dict>"))]
    fn from_dict(
        py: Python<'_>,
        data: &Bound<'_, PyAny>,
        base_dir: Option<PathBuf>,
        name: &str,
    ) -> PyResult<Self> {
        let text: String = py
            .import("json")?
            .call_method1("dumps", (data,))?
            .extract()?;
        Self::parse(&text, "json", base_dir, name)
    }

    /// A task from arrays.
    ///
    /// * ``arms``: a dict ``name -> Robot`` or ``name -> (Robot, world_from_base)`` (4×4; the
    ///   chain base in the world frame, default identity), in the order used for pairs.
    /// * ``object_poses``: ``(n, 4, 4)`` ``world_from_object`` along the task; the first is the
    ///   grasp pose. ``times``: ``(n,)`` seconds (default ``0, 1, 2, …``).
    /// * ``candidates``: ``(k, 4, 4)`` ``object_from_wrist`` grasp candidates, with optional
    ///   ``likelihoods`` ``(k,)`` (> 0), ``labels`` and ``contacts`` ``(k, 3)`` (object frame;
    ///   NaN rows = unknown).
    /// * settings as in the task file: ``mode`` (``twist``/``translation``/``rotation``),
    ///   ``length_scale``, ``norm`` (``rms``/``l2``/``l1``), ``mu0``, ``likelihood`` (``"product"``,
    ///   ``"ignore"`` or a weight), ``pairs``, ``min_separation`` (m), and the trajectory IK's
    ///   ``max_joint_step``, ``branches``, ``ik_random_seed`` (the random seed of the IK's
    ///   restarts; default 0), ``ik_tolerance``, ``ik_iterations``, ``redundancy``
    ///   (``"first"``, ``"best_branch"`` or ``"optimize"``: the task file's ``ik.redundancy``);
    ///   ``measure``
    ///   (``"task_relevant"``, ``"velocity_ratio"``, ``"duration"`` or ``"dynamic"``: the
    ///   last needs the robot's inertial data and effort limits) and ``joint_limit_penalty`` (Tsai's
    ///   penalty gain ``k``, e.g. 50; ``None``: none), the task file's ``index.measure`` and
    ///   ``index.joint_limit_penalty``; ``payload``, the carried object's mass properties
    ///   ``{"mass": kg, "com": [x, y, z] (object frame, m), "inertia": 3x3 or [ixx, iyy, izz]
    ///   (kg·m² about the centre of mass)}`` (the task file's ``object.mass``,
    ///   ``center_of_mass`` and ``inertia``): the joint torques are then checked along the task
    ///   and the ``torque_margin``, ``payload_capacity`` and ``dynamic_manipulability`` columns
    ///   reported (``docs/dynamics.md``).
    #[staticmethod]
    #[pyo3(signature = (
        arms,
        object_poses,
        candidates,
        *,
        times = None,
        likelihoods = None,
        labels = None,
        contacts = None,
        mode = "twist",
        length_scale = 1.0,
        norm = "rms",
        mu0 = None,
        likelihood = None,
        pairs = 10,
        min_separation = 0.08,
        max_joint_step = 0.5,
        ik_limit_margin = 0.1,
        branches = 4,
        ik_random_seed = None,
        ik_tolerance = 1e-5,
        ik_iterations = 200,
        redundancy = None,
        measure = "task_relevant",
        joint_limit_penalty = None,
        payload = None,
        name = "<arrays>",
        robot_name = "robot"
    ))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        arms: &Bound<'_, PyDict>,
        object_poses: FloatArray<'_>,
        candidates: FloatArray<'_>,
        times: Option<FloatArray<'_>>,
        likelihoods: Option<FloatArray<'_>>,
        labels: Option<Vec<String>>,
        contacts: Option<FloatArray<'_>>,
        mode: &str,
        length_scale: f64,
        norm: &str,
        mu0: Option<f64>,
        likelihood: Option<&Bound<'_, PyAny>>,
        pairs: usize,
        min_separation: f64,
        max_joint_step: f64,
        ik_limit_margin: f64,
        branches: usize,
        ik_random_seed: Option<u64>,
        ik_tolerance: f64,
        ik_iterations: usize,
        redundancy: Option<&str>,
        measure: &str,
        joint_limit_penalty: Option<f64>,
        payload: Option<&Bound<'_, PyAny>>,
        name: &str,
        robot_name: &str,
    ) -> PyResult<Self> {
        let ik_random_seed = ik_random_seed.unwrap_or(defaults::IK_RANDOM_SEED);
        let mut builder = Task::builder(name).robot_name(robot_name);
        for (key, value) in arms.iter() {
            let arm_name: String = key
                .extract()
                .map_err(|_| error("arm names (the keys of arms) must be strings"))?;
            let (chain, world_from_base) = arm_setup(&arm_name, &value)?;
            builder = builder.arm(arm_name, chain, world_from_base);
        }
        check_shape(&object_poses, &[None, Some(4), Some(4)], "object_poses")?;
        let (object_path, _) = poses(&object_poses, "object_poses")?;
        if object_path.is_empty() {
            return Err(error("object_poses: give at least one pose"));
        }
        let n = object_path.len();
        let times: Vec<f64> = match &times {
            None => (0..n).map(|i| i as f64).collect(),
            Some(t) => {
                check_shape(t, &[Some(n)], "times")?;
                Buffer::from_array(t, "times")?.data
            }
        };
        if times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|w| w[1] < w[0]) {
            return Err(error("times must be finite and non-decreasing (s)"));
        }
        check_shape(&candidates, &[None, Some(4), Some(4)], "candidates")?;
        let (candidate_poses, _) = poses(&candidates, "candidates")?;
        let k = candidate_poses.len();
        let log_likelihoods: Vec<f64> = match &likelihoods {
            None => vec![0.0; k],
            Some(l) => {
                check_shape(l, &[Some(k)], "likelihoods")?;
                let values = Buffer::from_array(l, "likelihoods")?.data;
                if let Some(i) = values.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
                    return Err(error(format!(
                        "likelihoods[{i}] must be a positive finite number"
                    )));
                }
                values.iter().map(|v| v.ln()).collect()
            }
        };
        if let Some(labels) = &labels {
            if labels.len() != k {
                return Err(error(format!(
                    "labels has {} entries but there are {k} candidates",
                    labels.len()
                )));
            }
        }
        let contact_points: Vec<Option<Point3<f64>>> = match &contacts {
            None => vec![None; k],
            Some(c) => {
                check_shape(c, &[Some(k), Some(3)], "contacts")?;
                Buffer::from_array(c, "contacts")?
                    .data
                    .chunks_exact(3)
                    .map(|p| {
                        p.iter()
                            .all(|v| v.is_finite())
                            .then(|| Point3::new(p[0], p[1], p[2]))
                    })
                    .collect()
            }
        };
        let candidates: Vec<Candidate> = candidate_poses
            .into_iter()
            .enumerate()
            .map(|(i, object_from_wrist)| Candidate {
                id: i,
                label: labels
                    .as_ref()
                    .map_or_else(|| format!("candidate {i}"), |l| l[i].clone()),
                object_from_wrist,
                log_likelihood: log_likelihoods[i],
                contact: contact_points[i],
                hand_joints: Vec::new(),
                width: None,
            })
            .collect();
        let norm: Norm = spelled("norm", norm)?;
        let likelihood = match likelihood {
            None => LikelihoodRule::Product,
            Some(value) => likelihood_rule(value)?,
        };
        let path = ObjectPath {
            samples: object_path
                .into_iter()
                .zip(&times)
                .map(|(world_from_object, &time)| PathSample {
                    time,
                    world_from_object,
                    step: 0,
                })
                .collect(),
            step_labels: vec!["path".to_string()],
        };
        if let Some(body) = crate::robot::payload_body(payload, "object")? {
            builder = builder.payload(body);
        }
        let task = builder
            .candidates(candidates)
            .object_path(path)
            .rows(index_mode(mode, length_scale)?)
            .norm(norm)
            .mu0(mu0)
            .likelihood(likelihood)
            .pairs(pairs)
            .min_separation(min_separation)
            .max_joint_step(max_joint_step)
            .ik_limit_margin(ik_limit_margin)
            .ik_branches(branches)
            .ik_random_seed(ik_random_seed)
            .ik_tolerance(ik_tolerance)
            .grasp_ik_iterations(ik_iterations)
            .redundancy(match redundancy {
                Some(name) => spelled("redundancy", name)?,
                None => Redundancy::default(),
            })
            .ranked(RankedIndex {
                measure: spelled("measure", measure)?,
                joint_limit_penalty,
                // An array task is one step: its norms are over every sample.
                ..RankedIndex::default()
            })
            .build()
            .map_err(lib_error)?;
        Ok(Self { task })
    }

    /// The same task with only the named arms, in the given order (e.g. one arm of a dual-arm
    /// task, or the two arms swapped).
    fn with_arms(&self, arms: Vec<String>) -> PyResult<Self> {
        Ok(Self {
            task: self.task.with_arms(&arms).map_err(lib_error)?,
        })
    }

    /// The task file (or the name given), as in the summary.
    #[getter]
    fn name(&self) -> String {
        self.task.source_name().to_string()
    }

    /// The robot's name.
    #[getter]
    fn robot_name(&self) -> String {
        self.task.robot_name().to_string()
    }

    /// Values that are probably mistakes — degrees in a radians field, millimetres, a
    /// quaternion written ``[w, x, y, z]``, an object starting inside the table or upside
    /// down (docs/task-file.md, "Plausibility warnings"): a list of ``(field, message)``.
    /// Warnings, not errors: the task is scored as written.
    #[getter]
    fn warnings(&self) -> Vec<(String, String)> {
        self.task
            .warnings()
            .iter()
            .map(|w| (w.field.clone(), w.message.clone()))
            .collect()
    }

    /// The arms, in order.
    #[getter]
    fn arms(&self) -> Vec<String> {
        self.arm_names()
    }

    /// The object path ``world_from_object``, shape ``(n, 4, 4)``; the first is the grasp pose.
    #[getter]
    fn object_poses<'py>(&self, py: Python<'py>) -> PyResult<Py<PyAny>> {
        let mut flat = Vec::with_capacity(16 * self.task.path().samples.len());
        for pose in self.task.path().poses() {
            push_isometry(&mut flat, pose);
        }
        let n = self.task.path().samples.len();
        Ok(array(py, flat, &[n, 4, 4])?.into_any().unbind())
    }

    /// The sample times (s), shape ``(n,)``.
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.task.path().times())
    }

    /// For each sample, the index of the step it ends in (0 for the initial pose).
    #[getter]
    fn sample_steps(&self) -> Vec<usize> {
        self.task.path().samples.iter().map(|s| s.step).collect()
    }

    /// The steps' labels, in order.
    #[getter]
    fn step_labels(&self) -> Vec<String> {
        self.task.path().step_labels.clone()
    }

    /// The candidates' wrist poses ``object_from_wrist``, shape ``(k, 4, 4)``.
    #[getter]
    fn candidate_poses<'py>(&self, py: Python<'py>) -> PyResult<Py<PyAny>> {
        let mut flat = Vec::with_capacity(16 * self.task.candidate_count());
        for c in self.task.all_candidates().map_err(lib_error)?.iter() {
            push_isometry(&mut flat, &c.object_from_wrist);
        }
        Ok(array(py, flat, &[self.task.candidate_count(), 4, 4])?
            .into_any()
            .unbind())
    }

    /// The candidates as dicts: ``id``, ``label``, ``object_from_wrist`` (4×4 array),
    /// ``likelihood``, ``log_likelihood``, ``contact`` (array of 3, or ``None``).
    #[getter]
    fn candidates<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for c in self.task.all_candidates().map_err(lib_error)?.iter() {
            let d = PyDict::new(py);
            d.set_item("id", c.id)?;
            d.set_item("label", &c.label)?;
            let mut flat = Vec::with_capacity(16);
            push_isometry(&mut flat, &c.object_from_wrist);
            d.set_item("object_from_wrist", array(py, flat, &[4, 4])?)?;
            d.set_item("likelihood", c.log_likelihood.exp())?;
            d.set_item("log_likelihood", c.log_likelihood)?;
            d.set_item(
                "contact",
                c.contact
                    .map(|p| PyArray1::from_vec(py, vec![p.x, p.y, p.z])),
            )?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The robot chain of one arm.
    fn robot(&self, arm: &str) -> PyResult<PyRobot> {
        Ok(PyRobot::new(self.arm(arm)?.chain.clone()))
    }

    /// Where one arm's chain base is in the task's world frame, ``world_from_base`` (4×4).
    fn world_from_base<'py>(&self, py: Python<'py>, arm: &str) -> PyResult<Py<PyAny>> {
        let mut flat = Vec::with_capacity(16);
        push_isometry(&mut flat, &self.arm(arm)?.world_from_base);
        Ok(array(py, flat, &[4, 4])?.into_any().unbind())
    }

    /// The wrist poses ``base_from_wrist`` (in the arm's base frame), shape ``(n, 4, 4)``, that
    /// candidate number ``candidate`` (its position in :attr:`candidates`) asks of ``arm``:
    /// the targets of the trajectory IK.
    fn wrist_trajectory<'py>(
        &self,
        py: Python<'py>,
        candidate: usize,
        arm: &str,
    ) -> PyResult<Py<PyAny>> {
        let setup = self.arm(arm)?;
        let c = self
            .task
            .candidate_at(candidate)
            .map_err(lib_error)?
            .ok_or_else(|| {
                error(format!(
                    "candidate {candidate} is out of range (the task has {})",
                    self.task.candidate_count()
                ))
            })?;
        let poses = wrist_trajectory(
            self.task.path(),
            &setup.world_from_base,
            &c.object_from_wrist,
        );
        let mut flat = Vec::with_capacity(16 * poses.len());
        for p in &poses {
            push_isometry(&mut flat, p);
        }
        Ok(array(py, flat, &[poses.len(), 4, 4])?.into_any().unbind())
    }

    fn __len__(&self) -> usize {
        self.task.candidate_count()
    }

    fn __repr__(&self) -> String {
        format!(
            "Task('{}', robot='{}', arms={:?}, candidates={}, samples={})",
            self.task.source_name(),
            self.task.robot_name(),
            self.arm_names(),
            self.task.candidate_count(),
            self.task.path().samples.len()
        )
    }
}
