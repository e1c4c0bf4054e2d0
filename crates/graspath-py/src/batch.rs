//! `graspath.select_batch`: many tasks (objects, each with its own pose, path, candidates and
//! scene) scored in one call without the GIL, the results as numpy columns with one row per
//! object, arm and candidate.
//!
//! A task can be cut into candidate slices (`slices`): a slice's scores are those of the whole
//! task, because every candidate is scored on its own and its ranking score takes the likelihood
//! relative to the largest of the *whole* task's candidates. Ranks are then ranks within the
//! slice; sorting the union of the slices' rows by score (best first, ties by candidate
//! position) gives the whole task's ranking, which is how `graspath.ray` merges its shards.

use crate::convert::{error, lib_error};
use crate::record::{gather_columns, set_gathered_columns, ColumnValues};
use crate::task::PyTask;
use graspath::select::record::{self, outputs, Trajectories};
use graspath::select::{select as run_selection, CandidateScore, Ranking};
use graspath::task::Task;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

/// One output row: a candidate of one object scored for one arm.
struct Row {
    object: usize,
    arm: String,
    arm_index: usize,
    candidate: usize,
    score: CandidateScore,
    ranking: Ranking,
}

/// One unit of work: one arm of one task over one candidate slice.
struct Unit<'a> {
    object: usize,
    task: &'a Task,
    arm_index: usize,
    start: usize,
    stop: usize,
}

/// Scores one unit and ranks its candidates (rank within the slice, score relative to the whole
/// task's largest likelihood: [`Task::slice`]), rows in candidate order.
fn run_unit(unit: &Unit<'_>) -> Result<Vec<Row>, graspath::Error> {
    let arm = &unit.task.arms()[unit.arm_index];
    // The task narrowed to this arm and slice: one arm, so no pairs are formed, and the arm's
    // scoring (its path, IK, scene) is exactly that of the whole task.
    let narrowed = unit
        .task
        .with_arms(&[&arm.name])
        .and_then(|t| t.slice(unit.start..unit.stop))?;
    let selection = run_selection(&narrowed, &|| {})?;
    let Some(result) = selection.arms.into_iter().next() else {
        return Ok(Vec::new());
    };
    Ok(result
        .scores
        .into_iter()
        .zip(result.rankings)
        .enumerate()
        .map(|(i, (score, ranking))| Row {
            object: unit.object,
            arm: arm.name.clone(),
            arm_index: unit.arm_index,
            candidate: unit.start + i,
            score,
            ranking,
        })
        .collect())
}

/// `(start, stop)` of every task: the whole task, or the slice given (checked).
fn task_slices(
    tasks: &[Task],
    slices: Option<Vec<(usize, usize)>>,
) -> PyResult<Vec<(usize, usize)>> {
    let Some(slices) = slices else {
        return Ok(tasks.iter().map(|t| (0, t.candidate_count())).collect());
    };
    if slices.len() != tasks.len() {
        return Err(error(format!(
            "slices: {} given for {} tasks (give one (start, stop) per task)",
            slices.len(),
            tasks.len()
        )));
    }
    for (i, (&(start, stop), task)) in slices.iter().zip(tasks).enumerate() {
        let n = task.candidate_count();
        if start > stop || stop > n {
            return Err(error(format!(
                "slices[{i}] = ({start}, {stop}) is not a candidate range of task {i} ('{}', \
                 {n} candidates): give 0 <= start <= stop <= {n}",
                task.source_name()
            )));
        }
    }
    Ok(slices)
}

/// Scores the candidates of many tasks — each an object with its own pose, path, candidates and
/// scene — for each of their arms, in one call: in parallel (rayon) without the GIL, and with
/// the same values at any thread count.
///
/// Returns numpy columns with one row per object, arm and candidate, in the order (object, arm
/// in the task's order, candidate), or with ``top_k`` only the ``top_k`` best-ranked rows of
/// each object and arm in the order (object, arm, rank):
///
/// * ``object`` (int64): the position of the task in ``tasks``; ``arm`` (str), ``arm_index``
///   (int64, its position in the task's arms); ``candidate`` (int64, the position in the task's
///   candidates), ``id`` (int64, the candidate's id), ``label`` (str);
/// * ``feasible`` (bool); ``failure_reason`` (object: the reason, ``unreachable``, ``joint_limit``,
///   ``discontinuity``, ``collision``, …, or ``None``); ``failure_sample`` (float64, NaN when
///   feasible); ``failure_joint`` (object: the joint at fault, or ``None``); ``rejected``
///   (object: why a feasible candidate is not ranked, or ``None``);
/// * ``log_likelihood`` (float64, the candidate's); ``mu_l2``, ``mu_linf`` (``inf`` on a
///   singular path), ``mu_l1``, ``mu_rms`` (float64, the norms of the ranked per-sample index — ``M_T`` in
///   the units of the task's index mode — NaN when infeasible); ``yoshikawa_at_grasp``,
///   ``clearance`` (m, the smallest distance to the scene), ``torque_margin`` and
///   ``payload_capacity`` (kg; with the object's mass), ``dynamic_manipulability`` ((m/s²)²; with the object's mass or ``measure="dynamic"``), ``duration`` (s; when motions are
///   timed) (float64, NaN where absent);
/// * ``score`` (float64, the ranking score: the norm combined with the likelihood relative to
///   the task's most likely candidate; NaN when not ranked) and ``rank`` (float64, 1 for the
///   best, NaN when not ranked).
///
/// Besides ``object``, ``arm_index`` and ``candidate``, the columns are the record columns
/// marked ``select_batch`` in :func:`record_columns` (``docs/candidate-record.md``).
///
/// ``slices`` (one ``(start, stop)`` per task) scores only those candidate positions; scores
/// are the whole task's and ranks are within the slice. ``threads`` runs the work on its own
/// pool of that many threads (default: rayon's global pool, all cores).
#[pyfunction]
#[pyo3(signature = (tasks, *, slices = None, top_k = None, threads = None))]
pub fn select_batch<'py>(
    py: Python<'py>,
    tasks: Vec<Bound<'py, PyTask>>,
    slices: Option<Vec<(usize, usize)>>,
    top_k: Option<usize>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    if top_k == Some(0) {
        return Err(error(
            "top_k must be at least 1 (or None for every candidate)",
        ));
    }
    if threads == Some(0) {
        return Err(error("threads must be at least 1 (or None for every core)"));
    }
    let tasks: Vec<Task> = tasks.iter().map(|t| t.get().task.clone()).collect();
    let slices = task_slices(&tasks, slices)?;
    let pool = threads
        .map(|n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| error(format!("threads: cannot start {n} threads: {e}")))
        })
        .transpose()?;
    let rows: Result<Vec<Row>, graspath::Error> = py.detach(|| {
        let units: Vec<Unit<'_>> = tasks
            .iter()
            .zip(&slices)
            .enumerate()
            .flat_map(|(object, (task, &(start, stop)))| {
                (0..task.arms().len()).map(move |arm_index| Unit {
                    object,
                    task,
                    arm_index,
                    start,
                    stop,
                })
            })
            .collect();
        let run = || -> Result<Vec<Row>, graspath::Error> {
            // Each unit keeps only its top k as soon as it is done, so memory holds the scores
            // of the units in flight, not of every candidate.
            let per_unit: Vec<Vec<Row>> = units
                .par_iter()
                .map(|unit| {
                    let mut rows = run_unit(unit)?;
                    if let Some(k) = top_k {
                        rows.retain(|r| r.ranking.rank.is_some_and(|rank| rank <= k));
                        rows.sort_by_key(|r| r.ranking.rank);
                    }
                    Ok(rows)
                })
                .collect::<Result<_, graspath::Error>>()?;
            Ok(per_unit.into_iter().flatten().collect())
        };
        match &pool {
            Some(pool) => pool.install(run),
            None => run(),
        }
    });
    let rows = rows.map_err(lib_error)?;
    let columns = py.detach(|| columns(&rows)).map_err(error)?;
    let dict = PyDict::new(py);
    set_gathered_columns(py, &dict, columns)?;
    Ok(dict)
}

/// The rows' columns, gathered without Python: the batch's own (`object`, `arm_index`,
/// `candidate`), then the record columns marked `select_batch` (see [`gather_columns`]).
fn columns(rows: &[Row]) -> Result<Vec<(&'static str, ColumnValues<'_>)>, String> {
    let int =
        |f: fn(&Row) -> usize| ColumnValues::Integers(rows.iter().map(|r| f(r) as i64).collect());
    let mut columns = vec![
        ("object", int(|r| r.object)),
        ("arm_index", int(|r| r.arm_index)),
        ("candidate", int(|r| r.candidate)),
    ];
    let records: Vec<record::Row<'_>> = rows
        .iter()
        .map(|r| record::Row::new(&r.arm, &r.score, &r.ranking, Trajectories::None))
        .collect();
    // No batch column is a per-sample series (the tasks' paths differ in length).
    columns.extend(gather_columns(&records, outputs::BATCH, 0)?);
    Ok(columns)
}
