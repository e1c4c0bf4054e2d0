//! The findings of a selection in plain sentences, shared by the CLI's table and the HTML
//! report, so both say the same thing in the same words.

use crate::json::tied_pairs;
use graspath::select::{ArmResult, Scored, Selection};
use graspath::task::Task;

/// A relative tolerance as a percentage without trailing noise (`1e-4` → `0.01 %`).
pub fn percent(tolerance: f64) -> String {
    let fixed = format!("{:.10}", tolerance * 100.0);
    let trimmed = fixed.trim_end_matches('0').trim_end_matches('.');
    format!("{trimmed} %")
}

fn others(n: usize) -> String {
    match n {
        1 => "1 other".to_string(),
        n => format!("{n} others"),
    }
}

/// One arm's best candidate and its ties: `left arm best: edge y=+0.180 (id 0), tied with 2
/// others within 0.01 % (ids 1, 2)`, or `… no other within 0.01 %`; `None` when the arm has
/// no eligible candidate.
pub fn best_sentence<S: Scored>(task: &Task, arm: &ArmResult<S>) -> Option<String> {
    let best = arm.best()?;
    let s = &arm.scores[best];
    let label = s.candidate().map_or("", |c| c.label.as_str());
    let tied = arm.tied_with(best, task.selection());
    let within = percent(task.selection().tie_tolerance);
    let ties = if tied.is_empty() {
        format!("no other within {within}")
    } else {
        let ids: Vec<String> = tied.iter().map(usize::to_string).collect();
        format!(
            "tied with {} within {within} (ids {})",
            others(tied.len()),
            ids.join(", ")
        )
    };
    Some(format!(
        "{} arm best: {} (id {}), {ties}",
        arm.arm,
        label,
        s.id()
    ))
}

/// The best pair and its ties among the kept pairs; `None` without a pair.
pub fn best_pair_sentence<S>(task: &Task, selection: &Selection<S>) -> Option<String> {
    let best = selection.pairs.first()?;
    let (a, b) = (&selection.arms[0].arm, &selection.arms[1].arm);
    let tied = tied_pairs(selection, task.selection().tie_tolerance);
    let within = percent(task.selection().tie_tolerance);
    let ties = if tied.is_empty() {
        format!("no other kept pair within {within}")
    } else {
        let list: Vec<String> = tied
            .iter()
            .map(|p| format!("{} + {}", p.first.id, p.second.id))
            .collect();
        format!(
            "tied with {} within {within} ({})",
            others(tied.len()),
            list.join(", ")
        )
    };
    Some(format!(
        "best pair: {a} {} + {b} {} (ids {} + {}, sum {:.4}), {ties}",
        best.first.label, best.second.label, best.first.id, best.second.id, best.score
    ))
}

/// Every sentence of the selection: each arm's best with its ties, then the best pair's.
pub fn findings_sentences<S: Scored>(task: &Task, selection: &Selection<S>) -> Vec<String> {
    selection
        .arms
        .iter()
        .filter_map(|arm| best_sentence(task, arm))
        .chain(best_pair_sentence(task, selection))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentages_print_without_float_noise() {
        assert_eq!(percent(1e-4), "0.01 %");
        assert_eq!(percent(0.0), "0 %");
        assert_eq!(percent(0.05), "5 %");
        assert_eq!(percent(0.07), "7 %"); // 0.07 × 100 = 7.000000000000001 in binary
        assert_eq!(percent(2.5e-6), "0.00025 %");
    }
}
