//! `graspath`: choose where a robot should grasp an object so that it can then perform a given
//! manipulation task well.

mod commands;
mod jsonl;
mod robot_args;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Task-relevant grasp selection (Ghalamzan et al., IROS 2016) and the kinematics behind it.
#[derive(Debug, Parser)]
#[command(name = "graspath", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Forward kinematics, Jacobian and manipulability for joint configurations (JSON Lines).
    Kinematics(commands::kinematics::KinematicsArgs),
    /// Inverse kinematics of tip poses (JSON Lines) or of a whole trajectory (--trajectory).
    Ik(commands::ik::IkArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Kinematics(args) => commands::kinematics::run(&args),
        Command::Ik(args) => commands::ik::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("graspath: error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
