//! `graspath.select` and `graspath.Selection`: scoring and ranking every candidate of a task,
//! with the same records the CLI writes (`candidates.json`, `pairs.json`, `summary.json`).

use crate::convert::{array, error, json_to_py};
use crate::task::PyTask;
use graspath::fsutil::{write_files, Existing};
use graspath::select::{select as run_selection, Selection};
use graspath::task::{Norm, Task};
use graspath_report::{candidates_json, pairs_json, summary_json};
use numpy::PyArray1;
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
    let mut bytes = serde_json::to_vec_pretty(value).map_err(error)?;
    bytes.push(b'\n');
    Ok(bytes)
}

/// Scores every candidate of ``task`` along its object path for each arm (trajectory IK,
/// ``M_T`` at every sample, the norms μ_l2, μ_l∞, μ_l1 and the indices at the grasp), ranks
/// them per arm and, with two arms, ranks the pairs. Runs in parallel without the GIL;
/// deterministic.
#[pyfunction]
pub fn select(py: Python<'_>, task: &Bound<'_, PyTask>) -> PySelection {
    let task = task.get().task.clone();
    let selection = py.detach(|| run_selection(&task, &|| {}));
    PySelection { task, selection }
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
    /// plotting and analysis: ``id`` (int64), ``feasible`` (bool), ``rank`` (float64, 1 for
    /// the best, NaN when not ranked), ``score``, ``mu_l2``, ``mu_linf`` (``inf`` on a singular path), ``mu_l1``,
    /// ``yoshikawa_at_grasp``, ``inverse_condition_at_grasp``,
    /// ``inverse_condition_squared_at_grasp``, ``clearance`` (m, the smallest distance to the
    /// scene along the motion), ``yoshikawa_penalized_at_grasp`` (with a joint-limit penalty),
    /// ``limit_distance_min`` (rad or m, the path's closest approach to a joint limit) (float64,
    /// NaN where absent), ``hugs_limit`` (bool), ``contact`` ``(k, 3)``, ``m_t`` ``(k, n)`` and
    /// ``ranked_index`` ``(k, n)`` (the ranked per-sample index: ``m_t`` unless the task sets
    /// ``measure`` or ``joint_limit_penalty``) (NaN where absent: infeasible, or the object still),
    /// and ``failure_sample`` (float64, the first failing sample, NaN when feasible). No value
    /// is a sentinel: whatever is absent is NaN.
    fn arrays<'py>(&self, py: Python<'py>, arm: &str) -> PyResult<Bound<'py, PyDict>> {
        let result = self.arm_result(arm)?;
        let samples = self.task.path.samples.len();
        let k = result.scores.len();
        let nan = f64::NAN;
        let dict = PyDict::new(py);
        let ids: Vec<i64> = result
            .scores
            .iter()
            .map(|s| s.candidate.id as i64)
            .collect();
        dict.set_item("id", PyArray1::from_vec(py, ids))?;
        let feasible: Vec<bool> = result
            .scores
            .iter()
            .map(graspath::select::CandidateScore::feasible)
            .collect();
        dict.set_item("feasible", PyArray1::from_vec(py, feasible))?;
        let ranks: Vec<f64> = result
            .rankings
            .iter()
            .map(|r| r.rank.map_or(nan, |v| v as f64))
            .collect();
        dict.set_item("rank", PyArray1::from_vec(py, ranks))?;
        let scores: Vec<f64> = result
            .rankings
            .iter()
            .map(|r| r.score.unwrap_or(nan))
            .collect();
        dict.set_item("score", PyArray1::from_vec(py, scores))?;
        let norm = |f: fn(&graspath::manipulability::PathNorms) -> f64| -> Vec<f64> {
            result
                .scores
                .iter()
                .map(|s| s.norms.as_ref().map_or(nan, f))
                .collect()
        };
        dict.set_item("mu_l2", PyArray1::from_vec(py, norm(|n| n.l2)))?;
        dict.set_item("mu_linf", PyArray1::from_vec(py, norm(|n| n.linf)))?;
        dict.set_item("mu_l1", PyArray1::from_vec(py, norm(|n| n.l1)))?;
        let at_grasp = |f: fn(&graspath::select::CandidateScore) -> Option<f64>| -> Vec<f64> {
            result.scores.iter().map(|s| f(s).unwrap_or(nan)).collect()
        };
        dict.set_item(
            "yoshikawa_at_grasp",
            PyArray1::from_vec(py, at_grasp(|s| s.yoshikawa_at_grasp)),
        )?;
        dict.set_item(
            "inverse_condition_at_grasp",
            PyArray1::from_vec(py, at_grasp(|s| s.inverse_condition_at_grasp)),
        )?;
        dict.set_item(
            "inverse_condition_squared_at_grasp",
            PyArray1::from_vec(py, at_grasp(|s| s.inverse_condition_squared_at_grasp)),
        )?;
        dict.set_item(
            "clearance",
            PyArray1::from_vec(py, at_grasp(|s| s.clearance)),
        )?;
        dict.set_item(
            "yoshikawa_penalized_at_grasp",
            PyArray1::from_vec(py, at_grasp(|s| s.yoshikawa_penalized_at_grasp)),
        )?;
        let limit_distance_min: Vec<f64> = result
            .scores
            .iter()
            .map(|s| {
                let d = s
                    .limit_distance
                    .iter()
                    .copied()
                    .fold(f64::INFINITY, f64::min);
                if d.is_finite() {
                    d
                } else {
                    nan
                }
            })
            .collect();
        dict.set_item(
            "limit_distance_min",
            PyArray1::from_vec(py, limit_distance_min),
        )?;
        let hugs: Vec<bool> = result
            .scores
            .iter()
            .map(graspath::select::CandidateScore::hugs_limit)
            .collect();
        dict.set_item("hugs_limit", PyArray1::from_vec(py, hugs))?;
        let contact: Vec<f64> = result
            .scores
            .iter()
            .flat_map(|s| s.candidate.contact.map_or([nan; 3], |p| [p.x, p.y, p.z]))
            .collect();
        dict.set_item("contact", array(py, contact, &[k, 3])?)?;
        let mut m_t = vec![nan; k * samples];
        for (row, s) in result.scores.iter().enumerate() {
            for (i, v) in s.m_t.iter().enumerate().take(samples) {
                if let Some(v) = v {
                    m_t[row * samples + i] = *v;
                }
            }
        }
        dict.set_item("m_t", array(py, m_t, &[k, samples])?)?;
        let mut ranked = vec![nan; k * samples];
        for (row, s) in result.scores.iter().enumerate() {
            let values = s.ranked_values.as_ref().unwrap_or(&s.m_t);
            for (i, v) in values.iter().enumerate().take(samples) {
                if let Some(v) = v {
                    ranked[row * samples + i] = *v;
                }
            }
        }
        dict.set_item("ranked_index", array(py, ranked, &[k, samples])?)?;
        let failure_sample: Vec<f64> = result
            .scores
            .iter()
            .map(|s| s.failure.as_ref().map_or(nan, |f| f.sample as f64))
            .collect();
        dict.set_item("failure_sample", PyArray1::from_vec(py, failure_sample))?;
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

    /// Writes ``candidates.json``, ``summary.json`` and, with two arms, ``pairs.json`` into
    /// ``out_dir`` (created if missing; an existing non-empty folder is refused), byte for byte as
    /// ``graspath select --out`` does; the files appear together or not at all. Returns the paths written.
    fn write(&self, out_dir: PathBuf) -> PyResult<Vec<PathBuf>> {
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
        if self.task.arms.len() == 2 {
            files.push((
                "pairs.json".to_string(),
                pretty(&pairs_json(&self.selection))?,
            ));
        }
        write_files(&out_dir, &files, Existing::Refuse).map_err(error)
    }

    /// The norm used for ranking: ``"l2"`` or ``"l1"``.
    #[getter]
    fn norm(&self) -> &'static str {
        match self.task.selection.norm {
            Norm::L2 => "l2",
            Norm::L1 => "l1",
        }
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
            self.task.source_name,
            self.task.candidates.len(),
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
