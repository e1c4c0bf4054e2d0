//! `graspath ik`: inverse kinematics of single poses (JSON Lines) or of a whole trajectory
//! (one JSON document).

use crate::bad_input;
use crate::jsonl::{for_each_line, open_input, source_name};
use crate::robot_args::RobotArgs;
use anyhow::{Context, Result};
use clap::Args;
use graspath::defaults;
use graspath::geometry::pose_from_rows;
use graspath::robot::{
    solve_ik, solve_trajectory, Chain, IkOptions, TrajectoryIkOptions, TrajectoryIkResult,
};
use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};
use std::io::Read;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Reads JSON Lines `{"pose":[[4×4]]}` (tip poses in the chain base frame, m, row-major) and
/// writes one line per pose: `{"q":[...] or null,"position_error":m,"rotation_error":rad,
/// "iterations":k,"time_us":t}`. With `--trajectory`, reads one document
/// `{"poses":[[[4×4]],...]}` and writes `{"branches":[{"q":[[...],...]}],"failure":...}`.
/// A target with a coordinate beyond ±1000 m is refused as bad input (exit code 2).
#[derive(Debug, Args)]
pub(crate) struct IkArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// Read from this file instead of stdin.
    #[arg(long, value_name = "FILE")]
    input: Option<PathBuf>,
    /// The start configuration: `mid` (middle of the limits), `zero`, or `q1,q2,...`
    /// (rad / m). Every pose of a JSON Lines input starts from it; a trajectory starts its
    /// first sample from it.
    #[arg(
        long,
        value_name = "Q_START",
        default_value = "mid",
        allow_hyphen_values = true
    )]
    start: String,
    /// Position (m) and rotation (rad) tolerance.
    #[arg(long, value_name = "EPS", default_value_t = defaults::IK_TOLERANCE)]
    tolerance: f64,
    /// Time budget per pose in milliseconds (single poses only: trajectories use iteration
    /// budgets so that their results are reproducible).
    #[arg(long, value_name = "MS", default_value_t = 5.0)]
    timeout_ms: f64,
    /// Random seed of the restarts (not the start configuration: see --start).
    #[arg(long, value_name = "N", default_value_t = defaults::IK_RANDOM_SEED)]
    random_seed: u64,
    /// Solve a whole trajectory `{"poses":[...]}` with continuous joint paths.
    #[arg(long)]
    trajectory: bool,
    /// Trajectories: largest joint change between consecutive samples (rad / m).
    #[arg(long, value_name = "STEP", default_value_t = defaults::MAX_JOINT_STEP)]
    max_joint_step: f64,
    /// Trajectories: how many distinct initial solutions (branches) to track.
    #[arg(long, value_name = "N", default_value_t = defaults::IK_BRANCHES)]
    branches: usize,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PoseLine {
    pose: [[f64; 4]; 4],
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TrajectoryInput {
    poses: Vec<[[f64; 4]; 4]>,
}

#[derive(Debug, Serialize)]
struct PoseOutput<'a> {
    q: Option<&'a [f64]>,
    position_error: f64,
    rotation_error: f64,
    iterations: usize,
    time_us: f64,
}

/// Runs the subcommand. The output is written only once the whole input has been processed.
pub(crate) fn run(args: &IkArgs) -> Result<()> {
    if !(args.tolerance.is_finite() && args.tolerance > 0.0) {
        return Err(bad_input!(
            "--tolerance: must be a positive number, got {}",
            args.tolerance
        ));
    }
    if !(args.timeout_ms.is_finite() && args.timeout_ms > 0.0) {
        return Err(bad_input!(
            "--timeout-ms: must be a positive number, got {}",
            args.timeout_ms
        ));
    }
    if !(args.max_joint_step.is_finite() && args.max_joint_step > 0.0) {
        return Err(bad_input!(
            "--max-joint-step: must be a positive number, got {}",
            args.max_joint_step
        ));
    }
    if args.branches == 0 {
        return Err(bad_input!("--branches: must be at least 1"));
    }
    let chain = args.robot.load()?;
    let q_start = parse_start(&args.start, &chain).context("--start")?;
    let options = IkOptions {
        position_tolerance: args.tolerance,
        rotation_tolerance: args.tolerance,
        max_time: Some(
            Duration::try_from_secs_f64(args.timeout_ms * 1e-3)
                .map_err(|e| bad_input!("--timeout-ms: {e}"))?,
        ),
        random_seed: args.random_seed,
        ..IkOptions::default()
    };
    let source = source_name(args.input.as_deref());
    let mut input = open_input(args.input.as_deref())?;
    let mut output = Vec::new();
    if args.trajectory {
        let mut text = String::new();
        input
            .read_to_string(&mut text)
            .map_err(|e| bad_input!("{source}: cannot read: {e}"))?;
        let document: TrajectoryInput = serde_json::from_str(&text).map_err(|e| {
            let e = graspath::input::plain_serde_message(&e.to_string());
            bad_input!("{source}: not a valid trajectory document: {e}")
        })?;
        let poses = document
            .poses
            .iter()
            .enumerate()
            .map(|(i, rows)| {
                target_from_rows(rows).with_context(|| format!("{source}: field 'poses[{i}]'"))
            })
            .collect::<Result<Vec<Isometry3<f64>>>>()?;
        if poses.is_empty() {
            return Err(bad_input!(
                "{source}: field 'poses': the trajectory has no poses"
            ));
        }
        let trajectory_options = TrajectoryIkOptions {
            ik: IkOptions {
                max_time: None,
                ..options
            },
            max_joint_step: args.max_joint_step,
            branches: args.branches,
            ..TrajectoryIkOptions::default()
        };
        let result: TrajectoryIkResult =
            solve_trajectory(&chain, &poses, &q_start, &trajectory_options)?;
        serde_json::to_writer(&mut output, &result)?;
        output.push(b'\n');
    } else {
        for_each_line(input, &source, |_, line: PoseLine| {
            let target = target_from_rows(&line.pose).context("field 'pose'")?;
            let start = Instant::now();
            let solution = solve_ik(&chain, &target, &q_start, &options)?;
            let time_us = start.elapsed().as_secs_f64() * 1e6;
            if !(solution.position_error.is_finite() && solution.rotation_error.is_finite()) {
                anyhow::bail!(
                    "the solver returned a non-finite error (position {}, rotation {})",
                    solution.position_error,
                    solution.rotation_error
                );
            }
            serde_json::to_writer(
                &mut output,
                &PoseOutput {
                    q: solution.q.as_deref(),
                    position_error: solution.position_error,
                    rotation_error: solution.rotation_error,
                    iterations: solution.iterations,
                    time_us,
                },
            )?;
            output.push(b'\n');
            Ok(())
        })?;
    }
    crate::output::write_result_to_stdout(&output)
}

/// Targets with a coordinate beyond ±this (m, chain base frame) are refused: no arm reaches
/// them, and the position error of such a target is not a meaningful (or even finite) number.
pub(crate) const MAX_TARGET_COORDINATE: f64 = 1e3;

/// A target pose from its 4×4 rows: a valid rigid transform within [`MAX_TARGET_COORDINATE`].
fn target_from_rows(rows: &[[f64; 4]; 4]) -> Result<Isometry3<f64>> {
    let pose = pose_from_rows(rows)?;
    let farthest = pose.translation.vector.amax();
    if farthest > MAX_TARGET_COORDINATE {
        return Err(bad_input!(
            "a coordinate of the target position is {farthest:e} m; targets beyond ±{MAX_TARGET_COORDINATE} m are refused (no arm reaches them; are the units metres?)"
        ));
    }
    Ok(pose)
}

/// `mid`, `zero` or comma-separated joint values, checked against the chain.
fn parse_start(text: &str, chain: &Chain) -> Result<Vec<f64>> {
    let q_start = match text.trim() {
        "mid" => chain.mid_configuration(),
        "zero" => vec![0.0; chain.dof()],
        values => values
            .split(',')
            .map(|v| {
                v.trim()
                    .parse::<f64>()
                    .map_err(|_| bad_input!("'{}' is not a number", v.trim()))
            })
            .collect::<Result<Vec<f64>>>()?,
    };
    if q_start.len() != chain.dof() {
        return Err(bad_input!(
            "expected 'mid', 'zero' or {} comma-separated values for the chain '{}', got {} values",
            chain.dof(),
            chain.name(),
            q_start.len()
        ));
    }
    if let Some(index) = q_start.iter().position(|v| !v.is_finite()) {
        return Err(bad_input!("value {} is not a finite number", index + 1));
    }
    Ok(q_start)
}
