//! `graspath generate`: grasp candidates with log-likelihoods on an object cloud.

use anyhow::{Context, Result};
use clap::Args;
use graspath::cloud::load_cloud_argument;
use graspath::fsutil::{check_file_target, write_file, Existing};
use graspath::grasp::model::{candidates_json, generate, GenerateOptions, GraspModel, Progress};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;

/// Generates grasp candidates for an object cloud from a trained model and writes the
/// candidate file (object frame, best first).
#[derive(Debug, Args)]
pub struct GenerateArgs {
    /// The model file written by `graspath train`.
    #[arg(long, value_name = "FILE")]
    model: PathBuf,
    /// The object cloud: .ply, .pcd, or a .json cloud source (primitive or mesh to sample).
    #[arg(long, value_name = "FILE")]
    cloud: PathBuf,
    /// Where to write the candidates (a new file, or any existing regular file with --force).
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
    /// Replace an existing --out file (atomically). Symbolic links and devices are refused
    /// even so.
    #[arg(long)]
    force: bool,
    /// Seed of every random choice: the same inputs and seed give the same bytes.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Number of seeds.
    #[arg(long, default_value_t = 50_000)]
    seeds: usize,
    /// Annealing steps.
    #[arg(long, default_value_t = 500)]
    steps: usize,
    /// Query-density kernels per link in contact.
    #[arg(long, default_value_t = 5000)]
    query_kernels: usize,
    /// Write at most this many candidates (all survivors of the staged selection by default).
    #[arg(long, value_name = "N")]
    max_candidates: Option<usize>,
    /// Print nothing on success and show no progress bar.
    #[arg(long)]
    quiet: bool,
}

/// Runs the subcommand.
pub fn run(args: &GenerateArgs) -> Result<()> {
    let existing = Existing::replace_if(args.force);
    check_file_target(&args.out, existing)?;
    let model = GraspModel::read(&args.model)?;
    let cloud = load_cloud_argument(&args.cloud)?;
    let source = args.cloud.display().to_string();
    if cloud.normals.is_none() && !args.quiet {
        eprintln!(
            "note: {source} has no normals; estimating them by PCA within {:.0} mm, oriented {}",
            model.features.normal_radius * 1000.0,
            match model.features.orientation {
                graspath::cloud::NormalOrientation::Viewpoint(v) =>
                    format!("towards the viewpoint {v:?}"),
                graspath::cloud::NormalOrientation::AwayFromCentroid =>
                    "away from the cloud's centroid".to_string(),
            }
        );
    }
    let options = GenerateOptions {
        seeds: args.seeds,
        steps: args.steps,
        query_kernels: args.query_kernels,
        seed: args.seed,
        ..GenerateOptions::default()
    };
    let bar = if args.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(1);
        bar.set_style(
            ProgressStyle::with_template("{msg:>18} [{bar:40}] {pos}/{len}")
                .context("progress style")?
                .progress_chars("=> "),
        );
        bar
    };
    let report = |p: Progress| {
        let (message, done, total) = match p {
            Progress::Preparing => ("query densities", 0, 1),
            Progress::Seeds(d, t) => ("seeds", d, t),
            Progress::FirstStage(d, t) => ("annealing 1/2", d, t),
            Progress::SecondStage(d, t) => ("annealing 2/2", d, t),
        };
        bar.set_message(message);
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let started = std::time::Instant::now();
    let mut candidates = generate(&model, &cloud, &options, &source, &report)?;
    bar.finish_and_clear();
    if let Some(n) = args.max_candidates {
        candidates.truncate(n);
    }
    write_file(
        &args.out,
        &candidates_json(&candidates, &model.label)?,
        existing,
    )?;
    if !args.quiet {
        let best = candidates.first().map_or(f64::NAN, |c| c.log_likelihood);
        println!(
            "{} candidates from {} points in {:.2} s (best log-likelihood {:.3}); wrote {}",
            candidates.len(),
            cloud.len(),
            started.elapsed().as_secs_f64(),
            best,
            args.out.display()
        );
    }
    Ok(())
}
