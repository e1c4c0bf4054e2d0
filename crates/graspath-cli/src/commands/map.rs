//! `graspath map --task FILE --x START:END:COUNT --y START:END:COUNT [--z …] [--yaw-deg …]
//! [--out DIR]`: the task's selection with the object started at every placement of a grid;
//! writes `map.json` and the heatmaps (SVG, PNG). The folder is written as a whole.

use crate::output::{OutputArgs, Progress};
use crate::Finished;
use anyhow::{Context, Result};
use clap::Args;
use graspath::output_files::{check_folder_target, write_files, Existing};
use graspath::placement::{placement_map, FamilyParameter, GridAxis, PlacementGrid};
use graspath::task::{builder_from_file, TaskFile};
use graspath_report::{placement_figures, placement_map_json, render_svg_and_png, Plot};
use std::path::{Path, PathBuf};

/// Options of `graspath map`.
#[derive(Debug, Args)]
#[command(after_help = crate::exit::TABLE)]
pub(crate) struct MapArgs {
    /// The task file (YAML or JSON; see docs/task-file.md). Its `object.pose` is replaced by
    /// each placement.
    #[arg(long, value_name = "FILE")]
    task: PathBuf,
    /// World x of the object's start (m): START:END:COUNT (both ends included) or one value.
    #[arg(long, value_name = "START:END:COUNT", allow_hyphen_values = true)]
    x: String,
    /// World y of the object's start (m): START:END:COUNT or one value.
    #[arg(long, value_name = "START:END:COUNT", allow_hyphen_values = true)]
    y: String,
    /// World z of the object's start (m): START:END:COUNT or one value (default: the task's).
    #[arg(long, value_name = "START:END:COUNT", allow_hyphen_values = true)]
    z: Option<String>,
    /// Yaw about the world vertical through the object's origin (degrees), added to the
    /// task's orientation: START:END:COUNT or one value (default: none).
    #[arg(
        long = "yaw-deg",
        value_name = "START:END:COUNT",
        allow_hyphen_values = true
    )]
    yaw_deg: Option<String>,
    /// Where to write `map.json` and the figures: a new or empty folder (or, with --force, a
    /// folder whose contents are replaced as a whole).
    #[arg(long, value_name = "DIR", default_value = "graspath-map")]
    out: PathBuf,
    /// Replace an existing non-empty --out folder as a whole.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    pub(crate) output: OutputArgs,
}

fn axis(text: &str, flag: &str) -> Result<GridAxis> {
    Ok(GridAxis::parse(text, flag)?)
}

fn grid(args: &MapArgs) -> Result<PlacementGrid> {
    Ok(PlacementGrid {
        x: axis(&args.x, "--x")?,
        y: axis(&args.y, "--y")?,
        z: args.z.as_deref().map(|t| axis(t, "--z")).transpose()?,
        yaw: args
            .yaw_deg
            .as_deref()
            .map(|t| axis(t, "--yaw-deg").map(|a| a.scaled(1f64.to_radians())))
            .transpose()?,
    })
}

/// Runs the subcommand.
pub(crate) fn run(args: &MapArgs) -> Result<Finished> {
    let existing = Existing::replace_if(args.force);
    check_folder_target(&args.out, existing)?;
    let grid = grid(args)?;
    let reading = tracing::info_span!("read the task").entered();
    let file = TaskFile::load(&args.task).context("cannot use the task file")?;
    super::check_out_spares_task_inputs(&args.out, &args.task, &file)?;
    let name = args.task.display().to_string();
    let base_dir = args
        .task
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let builder = builder_from_file(&file, &name, &base_dir).context("cannot use the task file")?;
    // The family parameter is read off the task at its own pose (candidates do not move).
    let task = builder
        .clone()
        .build()
        .context("cannot use the task file")?;
    super::print_warnings(&name, &task);
    let parameter = FamilyParameter::from_task_file(&file, &task.all_candidates()?);
    drop(task);
    drop(reading);
    let progress = Progress::new(&args.output, grid.len() as u64, &name, "placements");
    let started = std::time::Instant::now();
    let map = tracing::info_span!("score the placements")
        .in_scope(|| placement_map(&builder, &grid, parameter, &|| progress.inc()))?;
    progress.finish();
    let elapsed = started.elapsed();
    let writing = tracing::info_span!("write the map files").entered();
    let json = placement_map_json(&name, &map);
    let mut bytes = serde_json::to_vec_pretty(&json)?;
    bytes.push(b'\n');
    let mut files = vec![("map.json".to_string(), bytes)];
    let figures = placement_figures(&map);
    let plots: Vec<&Plot> = figures.iter().map(|figure| &figure.plot).collect();
    for (figure, (svg, png)) in figures.iter().zip(render_svg_and_png(&plots)?) {
        files.push((format!("{}.svg", figure.name), svg.into_bytes()));
        files.push((format!("{}.png", figure.name), png));
    }
    write_files(&args.out, &files, existing)?;
    drop(writing);
    if args.output.json {
        crate::say!("{}", serde_json::to_string_pretty(&json)?);
    } else if !args.output.quiet {
        print_map_table(&map, &name, elapsed);
        crate::say!("  wrote {}", args.out.display());
    }
    Ok(Finished::Done)
}

fn print_map_table(
    map: &graspath::placement::PlacementMap,
    name: &str,
    elapsed: std::time::Duration,
) {
    crate::say!(
        "{name}: {} placements x {} arm(s), {:.3} s",
        map.records.len(),
        map.arms.len(),
        elapsed.as_secs_f64()
    );
    for (k, arm) in map.arms.iter().enumerate() {
        let with_best: Vec<_> = map
            .records
            .iter()
            .filter_map(|r| r.arms[k].best.as_ref().map(|b| (r, b)))
            .collect();
        let best = with_best
            .iter()
            .max_by(|a, b| a.1.score.total_cmp(&b.1.score));
        match best {
            Some((r, b)) => crate::say!(
                "  arm {arm}: a grasp at {} of {} placements; highest score {:.4} ({}, id {}) at \
                 x {:.3}, y {:.3}, z {:.3}, yaw {:+.1}°",
                with_best.len(),
                map.records.len(),
                b.score,
                b.label,
                b.id,
                r.x,
                r.y,
                r.z,
                r.yaw_deg
            ),
            None => crate::say!("  arm {arm}: no placement has an eligible candidate"),
        }
    }
}
