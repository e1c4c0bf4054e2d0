//! The demo's timing finding per experiment: how long each feasible candidate's motion takes
//! (`docs/timing.md`) against its `μ_l2` — the rank correlation (Spearman's ρ, ties sharing
//! their mean rank), the index's best grasp's duration and the fastest grasp.

use graspath::placement::pearson;
use graspath::select::Selection;
use serde_json::{json, Value};

/// Per arm: `timed` (feasible candidates with a duration), `spearman_duration_mu_l2`,
/// `durations_s` `[shortest, longest]`, `best_by_index` `{label, duration_s}`, `fastest`
/// `{label, duration_s}` and `fastest_is_best_by_index`; `null` when the task is not timed.
pub(super) fn timing_finding(selection: &Selection) -> Value {
    let arms: Vec<Value> = selection
        .arms
        .iter()
        .map(|arm| {
            let timed: Vec<(usize, f64, f64)> = arm
                .scores
                .iter()
                .enumerate()
                .filter_map(|(i, s)| Some((i, s.durations?.total(), s.norms?.l2)))
                .collect();
            if timed.is_empty() {
                return Value::Null;
            }
            let durations: Vec<f64> = timed.iter().map(|t| t.1).collect();
            let norms: Vec<f64> = timed.iter().map(|t| t.2).collect();
            let ranked: Vec<(f64, f64)> =
                ranks(&durations).into_iter().zip(ranks(&norms)).collect();
            let (fastest, shortest) =
                timed
                    .iter()
                    .map(|t| (t.0, t.1))
                    .fold(
                        (usize::MAX, f64::INFINITY),
                        |a, b| if b.1 < a.1 { b } else { a },
                    );
            let longest = durations.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let described = |i: usize| {
                json!({
                    "label": arm.scores[i].candidate.label,
                    "duration_s": arm.scores[i].durations.map(|d| d.total()),
                })
            };
            let best = arm.best();
            json!({
                "arm": arm.arm,
                "timed": timed.len(),
                "spearman_duration_mu_l2": pearson(&ranked),
                "durations_s": [shortest, longest],
                "best_by_index": best.map(described),
                "fastest": described(fastest),
                "fastest_is_best_by_index": best == Some(fastest),
            })
        })
        .collect();
    if arms.iter().all(Value::is_null) {
        Value::Null
    } else {
        Value::Array(arms)
    }
}

/// The 1-based ranks of `values`, ties sharing their mean rank.
fn ranks(values: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut ranks = vec![0.0; values.len()];
    let mut start = 0;
    while start < order.len() {
        let mut end = start + 1;
        while end < order.len() && values[order[end]] == values[order[start]] {
            end += 1;
        }
        // Positions start..end (0-based) share the mean of ranks start+1..=end.
        let mean = (start + 1 + end) as f64 / 2.0;
        for &i in &order[start..end] {
            ranks[i] = mean;
        }
        start = end;
    }
    ranks
}

#[cfg(test)]
mod tests {
    use super::ranks;
    use graspath::placement::pearson;

    #[test]
    fn ranks_share_ties_and_spearman_reads_monotone_orders() {
        assert_eq!(ranks(&[3.0, 1.0, 2.0, 1.0]), vec![4.0, 1.5, 3.0, 1.5]);
        let up: Vec<(f64, f64)> = ranks(&[0.1, 0.5, 0.7, 2.0])
            .into_iter()
            .zip(ranks(&[1.0, 8.0, 27.0, 64.0]))
            .collect();
        assert!((pearson(&up).unwrap() - 1.0).abs() < 1e-12);
        let down: Vec<(f64, f64)> = ranks(&[0.1, 0.5, 0.7, 2.0])
            .into_iter()
            .zip(ranks(&[5.0, 4.0, 2.0, -1.0]))
            .collect();
        assert!((pearson(&down).unwrap() + 1.0).abs() < 1e-12);
        // d² = (1, 1, 0, 0): ρ = 1 − 6·2 / (4·15) = 0.8.
        let swapped: Vec<(f64, f64)> = ranks(&[1.0, 2.0, 3.0, 4.0])
            .into_iter()
            .zip(ranks(&[2.0, 1.0, 3.0, 4.0]))
            .collect();
        assert!((pearson(&swapped).unwrap() - 0.8).abs() < 1e-12);
    }
}
