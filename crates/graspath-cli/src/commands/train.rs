//! `graspath train`: learn a one-shot grasp model from a demonstration file.

use anyhow::Result;
use clap::Args;
use graspath::grasp::model::train_file;
use graspath::output_files::{check_file_target, write_file, Existing};
use std::path::PathBuf;

/// Learns a grasp model (contact models per link in contact, hand-configuration model) from
/// one demonstration and writes it as a versioned JSON model file.
#[derive(Debug, Args)]
pub(crate) struct TrainArgs {
    /// The demonstration JSON (hand, object cloud, waypoints from pre-grasp to grasp).
    demonstration: PathBuf,
    /// Where to write the model file (a new file, or any existing regular file with --force).
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
    /// Replace an existing --out file (atomically). Symbolic links and devices are refused
    /// even so.
    #[arg(long)]
    force: bool,
    /// Print nothing on success.
    #[arg(long)]
    quiet: bool,
}

/// Runs the subcommand.
pub(crate) fn run(args: &TrainArgs) -> Result<()> {
    let existing = Existing::replace_if(args.force);
    check_file_target(&args.out, existing)?;
    super::check_out_spares(&args.out, &[&args.demonstration])?;
    let model = train_file(&args.demonstration)?;
    write_file(&args.out, &model.to_json()?, existing)?;
    if !args.quiet {
        let links: Vec<String> = model
            .contact_links()
            .map(|(link, points)| format!("{link} ({points} contact points)"))
            .collect();
        println!(
            "trained '{}' for hand '{}': links in contact: {}; wrote {}",
            model.label,
            model.hand.name,
            links.join(", "),
            args.out.display()
        );
    }
    Ok(())
}
