//! The JSON documents of a selection (`candidates.json`, `pairs.json`, `summary.json`).
//!
//! Numbers that are infinite (a `μ_l∞` on a singular path) are written as `null` with a flag
//! beside them, since JSON has no infinity. Output is byte-identical for the same input.

use crate::pretty::write_pretty_at;
use crate::world::has_world;
use graspath::manipulability::JacobianRows;
use graspath::manipulability::NormSamples;
use graspath::select::record::{outputs, JsonRecord, Row, Trajectories};
use graspath::select::{
    values_tied, ArmPair, ArmResult, CandidateScore, Ranking, Scored, Selection, Streamed,
};
use graspath::spelling::Spelled;
use graspath::task::Task;
use serde::Serialize;
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::io::Write;

fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

/// One candidate's record (the columns of [`graspath::select::record`]): `ranking` complete
/// (`candidates.json`) or, when `streamed`, without `rank` and `pareto`, which need every
/// candidate.
fn candidate_record<'a>(
    arm: &'a str,
    score: &'a CandidateScore,
    ranking: &'a Ranking,
    trajectories: Trajectories,
    streamed: bool,
) -> JsonRecord<'a> {
    JsonRecord {
        row: Row::new(arm, score, ranking, trajectories),
        output: if streamed {
            outputs::JSON_LINES
        } else {
            outputs::JSON
        },
    }
}

/// `candidates.json`: one record per candidate and arm, in candidate order, arm by arm.
pub fn candidates_json(selection: &Selection) -> Value {
    candidates_json_with(selection, Trajectories::All)
}

/// `candidates.json` with the joint trajectories of `trajectories` only.
pub fn candidates_json_with(selection: &Selection, trajectories: Trajectories) -> Value {
    let mut records = Vec::new();
    for arm in &selection.arms {
        for (score, ranking) in arm.scores.iter().zip(&arm.rankings) {
            let record = candidate_record(&arm.arm, score, ranking, trajectories, false);
            records.push(serde_json::to_value(record).expect("records serialise"));
        }
    }
    Value::Array(records)
}

/// The bytes of `candidates.json` as the CLI writes it (see [`write_candidates_json`]).
pub fn candidates_json_bytes(selection: &Selection, trajectories: Trajectories) -> Vec<u8> {
    let mut bytes = Vec::new();
    write_candidates_json(&mut bytes, selection, trajectories).expect("writing to memory");
    bytes
}

/// Writes `candidates.json` as the CLI does: `candidates_json_with(selection, trajectories)` in
/// serde_json's pretty form, then a newline. The records are rendered straight from their
/// fields (no `Value` in between), indented as elements of the top-level array, in chunks on
/// all cores; each wave of chunks is written while the next one renders, so neither the
/// document nor a copy of it is held whole. The bytes are serde_json's.
pub fn write_candidates_json<W: Write + Send>(
    out: &mut W,
    selection: &Selection,
    trajectories: Trajectories,
) -> std::io::Result<()> {
    use rayon::prelude::*;
    /// Records a chunk, rendered by one task.
    const CHUNK: usize = 16;
    /// Chunks a wave, rendered together while the wave before is written.
    const WAVE: usize = 8;
    let pairs: Vec<(&str, &CandidateScore, &Ranking)> = selection
        .arms
        .iter()
        .flat_map(|arm| {
            arm.scores
                .iter()
                .zip(&arm.rankings)
                .map(move |(score, ranking)| (arm.arm.as_str(), score, ranking))
        })
        .collect();
    if pairs.is_empty() {
        return out.write_all(b"[]\n");
    }
    // Each record after its separator, one level in.
    let render = |c: usize, chunk: &[(&str, &CandidateScore, &Ranking)]| {
        let mut bytes = Vec::new();
        for (i, &(arm, score, ranking)) in chunk.iter().enumerate() {
            let first = c == 0 && i == 0;
            bytes.extend_from_slice(if first { b"\n  " } else { b",\n  " });
            let record = candidate_record(arm, score, ranking, trajectories, false);
            write_pretty_at(&mut bytes, &record, 1).expect("records serialise");
        }
        bytes
    };
    let chunks: Vec<&[(&str, &CandidateScore, &Ranking)]> = pairs.chunks(CHUNK).collect();
    out.write_all(b"[")?;
    let mut rendered: Vec<Vec<u8>> = Vec::new();
    for (w, wave) in chunks.chunks(WAVE).enumerate() {
        let write = |out: &mut W| rendered.iter().try_for_each(|chunk| out.write_all(chunk));
        let (written, next) = rayon::join(
            || write(out),
            || {
                wave.par_iter()
                    .enumerate()
                    .map(|(i, chunk)| render(w * WAVE + i, chunk))
                    .collect()
            },
        );
        written?;
        rendered = next;
    }
    rendered.iter().try_for_each(|chunk| out.write_all(chunk))?;
    out.write_all(b"\n]\n")
}

/// Writes one streamed candidate as a line of `candidates.jsonl`: the fields of its
/// `candidates.json` record except `rank` and `pareto` (they need every candidate; see
/// [`write_ranking_jsonl`]), compact, then a newline.
pub fn write_candidate_line(
    out: &mut impl Write,
    streamed: &Streamed<'_>,
    trajectories: Trajectories,
) -> std::io::Result<()> {
    let record = candidate_record(
        streamed.arm,
        streamed.score,
        streamed.ranking,
        trajectories,
        true,
    );
    serde_json::to_writer(&mut *out, &record)?;
    out.write_all(b"\n")
}

#[derive(Serialize)]
struct RankingRecord<'a> {
    arm: &'a str,
    id: usize,
    rank: usize,
    score: Option<f64>,
    pareto: bool,
}

/// Writes `ranking.jsonl`: one line per eligible candidate and arm, `{"arm", "id", "rank",
/// "score", "pareto"}`, best first, arm by arm (the `rank`, `score` and `pareto` of its
/// `candidates.json` record). Candidates that are not eligible (infeasible or rejected) have no
/// line: their `rank` is `null` and `pareto` false.
pub fn write_ranking_jsonl<S: Scored>(
    out: &mut impl Write,
    selection: &Selection<S>,
) -> std::io::Result<()> {
    for arm in &selection.arms {
        for (rank, i) in ranked_order(arm) {
            let record = RankingRecord {
                arm: &arm.arm,
                id: arm.scores[i].id(),
                rank,
                score: arm.rankings[i].score.and_then(finite),
                pareto: arm.rankings[i].pareto,
            };
            serde_json::to_writer(&mut *out, &record)?;
            out.write_all(b"\n")?;
        }
    }
    Ok(())
}

/// The eligible candidates of `arm` as (rank, index into its scores), best first: the rows of
/// `ranking.jsonl` and `ranking.parquet`.
pub(crate) fn ranked_order<S>(arm: &ArmResult<S>) -> Vec<(usize, usize)> {
    let mut ranked: Vec<(usize, usize)> = arm
        .rankings
        .iter()
        .enumerate()
        .filter_map(|(i, r)| r.rank.map(|rank| (rank, i)))
        .collect();
    ranked.sort_unstable();
    ranked
}

/// `pairs.json`: the best pairs, keyed by the two arms' names (`left`, `right` on Baxter).
pub fn pairs_json<S>(selection: &Selection<S>) -> Value {
    if selection.arms.len() != 2 {
        return Value::Array(Vec::new());
    }
    let (a, b) = (&selection.arms[0], &selection.arms[1]);
    Value::Array(
        selection
            .pairs
            .iter()
            .map(|p| {
                let ca = &p.first;
                let cb = &p.second;
                let mut m = Map::new();
                m.insert(a.arm.clone(), json!(ca.id));
                m.insert(b.arm.clone(), json!(cb.id));
                m.insert(format!("{}_label", a.arm), json!(ca.label));
                m.insert(format!("{}_label", b.arm), json!(cb.label));
                m.insert("score".into(), json!(p.score));
                m.insert("rank".into(), json!(p.rank));
                Value::Object(m)
            })
            .collect(),
    )
}

/// The task's `index` section as run: the rows, and the measure and penalty when the ranked
/// index is not the paper's `M_T`.
fn index_json(task: &Task) -> Value {
    let mut index = match task.rows() {
        JacobianRows::Twist { length_scale } => {
            json!({"mode": "twist", "length_scale": length_scale})
        }
        JacobianRows::Translation => json!({"mode": "translation"}),
        JacobianRows::Rotation => json!({"mode": "rotation"}),
    };
    if !task.ranked().is_task_relevant() {
        index["measure"] = json!(task.ranked().measure.as_str());
        index["joint_limit_penalty"] = json!(task.ranked().joint_limit_penalty);
    }
    if task.ranked().over != NormSamples::All {
        index["over"] = json!(task.ranked().over.as_str());
    }
    index
}

/// True when the task selected nothing: with one arm, no candidate is ranked (none is feasible,
/// or every feasible one is rejected by `mu0`); with two arms, no valid pair exists. The CLI's
/// `select` then exits with code 3 (unless `--allow-empty`), and `summary.json` says so in
/// `nothing_selected`.
pub fn nothing_selected<S: Scored>(selection: &Selection<S>) -> bool {
    if selection.arms.len() == 2 {
        selection.pairs.is_empty()
    } else {
        selection.arms.iter().all(|arm| arm.best().is_none())
    }
}

/// The kept pairs after the best whose summed norm is tied with the best pair's (relative
/// difference at most `tolerance`, see [`graspath::select::values_tied`]), best first. Only the
/// kept pairs (`selection.pairs`, task setting `pairs`) are looked at.
pub fn tied_pairs<S>(selection: &Selection<S>, tolerance: f64) -> Vec<&ArmPair> {
    let Some(best) = selection.pairs.first() else {
        return Vec::new();
    };
    selection.pairs[1..]
        .iter()
        .filter(|p| values_tied(best.score, p.score, tolerance))
        .collect()
}

/// `summary.json`: the task in brief and the selected grasp per arm (and pair). The selected
/// grasp lists in `tied_with` the ids of the other eligible candidates whose score is within
/// `tie_tolerance` of its own (see [`graspath::select::scores_tied`]); the best pair lists the
/// kept pairs tied with it. A task that
/// describes its world (a scene, an approach or retreat, or a gripper) also gets, per arm,
/// `failures`: how many candidates failed for each reason (`collision`, `gripper_width`, ...;
/// reasons that did not occur are left out), `colliding_bodies` when some collide: each pair
/// of bodies the collisions name with how many candidates failed on it, the most frequent
/// first (see [`ArmResult::colliding_body_pairs`](graspath::select::ArmResult::colliding_body_pairs)),
/// and, with two arms, `colliding_pairs`: how many
/// pairs better than the last kept were refused because the arms collide. A task that says
/// nothing about its world gets the summary it had before scenes existed.
pub fn summary_json<S: Scored>(task: &Task, selection: &Selection<S>) -> Value {
    let world = has_world(task);
    let arms: Vec<Value> = selection
        .arms
        .iter()
        .map(|arm| {
            let selected = arm.best().map(|i| {
                let s = &arm.scores[i];
                let norms = s.norms();
                json!({
                    "id": s.id(),
                    "label": s.candidate().map(|c| c.label.as_str()),
                    "score": arm.rankings[i].score,
                    "mu_l2": norms.map(|n| n.l2),
                    "mu_linf": norms.and_then(|n| finite(n.linf)),
                    "mu_l1": norms.map(|n| n.l1),
                    "mu_rms": norms.map(|n| n.rms),
                    "yoshikawa_at_grasp": s.yoshikawa_at_grasp(),
                    "tied_with": arm.tied_with(i, task.selection()),
                })
            });
            let by_yoshikawa = arm
                .best_by(Scored::yoshikawa_at_grasp)
                .map(|i| arm.scores[i].id());
            let mut summary = json!({
                "arm": arm.arm,
                "candidates": arm.scores.len(),
                "feasible": arm.feasible_count(),
                "eligible": arm.rankings.iter().filter(|r| r.rank.is_some()).count(),
                "selected": selected,
                "best_by_yoshikawa_at_grasp": by_yoshikawa,
            });
            if world {
                let mut failures: BTreeMap<&str, usize> = BTreeMap::new();
                for reason in arm.scores.iter().filter_map(Scored::failure_reason) {
                    *failures.entry(reason.as_str()).or_default() += 1;
                }
                summary["failures"] = json!(failures);
                let colliding = arm.colliding_body_pairs();
                if !colliding.is_empty() {
                    summary["colliding_bodies"] = colliding
                        .iter()
                        .map(|(bodies, n)| json!({ "bodies": bodies, "candidates": n }))
                        .collect();
                }
            }
            summary
        })
        .collect();
    let pairs = pairs_json(selection);
    let best_pair = pairs
        .as_array()
        .and_then(|p| p.first().cloned())
        .map(|mut best| {
            best["tied_with"] = Value::Array(
                tied_pairs(selection, task.selection().tie_tolerance)
                    .iter()
                    .map(|p| {
                        let mut m = Map::new();
                        m.insert(selection.arms[0].arm.clone(), json!(p.first.id));
                        m.insert(selection.arms[1].arm.clone(), json!(p.second.id));
                        Value::Object(m)
                    })
                    .collect(),
            );
            best
        });
    let mut summary = json!({
        "task": task.source_name(),
        "robot": task.robot_name(),
        "samples": task.path().samples.len(),
        "steps": task.path().step_labels,
        "duration_s": task.path().samples.last().map(|s| s.time),
        "index": index_json(task),
        "norm": task.selection().norm.as_str(),
        "mu0": task.selection().mu0,
        "arms": arms,
        "best_pair": best_pair,
        "tie_tolerance": task.selection().tie_tolerance,
        "nothing_selected": nothing_selected(selection),
    });
    if world && selection.arms.len() == 2 {
        summary["colliding_pairs"] = json!(selection.colliding_pairs);
    }
    // Values that are probably mistakes (only when there are some: files of tasks without
    // any keep their bytes).
    if !task.warnings().is_empty() {
        summary["warnings"] = json!(task
            .warnings()
            .iter()
            .map(|w| json!({"field": w.field, "message": w.message}))
            .collect::<Vec<_>>());
    }
    summary
}
