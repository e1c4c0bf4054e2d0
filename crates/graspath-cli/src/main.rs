//! `graspath`: choose where a robot should grasp an object so that it can then perform a given
//! manipulation task well.
#![warn(unreachable_pub)]

mod commands;
mod exit;
mod jsonl;
mod output;
mod robot_args;
mod timings;
mod writeback;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// mimalloc instead of the C library's allocator: scoring workers free results that another
/// thread allocated, which the C library's allocator serialises on a lock per arena.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Task-relevant grasp selection (Ghalamzan et al., IROS 2016) and the kinematics behind it.
#[derive(Debug, Parser)]
#[command(name = "graspath", version, about, long_about = None, after_help = exit::TABLE)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Forward kinematics, Jacobian and manipulability for joint configurations (JSON Lines).
    Kinematics(commands::kinematics::KinematicsArgs),
    /// Score every grasp candidate along a task and rank them (one arm or arm pairs).
    Select(commands::select::SelectArgs),
    /// Run the selection with the object started at every placement of a grid (x, y, z, yaw):
    /// map.json and heatmaps.
    Map(commands::map::MapArgs),
    /// Reproduce the paper's experiments on the built-in Baxter (no files needed).
    Demo(commands::demo::DemoArgs),
    /// Inverse kinematics of tip poses (JSON Lines) or of a whole trajectory (--trajectory).
    Ik(commands::ik::IkArgs),
    /// Learn a one-shot grasp model from one demonstration (hand, object cloud, waypoints).
    Train(commands::train::TrainArgs),
    /// Generate grasp candidates with log-likelihoods on an object cloud from a trained model.
    Generate(commands::generate::GenerateArgs),
    /// Write the task's world (arms, gripper, object, table, obstacles) as MJCF for MuJoCo.
    ExportMjcf(commands::export_mjcf::ExportMjcfArgs),
}

/// How a run that did not fail ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Finished {
    /// Everything asked for was done.
    Done,
    /// `select` wrote its results but selected nothing (exit code 3).
    NothingSelected,
}

/// On SIGINT, SIGTERM or SIGHUP: the run's temporary files and folders are removed (an old
/// folder being replaced is put back) and the process exits with 128 + the signal's number, as
/// a shell reports a process killed by it.
#[cfg(unix)]
fn remove_temporaries_on_signals() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            graspath::output_files::remove_temporaries();
            eprintln!("graspath: stopped by a signal; nothing was written");
            std::process::exit(128 + signal);
        }
    });
}

fn main() -> ExitCode {
    #[cfg(unix)]
    remove_temporaries_on_signals();
    let cli = Cli::parse();
    let done = |r: anyhow::Result<()>| r.map(|()| Finished::Done);
    let timings = match &cli.command {
        Command::Select(args) if args.output.timings => timings::Recorder::install(),
        Command::Map(args) if args.output.timings => timings::Recorder::install(),
        _ => None,
    };
    let result = match cli.command {
        Command::Kinematics(args) => done(commands::kinematics::run(&args)),
        Command::Select(args) => commands::select::run(&args),
        Command::Map(args) => commands::map::run(&args),
        Command::Demo(args) => done(commands::demo::run(&args)),
        Command::Ik(args) => done(commands::ik::run(&args)),
        Command::Train(args) => done(commands::train::run(&args)),
        Command::Generate(args) => done(commands::generate::run(&args)),
        Command::ExportMjcf(args) => done(commands::export_mjcf::run(&args)),
    };
    if let Some(timings) = timings {
        eprint!("{}", timings.report());
    }
    ExitCode::from(match result {
        Ok(Finished::Done) => exit::SUCCESS,
        Ok(Finished::NothingSelected) => exit::NOTHING_SELECTED,
        Err(error) => {
            eprintln!("graspath: error: {}", exit::message(&error));
            exit::code_of(&error)
        }
    })
}
