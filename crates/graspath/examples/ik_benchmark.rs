//! TRAC-IK's benchmark protocol on graspath's IK solver.
//!
//! For each robot: draw joint configurations uniformly within the limits (seeded), compute
//! the tip pose by forward kinematics, and solve IK for that pose from the mid-limits start
//! configuration with tolerance 1e-5 (m and rad) and a 5 ms budget, one solve at a time on one
//! thread. Prints the solve rate and the mean, median, p99 and maximum time per solve.
//!
//! ```text
//! cargo run --release -p graspath --example ik_benchmark -- --samples 10000
//! ```
//!
//! Options: `--samples N` (default 10000), `--robot baxter|panda|ur5|all` (default all),
//! `--seed S` (default 42), `--shared DIR` (default `$GRASPATH_SHARED` or `../shared`),
//! `--max-time-ms T` (default 5; 0 for none), `--max-iterations K` (default 100000).

use graspath::robot::{load_urdf_chain, solve_ik, Chain, IkOptions};
use nalgebra::Isometry3;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use std::path::PathBuf;
use std::time::{Duration, Instant};

struct Args {
    samples: usize,
    robot: String,
    seed: u64,
    shared: PathBuf,
    max_time_ms: f64,
    max_iterations: usize,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        samples: 10_000,
        robot: "all".into(),
        seed: 42,
        max_time_ms: 5.0,
        max_iterations: IkOptions::default().max_iterations,
        shared: std::env::var_os("GRASPATH_SHARED")
            .map(PathBuf::from)
            .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared")),
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        match flag.as_str() {
            "--samples" => {
                args.samples = value()?.parse().map_err(|e| format!("--samples: {e}"))?;
            }
            "--robot" => args.robot = value()?,
            "--seed" => args.seed = value()?.parse().map_err(|e| format!("--seed: {e}"))?,
            "--shared" => args.shared = PathBuf::from(value()?),
            "--max-time-ms" => {
                args.max_time_ms = value()?
                    .parse()
                    .map_err(|e| format!("--max-time-ms: {e}"))?;
            }
            "--max-iterations" => {
                args.max_iterations = value()?
                    .parse()
                    .map_err(|e| format!("--max-iterations: {e}"))?;
            }
            other => return Err(format!("unknown option {other}")),
        }
    }
    Ok(args)
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("ik_benchmark: {e}");
            std::process::exit(2);
        }
    };
    let robots = [
        ("baxter", "baxter.urdf", "base", "left_gripper"),
        ("panda", "panda.urdf", "panda_link0", "panda_hand_tcp"),
        ("ur5", "ur5_robot.urdf", "base_link", "tool0"),
    ];
    println!(
        "{:<8} {:>4} {:>8} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9}",
        "robot",
        "dof",
        "samples",
        "solved",
        "mean_us",
        "median_us",
        "p99_us",
        "p99.9_us",
        "max_us",
        "mean_it"
    );
    for (name, file, base, tip) in robots {
        if args.robot != "all" && args.robot != name {
            continue;
        }
        let path = args.shared.join("robots").join(file);
        let chain = match load_urdf_chain(&path, base, tip, None) {
            Ok(c) => c,
            Err(e) => {
                eprintln!("ik_benchmark: {name}: {e}");
                std::process::exit(1);
            }
        };
        run(name, &chain, &args);
    }
}

fn run(name: &str, chain: &Chain, args: &Args) {
    let samples = args.samples;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(args.seed);
    let targets: Vec<Isometry3<f64>> = (0..samples)
        .map(|_| {
            let q: Vec<f64> = chain
                .lower()
                .iter()
                .zip(chain.upper())
                .map(|(&lo, &hi)| rng.random_range(lo..=hi))
                .collect();
            nalgebra::convert(chain.pose(&q).expect("q has the chain's length"))
        })
        .collect();
    let q_start = chain.mid_configuration();
    let options = IkOptions {
        position_tolerance: 1e-5,
        rotation_tolerance: 1e-5,
        // 0 turns the time budget off (iterations only: reproducible).
        max_time: (args.max_time_ms > 0.0)
            .then(|| Duration::from_secs_f64(args.max_time_ms * 1e-3)),
        max_iterations: args.max_iterations,
        ..IkOptions::default()
    };
    let mut times = Vec::with_capacity(samples);
    let mut solved = 0usize;
    let mut iterations = 0usize;
    for target in &targets {
        let start = Instant::now();
        let solution = solve_ik(chain, target, &q_start, &options).expect("valid input");
        times.push(start.elapsed().as_secs_f64() * 1e6);
        iterations += solution.iterations;
        if let Some(q) = &solution.q {
            // Independent check: the configuration is in the limits and reaches the target.
            assert!(
                chain.within_limits(q),
                "{name}: solution outside the limits"
            );
            let reached: Isometry3<f64> = nalgebra::convert(chain.pose(q).expect("fk"));
            assert!(
                (reached.translation.vector - target.translation.vector).norm() <= 1e-5
                    && reached.rotation.angle_to(&target.rotation) <= 1e-5,
                "{name}: solution misses the target"
            );
            solved += 1;
        }
    }
    let mean = times.iter().sum::<f64>() / samples as f64;
    times.sort_by(f64::total_cmp);
    let pct = |p: f64| times[((samples as f64 * p).ceil() as usize).clamp(1, samples) - 1];
    println!(
        "{:<8} {:>4} {:>8} {:>9.3}% {:>10.1} {:>10.1} {:>10.1} {:>10.1} {:>10.1} {:>9.1}",
        name,
        chain.dof(),
        samples,
        100.0 * solved as f64 / samples as f64,
        mean,
        pct(0.5),
        pct(0.99),
        pct(0.999),
        times[samples - 1],
        iterations as f64 / samples as f64
    );
}
