//! Terminal output: progress bars, the one-screen summary table, `--quiet` and `--json`.

/// `println!` that ignores a closed stdout (e.g. `graspath demo | head`) instead of panicking.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

use clap::Args;
use graspath::select::Selection;
use graspath::task::Task;
use graspath_report::{findings_sentences, nothing_selected};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::Duration;

/// Output switches shared by the long-running subcommands.
#[derive(Debug, Clone, Args)]
pub struct OutputArgs {
    /// Print nothing but errors.
    #[arg(long, conflicts_with = "json")]
    pub quiet: bool,
    /// Print the summary as JSON on stdout (for scripts) instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// A progress bar on a terminal (stderr), hidden otherwise or with `--quiet`/`--json`.
pub fn progress_bar(output: &OutputArgs, total: u64, title: &str) -> ProgressBar {
    if output.quiet || output.json || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} candidates ({eta})")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(title.to_string());
    bar
}

fn number(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.4}"),
        Some(_) => "inf".into(),
        None => "-".into(),
    }
}

/// The one-screen summary: per arm the best five candidates and the failures by reason.
pub fn print_summary_table(task: &Task, selection: &Selection, title: &str, elapsed: Duration) {
    say!(
        "{title}: {} candidates x {} arm(s), {} samples, {:.3} s",
        task.candidates.len(),
        task.arms.len(),
        task.path.samples.len(),
        elapsed.as_secs_f64()
    );
    for arm in &selection.arms {
        let mut reasons: std::collections::BTreeMap<&str, usize> = Default::default();
        for s in &arm.scores {
            if let Some(f) = &s.failure {
                *reasons.entry(f.reason.as_str()).or_default() += 1;
            }
        }
        let rejected = arm.rankings.iter().filter(|r| r.rejected.is_some()).count();
        let reasons: Vec<String> = reasons.iter().map(|(r, n)| format!("{n} {r}")).collect();
        say!(
            "  arm {}: {} feasible, {} rejected by the selection rule{}",
            arm.arm,
            arm.feasible_count(),
            rejected,
            if reasons.is_empty() {
                String::new()
            } else {
                format!(", infeasible: {}", reasons.join(", "))
            }
        );
        // In a scene the last column is the clearance from it (m); else Yoshikawa's index.
        let in_scene = task.collisions.is_some();
        say!(
            "    {:>4}  {:>5}  {:<28} {:>10} {:>10} {:>10} {:>10}",
            "rank",
            "id",
            "label",
            "score",
            "mu_l2",
            "mu_linf",
            if in_scene { "clearance" } else { "yoshikawa" }
        );
        let mut ranked: Vec<usize> = (0..arm.rankings.len())
            .filter(|&i| arm.rankings[i].rank.is_some())
            .collect();
        ranked.sort_by_key(|&i| arm.rankings[i].rank);
        // Candidates tied with the best (see `selection.tie_tolerance`) show `=` before their rank.
        let tied_with_best = arm
            .best()
            .map(|b| arm.tied_with(b, &task.selection))
            .unwrap_or_default();
        for &i in ranked.iter().take(5) {
            let s = &arm.scores[i];
            let c = &s.candidate;
            let rank = arm.rankings[i].rank.unwrap_or(0);
            let rank = if tied_with_best.contains(&c.id) {
                format!("={rank}")
            } else {
                rank.to_string()
            };
            say!(
                "    {:>4}  {:>5}  {:<28} {:>10} {:>10} {:>10} {:>10}",
                rank,
                c.id,
                c.label.chars().take(28).collect::<String>(),
                number(arm.rankings[i].score),
                number(s.norms.map(|n| n.l2)),
                number(s.norms.map(|n| n.linf)),
                number(if in_scene {
                    s.clearance
                } else {
                    s.yoshikawa_at_grasp
                }),
            );
        }
    }
    for sentence in findings_sentences(task, selection) {
        say!("  {sentence}");
    }
    if selection.colliding_pairs > 0 {
        say!(
            "  {} better pair(s) refused: the two arms would touch along the motion",
            selection.colliding_pairs
        );
    }
    if nothing_selected(selection) {
        say!("  nothing selected: no feasible candidate (two arms: no valid pair)");
    }
}
