//! `graspath kinematics`: forward kinematics, the Jacobian and manipulability indices for each
//! input configuration.

use crate::jsonl::{for_each_line, open_input, source_name};
use crate::robot_args::RobotArgs;
use anyhow::Result;
use clap::Args;
use graspath::geometry::pose_to_rows;
use graspath::manipulability::{inverse_condition, yoshikawa, JacobianPart};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::PathBuf;

/// Reads JSON Lines `{"q":[...]}` (rad / m) and writes one JSON line per input.
#[derive(Debug, Args)]
pub(crate) struct KinematicsArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// Read from this file instead of stdin.
    #[arg(long, value_name = "FILE")]
    input: Option<PathBuf>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Input {
    q: Vec<f64>,
}

#[derive(Debug, Serialize)]
struct Output {
    /// `base_from_tip`, 4×4 row-major.
    pose: [[f64; 4]; 4],
    /// 6×n row-major, rows `[v; ω]` in the base frame.
    jacobian: Vec<Vec<f64>>,
    yoshikawa: f64,
    yoshikawa_translation: f64,
    inverse_condition: f64,
    within_limits: bool,
}

/// Runs the subcommand.
pub(crate) fn run(args: &KinematicsArgs) -> Result<()> {
    let chain = args.robot.load()?;
    let source = source_name(args.input.as_deref());
    let input = open_input(args.input.as_deref())?;
    // Everything is computed before anything is printed: an error leaves no partial output.
    let mut out: Vec<u8> = Vec::new();
    let mut jacobian = nalgebra::Matrix6xX::zeros(chain.dof());
    for_each_line(input, &source, |_, line: Input| {
        let pose = chain.pose_and_jacobian_into(&line.q, &mut jacobian)?;
        let output = Output {
            pose: pose_to_rows(&nalgebra::convert(pose)),
            jacobian: (0..6)
                .map(|r| jacobian.row(r).iter().copied().collect())
                .collect(),
            yoshikawa: yoshikawa(&jacobian, JacobianPart::Full),
            yoshikawa_translation: yoshikawa(&jacobian, JacobianPart::Translation),
            inverse_condition: inverse_condition(&jacobian, JacobianPart::Full),
            within_limits: chain.within_limits(&line.q),
        };
        serde_json::to_writer(&mut out, &output)?;
        out.write_all(b"\n")?;
        Ok(())
    })?;
    crate::output::write_result_to_stdout(&out)
}
