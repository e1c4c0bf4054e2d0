//! `graspath select --task FILE [--out DIR] [--report]`: score every candidate along the task,
//! rank them, and write `candidates.json`, `pairs.json` (two arms) and `summary.json`; with
//! `--report` also the figures (SVG and PNG) and `report.html`. The folder is written as a
//! whole (see `graspath::fsutil`).

use crate::output::{print_summary_table, progress_bar, OutputArgs};
use crate::Finished;
use anyhow::{Context, Result};
use clap::Args;
use graspath::fsutil::{check_folder_target, write_files, Existing};
use graspath::placement::FamilyParameter;
use graspath::select::{select, Selection};
use graspath::task::{Task, TaskFile};
use graspath_report::{candidates_json, nothing_selected, pairs_json, render_report, summary_json};
use std::path::PathBuf;
use std::time::Duration;

/// Options of `graspath select`.
#[derive(Debug, Args)]
#[command(after_help = crate::exit::TABLE)]
pub struct SelectArgs {
    /// The task file (YAML or JSON; see docs/task-file.md).
    #[arg(long, value_name = "FILE")]
    task: PathBuf,
    /// Where to write the results: a new or empty folder (or, with --force, a folder whose
    /// contents are replaced as a whole).
    #[arg(long, value_name = "DIR", default_value = "graspath-out")]
    out: PathBuf,
    /// Replace an existing non-empty --out folder (its old contents are deleted once the new
    /// results are in place). Symbolic links and devices are refused even so.
    #[arg(long)]
    force: bool,
    /// Exit with 0 instead of 3 when nothing is selected (no feasible candidate, or no valid
    /// pair with two arms).
    #[arg(long)]
    allow_empty: bool,
    /// Also write the figures (SVG, PNG) and a self-contained `report.html` with a 3D view.
    #[arg(long)]
    report: bool,
    #[command(flatten)]
    output: OutputArgs,
}

/// A task's selection and the files that report it (relative names, rendered in memory).
pub struct TaskRun {
    /// The scores, rankings and pairs.
    pub selection: Selection,
    /// `(name, bytes)`: `candidates.json`, `summary.json`, `pairs.json` with two arms, and with
    /// `report` the figures and `report.html`.
    pub files: Vec<(String, Vec<u8>)>,
    /// Time spent selecting.
    pub elapsed: Duration,
}

/// Runs a loaded task and renders its files (with the figures and `report.html` when `report`
/// is set; `parameter`, the candidate family's parameter, is their x axis); nothing is written
/// yet.
pub fn run_task(
    task: &Task,
    parameter: Option<&FamilyParameter>,
    output: &OutputArgs,
    title: &str,
    report: bool,
) -> Result<TaskRun> {
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
        files.extend(render_report(task, &selection, parameter)?);
    }
    Ok(TaskRun {
        selection,
        files,
        elapsed,
    })
}

/// Runs the subcommand: [`Finished::NothingSelected`] (exit code 3) when nothing is selected
/// and `--allow-empty` is not given; the results are written in either case.
pub fn run(args: &SelectArgs) -> Result<Finished> {
    let existing = Existing::replace_if(args.force);
    // Refuse a bad --out before the work, not after it.
    check_folder_target(&args.out, existing)?;
    let file = TaskFile::load(&args.task).context("cannot use the task file")?;
    let title = args.task.display().to_string();
    let base_dir = args.task.parent().map(PathBuf::from).unwrap_or_default();
    let task = Task::from_file(&file, &title, &base_dir).context("cannot use the task file")?;
    let parameter = FamilyParameter::from_task_file(&file, &task.candidates);
    let run = run_task(&task, parameter.as_ref(), &args.output, &title, args.report)?;
    write_files(&args.out, &run.files, existing)?;
    let empty = nothing_selected(&run.selection);
    if args.output.json {
        crate::say!(
            "{}",
            serde_json::to_string_pretty(&summary_json(&task, &run.selection))?
        );
    } else if !args.output.quiet {
        print_summary_table(&task, &run.selection, &title, run.elapsed);
        crate::say!("  wrote {}", args.out.display());
    }
    if empty && !args.allow_empty {
        let what = if task.arms.len() == 2 {
            "no valid pair of grasps"
        } else {
            "no feasible candidate"
        };
        eprintln!(
            "graspath: nothing selected ({what}); the results are in {}; exit code 3 (--allow-empty exits 0)",
            args.out.display()
        );
        return Ok(Finished::NothingSelected);
    }
    Ok(Finished::Done)
}
