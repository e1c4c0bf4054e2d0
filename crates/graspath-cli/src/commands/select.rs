//! `graspath select --task FILE [--out DIR] [--report]`: score every candidate along the task,
//! rank them, and write `candidates.json`, `pairs.json` (two arms) and `summary.json`; with
//! `--report` also the figures (SVG and PNG) and `report.html`.

use crate::output::{print_summary_table, progress_bar, OutputArgs};
use anyhow::{Context, Result};
use clap::Args;
use graspath::select::{select, Selection};
use graspath::task::Task;
use graspath_report::{
    candidates_json, pairs_json, render_report, summary_json, write_files_atomically,
};
use std::path::{Path, PathBuf};

/// Options of `graspath select`.
#[derive(Debug, Args)]
pub struct SelectArgs {
    /// The task file (YAML or JSON; see docs/task-file.md).
    #[arg(long, value_name = "FILE")]
    task: PathBuf,
    /// Where to write the results.
    #[arg(long, value_name = "DIR", default_value = "graspath-out")]
    out: PathBuf,
    /// Also write the figures (SVG, PNG) and a self-contained `report.html` with a 3D view.
    #[arg(long)]
    report: bool,
    #[command(flatten)]
    output: OutputArgs,
}

/// Runs a loaded task and writes its files into `out` (with the figures and `report.html` when
/// `report` is set); returns the selection.
pub fn run_task(
    task: &Task,
    out: &Path,
    output: &OutputArgs,
    title: &str,
    report: bool,
) -> Result<Selection> {
    let total = task.candidates.len() * task.arms.len();
    let bar = progress_bar(output, total as u64, title);
    let started = std::time::Instant::now();
    let selection = select(task, &|| bar.inc(1));
    bar.finish_and_clear();
    let elapsed = started.elapsed();
    let pretty = |v: serde_json::Value| -> Result<Vec<u8>> {
        let mut bytes = serde_json::to_vec_pretty(&v)?;
        bytes.push(b'\n');
        Ok(bytes)
    };
    let mut files = vec![
        (
            "candidates.json".to_string(),
            pretty(candidates_json(&selection))?,
        ),
        (
            "summary.json".to_string(),
            pretty(summary_json(task, &selection))?,
        ),
    ];
    if task.arms.len() == 2 {
        files.push(("pairs.json".to_string(), pretty(pairs_json(&selection))?));
    }
    if report {
        files.extend(render_report(task, &selection)?);
    }
    write_files_atomically(out, &files)?;
    if output.json {
        crate::say!(
            "{}",
            serde_json::to_string_pretty(&summary_json(task, &selection))?
        );
    } else if !output.quiet {
        print_summary_table(task, &selection, title, elapsed, out);
    }
    Ok(selection)
}

/// Runs the subcommand.
pub fn run(args: &SelectArgs) -> Result<()> {
    let task = Task::load(&args.task).context("cannot use the task file")?;
    run_task(
        &task,
        &args.out,
        &args.output,
        &args.task.display().to_string(),
        args.report,
    )?;
    Ok(())
}
