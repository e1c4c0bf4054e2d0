//! `graspath generate`: grasp candidates with log-likelihoods on an object cloud.

use anyhow::{Context, Result};
use clap::Args;
use graspath::cloud::{load_cloud_filtered, CropBox, OutlierOptions, StatisticalOutliers};
use graspath::grasp::model::{candidates_json, generate, GenerateOptions, GraspModel, Progress};
use graspath::output_files::{check_file_target, write_file, Existing};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;

/// Generates grasp candidates for an object cloud from a trained model and writes the
/// candidate file (object frame, best first).
#[derive(Debug, Args)]
pub(crate) struct GenerateArgs {
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
    /// Random seed of every random choice: the same inputs and seed give the same bytes.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Number of initial grasps drawn before annealing (the model spec's "seeds").
    #[arg(long, value_name = "N", default_value_t = 50_000)]
    initial_grasps: usize,
    /// Annealing steps.
    #[arg(long, default_value_t = 500)]
    steps: usize,
    /// Query-density kernels per link in contact.
    #[arg(long, default_value_t = 5000)]
    query_kernels: usize,
    /// Write at most this many candidates (all survivors of the staged selection by default).
    #[arg(long, value_name = "N")]
    max_candidates: Option<usize>,
    /// Keep only the points inside this box of the cloud's frame (m):
    /// XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX.
    #[arg(
        long,
        value_name = "XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    crop_box: Option<Vec<f64>>,
    /// Remove the points farther than this from the sensor origin (m).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    max_range: Option<f64>,
    /// The sensor origin in the cloud's frame (m), for --max-range: X,Y,Z [default: 0,0,0].
    #[arg(
        long,
        value_name = "X,Y,Z",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    sensor_origin: Option<Vec<f64>>,
    /// Statistical outlier removal: k, the nearest neighbours whose mean distance is compared
    /// (turns the removal on; 20 when only --outlier-std-ratio is given).
    #[arg(long, value_name = "K")]
    outlier_neighbours: Option<usize>,
    /// Statistical outlier removal: remove a point whose mean neighbour distance exceeds the
    /// cloud's mean by more than this many standard deviations (turns the removal on; 2.0 when
    /// only --outlier-neighbours is given).
    #[arg(long, value_name = "ALPHA", allow_negative_numbers = true)]
    outlier_std_ratio: Option<f64>,
    /// Print nothing on success and show no progress bar.
    #[arg(long)]
    quiet: bool,
}

impl GenerateArgs {
    /// The outlier options given by the flags.
    fn outliers(&self) -> Result<OutlierOptions> {
        let count = |flag: &str, values: &Option<Vec<f64>>, n: usize| match values {
            Some(v) if v.len() != n => Err(anyhow::anyhow!(
                "{flag} needs {n} comma-separated numbers, got {}",
                v.len()
            )),
            _ => Ok(()),
        };
        count("--crop-box", &self.crop_box, 6)?;
        count("--sensor-origin", &self.sensor_origin, 3)?;
        let statistical = (self.outlier_neighbours.is_some() || self.outlier_std_ratio.is_some())
            .then(|| {
                let defaults = StatisticalOutliers::default();
                StatisticalOutliers {
                    neighbours: self.outlier_neighbours.unwrap_or(defaults.neighbours),
                    std_ratio: self.outlier_std_ratio.unwrap_or(defaults.std_ratio),
                }
            });
        Ok(OutlierOptions {
            crop_box: self.crop_box.as_ref().map(|v| CropBox {
                min: [v[0], v[1], v[2]],
                max: [v[3], v[4], v[5]],
            }),
            max_range: self.max_range,
            sensor_origin: self.sensor_origin.as_ref().map(|v| [v[0], v[1], v[2]]),
            statistical,
        })
    }
}

/// Runs the subcommand.
pub(crate) fn run(args: &GenerateArgs) -> Result<()> {
    let existing = Existing::replace_if(args.force);
    check_file_target(&args.out, existing)?;
    super::check_out_spares(&args.out, &[&args.model, &args.cloud])?;
    let model = GraspModel::read(&args.model)?;
    let (cloud, cloud_report) = load_cloud_filtered(&args.cloud, &args.outliers()?)?;
    let source = args.cloud.display().to_string();
    if !args.quiet && cloud_report.kept() != cloud_report.read {
        eprintln!("note: {source}: {cloud_report}");
    }
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
        initial_grasps: args.initial_grasps,
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
            Progress::InitialGrasps(d, t) => ("initial grasps", d, t),
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
