//! `graspath.select` and `graspath.Selection`: scoring and ranking every candidate of a task,
//! with the same records the CLI writes (`candidates.json`, `pairs.json`, `summary.json`).

use crate::convert::{array, error, json_to_py, lib_error};
use crate::record::{gather_columns, set_gathered_columns};
use crate::task::PyTask;
use graspath::output_files::{write_files, Existing};
use graspath::select::record::{outputs, Row, Trajectories};
use graspath::select::{select as run_selection, selected_motions, Selection};
use graspath::spelling::Spelled;
use graspath::task::Task;
use graspath_report::{candidates_json, pairs_json, summary_json, trajectory_files};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// The result of :func:`select`.
#[pyclass(module = "graspath", name = "Selection", frozen)]
pub struct PySelection {
    task: Task,
    selection: Selection,
}

/// Pretty JSON with a final newline, exactly as `graspath select` writes its files.
fn pretty(value: &serde_json::Value) -> PyResult<Vec<u8>> {
    let mut bytes = serde_json::to_vec_pretty(value).map_err(|e| error(e.to_string()))?;
    bytes.push(b'\n');
    Ok(bytes)
}

/// Scores every candidate of ``task`` along its object path for each arm (trajectory IK,
/// ``M_T`` at every sample, the norms μ_l2, μ_l∞, μ_l1 and the indices at the grasp), ranks
/// them per arm and, with two arms, ranks the pairs. Runs in parallel without the GIL;
/// deterministic. A selection whose estimated memory exceeds the task's
/// ``limits.max_memory_mib`` is refused before any work (use :func:`select_batch`).
#[pyfunction]
pub fn select(py: Python<'_>, task: &Bound<'_, PyTask>) -> PyResult<PySelection> {
    let task = task.get().task.clone();
    task.check_selection_memory().map_err(lib_error)?;
    let selection = py
        .detach(|| run_selection(&task, &|| {}))
        .map_err(lib_error)?;
    Ok(PySelection { task, selection })
}

#[pymethods]
impl PySelection {
    /// One record per candidate and arm, in candidate order, arm by arm: the list the CLI
    /// writes to ``candidates.json`` (``id``, ``arm``, ``label``, ``object_from_wrist``,
    /// ``feasible``, ``failure``, ``rank``, ``score``, ``mu_l2``, ``mu_linf``, ``m_t``,
    /// ``joint_trajectory``, …; an infinite μ_l∞ is ``None`` with ``mu_linf_infinite``).
    #[getter]
    fn candidates<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &candidates_json(&self.selection))
    }

    /// The best arm pairs (two-arm tasks; empty otherwise), as in ``pairs.json``.
    #[getter]
    fn pairs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &pairs_json(&self.selection))
    }

    /// The task in brief and the selected grasp per arm (and pair), as in ``summary.json``.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &summary_json(&self.task, &self.selection))
    }

    /// The arms, in order.
    #[getter]
    fn arms(&self) -> Vec<String> {
        self.selection.arms.iter().map(|a| a.arm.clone()).collect()
    }

    /// The id of the best-ranked candidate of ``arm`` (``None`` when none is eligible).
    fn best(&self, arm: &str) -> PyResult<Option<usize>> {
        let result = self.arm_result(arm)?;
        Ok(result.best().map(|i| result.scores[i].candidate.id))
    }

    /// One arm's results as numpy arrays over the candidates (in candidate order), for
    /// plotting and analysis: the record columns marked ``arrays`` in
    /// :func:`record_columns` (``docs/candidate-record.md``) — ``id`` (int64), ``label`` (str),
    /// ``feasible`` (bool), ``failure_reason`` (object, ``None`` when feasible),
    /// ``failure_sample`` (float64, NaN when feasible), ``failure_joint`` (object), ``rejected``
    /// (object), ``rank`` (float64, 1 for the best, NaN when not ranked), ``score``,
    /// ``log_likelihood``,
    /// ``mu_l2``, ``mu_linf`` (``inf`` on a singular path), ``mu_l1``, ``mu_rms``, ``yoshikawa_at_grasp``,
    /// ``yoshikawa_penalized_at_grasp`` (with a joint-limit penalty),
    /// ``inverse_condition_at_grasp``, ``inverse_condition_squared_at_grasp``,
    /// ``limit_distance_min`` (rad or m, the path's closest approach to a joint limit),
    /// ``clearance`` (m, the smallest distance to the scene along the motion),
    /// ``torque_margin`` and ``payload_capacity`` (kg; with the object's mass), ``dynamic_manipulability`` ((m/s²)²; with the object's mass or ``measure="dynamic"``) (float64, NaN
    /// where absent), ``hugs_limit`` (bool), ``contact`` ``(k, 3)``, ``m_t`` ``(k, n)`` and
    /// ``ranked_index`` ``(k, n)`` (the ranked per-sample index: ``m_t`` unless the task sets
    /// ``measure`` or ``joint_limit_penalty``) (NaN where absent: infeasible, or the object
    /// still). No value is a sentinel: whatever is absent is NaN (or ``None``).
    fn arrays<'py>(&self, py: Python<'py>, arm: &str) -> PyResult<Bound<'py, PyDict>> {
        let result = self.arm_result(arm)?;
        let samples = self.task.path().samples.len();
        // The values are gathered with the GIL released (a large selection's columns take a
        // while); only the arrays are made with it.
        let columns = py
            .detach(|| {
                let rows: Vec<Row<'_>> = result
                    .scores
                    .iter()
                    .zip(&result.rankings)
                    .map(|(score, ranking)| {
                        Row::new(&result.arm, score, ranking, Trajectories::None)
                    })
                    .collect();
                gather_columns(&rows, outputs::ARRAYS, samples)
            })
            .map_err(error)?;
        let dict = PyDict::new(py);
        set_gathered_columns(py, &dict, columns)?;
        Ok(dict)
    }

    /// One arm's joint path along the task for one candidate (its position in the task's
    /// candidates), shape ``(n, dof)``; ``None`` when the candidate is infeasible.
    fn joint_trajectory<'py>(
        &self,
        py: Python<'py>,
        arm: &str,
        candidate: usize,
    ) -> PyResult<Option<Py<PyAny>>> {
        let result = self.arm_result(arm)?;
        let score = result.scores.get(candidate).ok_or_else(|| {
            error(format!(
                "candidate {candidate} is out of range (the task has {})",
                result.scores.len()
            ))
        })?;
        if score.joint_trajectory.is_empty() {
            return Ok(None);
        }
        let n = score.joint_trajectory.len();
        let dof = score.joint_trajectory[0].len();
        let flat: Vec<f64> = score.joint_trajectory.iter().flatten().copied().collect();
        Ok(Some(array(py, flat, &[n, dof])?.into_any().unbind()))
    }

    /// The selected motions, timed (when the task times motions and something is selected;
    /// otherwise an empty list): the best candidate's with one arm, the best pair's two on one
    /// timeline with two. One dict per arm: ``arm``, ``candidate`` (id), ``label``,
    /// ``duration`` (s), ``joint_names``, ``time`` ``(n,)`` (s), ``positions``,
    /// ``velocities``, ``accelerations`` ``(n, dof)`` (rad, rad/s, rad/s²) and ``efforts``
    /// ``(n, dof)`` (N·m; ``None`` without the arm's dynamics), sampled every ``period``
    /// seconds (``None``: at the timing grid's points, where the motion passes through every
    /// IK sample). ``trajectory.json`` holds the same motions (``graspath select``).
    #[pyo3(signature = (period = Some(0.01)), text_signature = "(self, period=0.01)")]
    fn timed_motions<'py>(
        &self,
        py: Python<'py>,
        period: Option<f64>,
    ) -> PyResult<Vec<Bound<'py, PyDict>>> {
        crate::physics::check_period(period)?;
        let motions = match py.detach(|| selected_motions(&self.task, &self.selection, period)) {
            None => return Ok(Vec::new()),
            Some(motions) => motions.map_err(|f| error(format!("cannot time the motion: {f}")))?,
        };
        motions
            .iter()
            .map(|motion| crate::physics::motion_dict(py, motion))
            .collect()
    }

    /// Writes ``candidates.json``, ``summary.json``, with two arms ``pairs.json`` and, when the
    /// task times motions, ``trajectory.json`` and ``trajectory-<arm>.csv`` (sampled every
    /// ``trajectory_period`` seconds; ``0``: at the timing grid's points) into ``out_dir``
    /// (created if missing; an existing non-empty folder is refused), byte for byte as
    /// ``graspath select --out`` does; the files appear together or not at all. Returns the
    /// paths written.
    #[pyo3(signature = (out_dir, trajectory_period = 0.01))]
    fn write(&self, out_dir: PathBuf, trajectory_period: f64) -> PyResult<Vec<PathBuf>> {
        let mut files = vec![
            (
                "candidates.json".to_string(),
                pretty(&candidates_json(&self.selection))?,
            ),
            (
                "summary.json".to_string(),
                pretty(&summary_json(&self.task, &self.selection))?,
            ),
        ];
        if self.task.arms().len() == 2 {
            files.push((
                "pairs.json".to_string(),
                pretty(&pairs_json(&self.selection))?,
            ));
        }
        if !(trajectory_period == 0.0 || (1e-4..=10.0).contains(&trajectory_period)) {
            return Err(error(format!(
                "trajectory_period: {trajectory_period} is not 0 or a period from 0.0001 to 10 s"
            )));
        }
        let period = (trajectory_period > 0.0).then_some(trajectory_period);
        files.extend(
            trajectory_files(&self.task, &self.selection, period)
                .map_err(|f| error(format!("cannot time the motion: {f}")))?,
        );
        write_files(&out_dir, &files, Existing::Refuse).map_err(lib_error)
    }

    /// The norm used for ranking: ``"rms"``, ``"l2"`` or ``"l1"``.
    #[getter]
    fn norm(&self) -> &'static str {
        self.task.selection().norm.as_str()
    }

    fn __repr__(&self) -> String {
        let arms: Vec<String> = self
            .selection
            .arms
            .iter()
            .map(|a| format!("{}: {} feasible", a.arm, a.feasible_count()))
            .collect();
        format!(
            "Selection('{}', candidates={}, {})",
            self.task.source_name(),
            self.task.candidate_count(),
            arms.join(", ")
        )
    }
}

impl PySelection {
    fn arm_result(&self, arm: &str) -> PyResult<&graspath::select::ArmResult> {
        self.selection
            .arms
            .iter()
            .find(|a| a.arm == arm)
            .ok_or_else(|| {
                let names: Vec<&str> = self.selection.arms.iter().map(|a| a.arm.as_str()).collect();
                error(format!("unknown arm '{arm}' (arms: {})", names.join(", ")))
            })
    }
}
