//! `graspath-fuzz`: fuzz every graspath input path (see `TESTING.md`).
//!
//! `cargo run --release -p graspath-fuzz -- [--target NAME|all] [--execs N | --seconds S]
//! [--seed S] [--findings DIR]`

use anyhow::{bail, Result};
use clap::Parser;
use graspath_fuzz::alloc::{self, LimitAlloc};
use graspath_fuzz::campaign::{self, Settings};
use graspath_fuzz::targets;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

#[global_allocator]
static ALLOCATOR: LimitAlloc = LimitAlloc;

/// Fuzz graspath's parsers and CLI inputs (stable Rust; panic, hang and allocation oracles).
#[derive(Debug, Parser)]
#[command(name = "graspath-fuzz")]
struct Args {
    /// A target name, or `all`.
    #[arg(long, default_value = "all")]
    target: String,
    /// Executions per target.
    #[arg(long, conflicts_with = "ci_slice")]
    execs: Option<u64>,
    /// Wall time per target (s).
    #[arg(long)]
    seconds: Option<f64>,
    /// Each target's deterministic CI-slice execution count.
    #[arg(long)]
    ci_slice: bool,
    /// Campaign seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Where reproducers and summary.json go.
    #[arg(long, default_value = "fuzz-findings")]
    findings: PathBuf,
    /// Time limit of one execution (ms).
    #[arg(long, default_value_t = 5000)]
    timeout_ms: u64,
    /// Time budget for minimising each new finding (s); 0 disables it.
    #[arg(long, default_value_t = 20.0)]
    minimise_seconds: f64,
    /// Bound on one allocation (bytes).
    #[arg(long, default_value_t = alloc::DEFAULT_SINGLE_LIMIT)]
    single_limit: usize,
    /// Bound on live memory (bytes).
    #[arg(long, default_value_t = alloc::DEFAULT_TOTAL_LIMIT)]
    total_limit: usize,
    /// List the targets and exit.
    #[arg(long)]
    list: bool,
    /// Internal: run as a worker.
    #[arg(long, hide = true)]
    worker: bool,
    /// Internal: first input index of a worker.
    #[arg(long, hide = true, default_value_t = 0)]
    start: u64,
    /// Internal: end (exclusive) of a worker's index range.
    #[arg(long, hide = true, default_value_t = u64::MAX)]
    end: u64,
    /// Internal: a worker's remaining time (ms).
    #[arg(long, hide = true)]
    deadline_ms: Option<u64>,
    /// Internal: replay one input file.
    #[arg(long, hide = true)]
    replay: Option<PathBuf>,
    /// Internal: the work directory shared with the parent.
    #[arg(long, hide = true)]
    work: Option<PathBuf>,
    /// Internal: where a replay records its finding.
    #[arg(long, hide = true)]
    death: Option<PathBuf>,
}

fn main() -> ExitCode {
    match run() {
        Ok(code) => code,
        Err(error) => {
            eprintln!("graspath-fuzz: error: {error:#}");
            ExitCode::from(2)
        }
    }
}

fn run() -> Result<ExitCode> {
    let args = Args::parse();
    alloc::set_limits(args.single_limit, args.total_limit);
    if args.list {
        for t in targets::all() {
            println!("{:<16} {}", t.name, t.description);
        }
        return Ok(ExitCode::SUCCESS);
    }
    let findings = if args.findings.is_absolute() {
        args.findings.clone()
    } else {
        std::env::current_dir()?.join(&args.findings)
    };
    let settings = Settings {
        seed: args.seed,
        execs: args.execs,
        seconds: args.seconds,
        ci_slice: args.ci_slice,
        findings,
        timeout_ms: args.timeout_ms,
        minimise_seconds: args.minimise_seconds,
        single_limit: args.single_limit,
        total_limit: args.total_limit,
        exe: std::env::current_exe()?,
        work: args.work.clone().unwrap_or_else(|| {
            targets::scratch_root().join(format!("graspath-fuzz-work-{}", std::process::id()))
        }),
    };
    let chosen: Vec<&'static targets::Target> = if args.target == "all" {
        targets::all().iter().collect()
    } else {
        args.target
            .split(',')
            .map(|name| {
                targets::by_name(name).ok_or_else(|| {
                    let names: Vec<&str> = targets::all().iter().map(|t| t.name).collect();
                    anyhow::anyhow!(
                        "--target: unknown target '{name}' (targets: all, {})",
                        names.join(", ")
                    )
                })
            })
            .collect::<Result<_>>()?
    };
    if args.worker {
        let [target] = chosen.as_slice() else {
            bail!("a worker runs one target")
        };
        campaign::worker_main(
            &settings,
            target,
            args.start,
            args.end,
            args.deadline_ms.map(Duration::from_millis),
        )?;
        return Ok(ExitCode::SUCCESS);
    }
    if let Some(input) = &args.replay {
        let [target] = chosen.as_slice() else {
            bail!("a replay runs one target")
        };
        let death = args
            .death
            .clone()
            .unwrap_or_else(|| input.with_extension("death"));
        let code = campaign::replay_main(&settings, target, input, &death)?;
        return Ok(ExitCode::from(code as u8));
    }
    if args.execs.is_none() && args.seconds.is_none() && !args.ci_slice {
        bail!("give --execs N, --seconds S or --ci-slice");
    }
    let summary = campaign::run(&settings, &chosen)?;
    let total: u64 = summary.targets.iter().map(|t| t.execs).sum();
    let new = summary
        .targets
        .iter()
        .flat_map(|t| &t.findings)
        .filter(|f| f.known.is_none())
        .count();
    println!(
        "total: {total} executions; {new} new findings; summary in {}",
        settings.findings.join("summary.json").display()
    );
    Ok(if new == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
