//! `graspath select --task FILE [--out DIR] [--report] [--format json|jsonl|parquet]`: score every
//! candidate along the task, rank them, and write `candidates.json`, `pairs.json` (two arms) and
//! `summary.json`; with `--report` also the figures (SVG and PNG) and `report.html`. With
//! `--format jsonl` the candidates are streamed to `candidates.jsonl` as they are scored and the
//! ranks written to `ranking.jsonl` at the end (docs/streaming.md); `--format parquet` streams
//! the same way to `candidates.parquet` and `ranking.parquet`. The folder is written as a
//! whole (see `graspath::output_files`).

use crate::output::{print_summary_table, OutputArgs, Progress};
use crate::writeback::Writeback;
use crate::Finished;
use anyhow::{Context, Result};
use clap::Args;
use graspath::output_files::{check_folder_target, Existing, FolderWriter};
use graspath::placement::FamilyParameter;
use graspath::select::record::Trajectories;
use graspath::select::{
    select, select_streaming_prepared, CandidateScalars, Scored, Selection, Streamed,
};
use graspath::task::{Task, TaskFile};
use graspath_report::{
    candidates_json_bytes, nothing_selected, pairs_json, render_report, summary_json,
    write_candidate_line, write_candidates_json, write_ranking_jsonl, write_ranking_parquet,
    CandidatesParquet,
};
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Duration;

/// Options of `graspath select`.
#[derive(Debug, Args)]
#[command(after_help = crate::exit::TABLE)]
pub(crate) struct SelectArgs {
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
    /// `json`: `candidates.json`, every candidate held in memory (small runs). `jsonl`:
    /// `candidates.jsonl`, one record per line written as the candidates are scored, and
    /// `ranking.jsonl` at the end; memory does not grow with the trajectories (large runs; see
    /// docs/streaming.md). `parquet`: the same, streamed to `candidates.parquet` and
    /// `ranking.parquet` (columnar, for pandas, polars, DuckDB, Arrow).
    #[arg(long, value_enum, default_value_t = Format::Json)]
    format: Format,
    /// Whose joint trajectories the records carry: `none`, `feasible` or `all` (default:
    /// `all` with `--format json`, `feasible` with `jsonl` and `parquet`).
    #[arg(long, value_enum, value_name = "WHICH")]
    trajectories: Option<TrajectoriesArg>,
    /// When the task times motions: the sampling period of the selected motions written to
    /// `trajectory.json` and `trajectory-<arm>.csv` (seconds, default 0.01; `0`: at the
    /// timing grid's points).
    #[arg(long, value_name = "SECONDS", default_value_t = 0.01, value_parser = sampling_period)]
    trajectory_period: f64,
    #[command(flatten)]
    pub(crate) output: OutputArgs,
}

/// `--trajectory-period`: 0 (the grid's points) or from 0.1 ms to 10 s.
fn sampling_period(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v == 0.0 || (1e-4..=10.0).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{text}` is not a sampling period: 0 (the timing grid's points) or 0.0001 to 10 seconds"
        )),
    }
}

/// `trajectory.json` and `trajectory-<arm>.csv` of the selected motions, when the task times
/// motions and something is selected (`graspath_report::trajectory_files`); none otherwise.
fn trajectory_files<S: Scored>(
    task: &Task,
    selection: &Selection<S>,
    period: f64,
) -> Result<Vec<(String, Vec<u8>)>> {
    graspath_report::trajectory_files(task, selection, (period > 0.0).then_some(period))
        .map_err(|f| anyhow::anyhow!("the selected motion cannot be timed: {f}"))
}

/// The candidate records' format (`--format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Format {
    /// `candidates.json`, one JSON document.
    Json,
    /// `candidates.jsonl` (JSON Lines, streamed) and `ranking.jsonl`.
    Jsonl,
    /// `candidates.parquet` (streamed, a row group at a time) and `ranking.parquet`.
    Parquet,
}

/// `--trajectories`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum TrajectoriesArg {
    /// No joint trajectories.
    None,
    /// Feasible candidates' only.
    Feasible,
    /// Every candidate's.
    All,
}

impl TrajectoriesArg {
    fn or_default_for(choice: Option<Self>, format: Format) -> Trajectories {
        match (choice, format) {
            (Some(Self::None), _) => Trajectories::None,
            (Some(Self::Feasible), _) | (None, Format::Jsonl | Format::Parquet) => {
                Trajectories::Feasible
            }
            (Some(Self::All), _) | (None, Format::Json) => Trajectories::All,
        }
    }
}

/// A task's selection and the files that report it (relative names, rendered in memory).
pub(crate) struct TaskRun {
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
pub(crate) fn run_task(
    task: &Task,
    parameter: Option<&FamilyParameter>,
    output: &OutputArgs,
    title: &str,
    report: bool,
    trajectories: Trajectories,
) -> Result<TaskRun> {
    let mut run = run_task_but_candidates(task, parameter, output, title, report)?;
    let candidates = candidates_json_bytes(&run.selection, trajectories);
    run.files
        .insert(0, ("candidates.json".to_string(), candidates));
    Ok(run)
}

/// [`run_task`] without `candidates.json`, which [`run`] writes as it renders it.
fn run_task_but_candidates(
    task: &Task,
    parameter: Option<&FamilyParameter>,
    output: &OutputArgs,
    title: &str,
    report: bool,
) -> Result<TaskRun> {
    let total = task.candidate_count() * task.arms().len();
    let progress = Progress::new(output, total as u64, title, "candidates");
    let started = std::time::Instant::now();
    let selection = select(task, &|| progress.inc())?;
    progress.finish();
    let elapsed = started.elapsed();
    let mut files = summary_files(task, &selection)?;
    if report {
        let _rendering = tracing::info_span!("render the report").entered();
        files.extend(render_report(task, &selection, parameter)?);
    }
    Ok(TaskRun {
        selection,
        files,
        elapsed,
    })
}

/// `summary.json` and, with two arms, `pairs.json`: their names and bytes.
fn summary_files<S: Scored>(
    task: &Task,
    selection: &Selection<S>,
) -> Result<Vec<(String, Vec<u8>)>> {
    let _summing_up = tracing::info_span!("sum up").entered();
    let pretty = |v: serde_json::Value| -> Result<Vec<u8>> {
        let mut bytes = serde_json::to_vec_pretty(&v)?;
        bytes.push(b'\n');
        Ok(bytes)
    };
    let mut files = vec![(
        "summary.json".to_string(),
        pretty(summary_json(task, selection))?,
    )];
    if task.arms().len() == 2 {
        files.push(("pairs.json".to_string(), pretty(pairs_json(selection))?));
    }
    Ok(files)
}

/// Writes `files` (rendered already) and the selected grasps' timed trajectories into the
/// output's temporary folder, then moves the folder into place.
fn write_other_files<S: Scored>(
    mut folder: FolderWriter,
    task: &Task,
    selection: &Selection<S>,
    trajectory_period: f64,
    files: &[(String, Vec<u8>)],
) -> Result<()> {
    let _writing = tracing::info_span!("write the other files").entered();
    for (name, bytes) in files {
        folder.write(name, bytes)?;
    }
    for (name, bytes) in trajectory_files(task, selection, trajectory_period)? {
        folder.write(&name, &bytes)?;
    }
    folder.finish()?;
    Ok(())
}

/// Where a streamed run's candidate records go.
enum Records {
    /// `candidates.jsonl`.
    Lines(BufWriter<Writeback>),
    /// `candidates.parquet`.
    Parquet(Box<CandidatesParquet<BufWriter<Writeback>>>),
}

/// Runs a loaded task with `--format jsonl` or `parquet`: the candidates file is written (into
/// the output's temporary folder) as the candidates are scored; the ranking file,
/// `summary.json` and, with two arms, `pairs.json` at the end; then the folder is moved into
/// place. Returns the selection reduced to the candidates' scalars, and the time spent
/// selecting.
fn stream_task(
    task: &Task,
    args: &SelectArgs,
    existing: Existing,
    title: &str,
    trajectories: Trajectories,
) -> Result<(Selection<CandidateScalars>, Duration)> {
    let mut folder = FolderWriter::begin(&args.out, existing)?;
    let cannot = |name: &str| format!("cannot write {}", args.out.join(name).display());
    let (candidates_name, ranking_name) = match args.format {
        Format::Parquet => ("candidates.parquet", "ranking.parquet"),
        Format::Json | Format::Jsonl => ("candidates.jsonl", "ranking.jsonl"),
    };
    let file = BufWriter::with_capacity(1 << 20, Writeback::new(folder.create(candidates_name)?));
    let mut records = match args.format {
        Format::Parquet => Records::Parquet(Box::new(
            CandidatesParquet::new(file, trajectories).with_context(|| cannot(candidates_name))?,
        )),
        Format::Json | Format::Jsonl => Records::Lines(file),
    };
    let total = task.candidate_count() * task.arms().len();
    let progress = Progress::new(&args.output, total as u64, title, "candidates");
    let started = std::time::Instant::now();
    // A write fails with the file written; a candidate file that can no longer be read (it
    // changed since it was checked) with its own error.
    // A JSON Lines record is rendered on the worker that scored its candidate (in parallel),
    // and written in candidate order; a Parquet row is appended to the writer's columns in
    // order.
    let lines = matches!(records, Records::Lines(_));
    let render_line = |streamed: &Streamed<'_>| -> std::io::Result<Vec<u8>> {
        let mut line = Vec::new();
        write_candidate_line(&mut line, streamed, trajectories).map(|()| line)
    };
    let render = |streamed: Streamed<'_>| lines.then(|| render_line(&streamed));
    let selection =
        select_streaming_prepared(task, &|| progress.inc(), render, |streamed, rendered| {
            match &mut records {
                Records::Lines(file) => rendered
                    .unwrap_or_else(|| render_line(&streamed))
                    .and_then(|line| file.write_all(&line))
                    .map_err(anyhow::Error::from),
                Records::Parquet(writer) => writer.push(&streamed).map_err(anyhow::Error::from),
            }
            .with_context(|| cannot(candidates_name))
        })?;
    progress.finish();
    let elapsed = started.elapsed();
    let finishing = tracing::info_span!("finish the candidates file").entered();
    let file = match records {
        Records::Lines(lines) => lines,
        Records::Parquet(writer) => writer.finish().with_context(|| cannot(candidates_name))?,
    };
    file.into_inner()
        .map_err(std::io::IntoInnerError::into_error)
        .with_context(|| cannot(candidates_name))?;
    drop(finishing);
    let _ranking_file = tracing::info_span!("write the ranking file").entered();
    let ranking = BufWriter::new(folder.create(ranking_name)?);
    let ranking = match args.format {
        Format::Parquet => {
            write_ranking_parquet(ranking, &selection).with_context(|| cannot(ranking_name))?
        }
        Format::Json | Format::Jsonl => {
            let mut ranking = ranking;
            write_ranking_jsonl(&mut ranking, &selection).with_context(|| cannot(ranking_name))?;
            ranking
        }
    };
    ranking
        .into_inner()
        .map_err(std::io::IntoInnerError::into_error)
        .with_context(|| cannot(ranking_name))?;
    drop(_ranking_file);
    let files = summary_files(task, &selection)?;
    write_other_files(folder, task, &selection, args.trajectory_period, &files)?;
    Ok((selection, elapsed))
}

/// Runs the subcommand: [`Finished::NothingSelected`] (exit code 3) when nothing is selected
/// and `--allow-empty` is not given; the results are written in either case.
pub(crate) fn run(args: &SelectArgs) -> Result<Finished> {
    let existing = Existing::replace_if(args.force);
    // Refuse a bad --out before the work, not after it.
    check_folder_target(&args.out, existing)?;
    let reading = tracing::info_span!("read the task").entered();
    let file = TaskFile::load(&args.task).context("cannot use the task file")?;
    super::check_out_spares_task_inputs(&args.out, &args.task, &file)?;
    let title = args.task.display().to_string();
    let base_dir = args.task.parent().map(PathBuf::from).unwrap_or_default();
    let trajectories = TrajectoriesArg::or_default_for(args.trajectories, args.format);
    if args.format == Format::Json {
        let task = Task::from_file(&file, &title, &base_dir).context("cannot use the task file")?;
        task.check_selection_memory().context(
            "cannot hold the selection in memory (stream it with --format jsonl or parquet)",
        )?;
        super::print_warnings(&title, &task);
        let parameter = FamilyParameter::from_task_file(&file, &task.all_candidates()?);
        drop(reading);
        let run =
            run_task_but_candidates(&task, parameter.as_ref(), &args.output, &title, args.report)?;
        // `candidates.json` is written as it is rendered, then the other files.
        let mut folder = FolderWriter::begin(&args.out, existing)?;
        let name = "candidates.json";
        let writing = tracing::info_span!("write the candidates file").entered();
        let mut file = folder.create(name)?;
        write_candidates_json(&mut file, &run.selection, trajectories)
            .with_context(|| format!("cannot write {}", args.out.join(name).display()))?;
        drop(writing);
        write_other_files(
            folder,
            &task,
            &run.selection,
            args.trajectory_period,
            &run.files,
        )?;
        return finish(args, &task, &run.selection, &title, run.elapsed);
    }
    if args.report {
        return Err(crate::bad_input!(
            "--report needs every candidate's series in memory: use it with --format json"
        ));
    }
    // A candidate family is computed, and a graspath candidate file read, chunk by chunk as
    // they are scored, never held whole.
    let task =
        Task::from_file_chunked(&file, &title, &base_dir).context("cannot use the task file")?;
    super::print_warnings(&title, &task);
    drop(reading);
    let (selection, elapsed) = stream_task(&task, args, existing, &title, trajectories)?;
    finish(args, &task, &selection, &title, elapsed)
}

/// Prints the outcome of a run whose results are written, and tells whether anything was
/// selected.
fn finish<S: Scored>(
    args: &SelectArgs,
    task: &Task,
    selection: &Selection<S>,
    title: &str,
    elapsed: Duration,
) -> Result<Finished> {
    let empty = nothing_selected(selection);
    if args.output.json {
        crate::say!(
            "{}",
            serde_json::to_string_pretty(&summary_json(task, selection))?
        );
    } else if !args.output.quiet {
        print_summary_table(task, selection, title, elapsed);
        crate::say!("  wrote {}", args.out.display());
    }
    if empty && !args.allow_empty {
        let what = if task.arms().len() == 2 {
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
