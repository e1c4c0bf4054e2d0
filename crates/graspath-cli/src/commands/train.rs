//! `graspath train`: learn a one-shot grasp model from a demonstration file.

use anyhow::Result;
use clap::Args;
use graspath::grasp::model::train_file;
use std::path::PathBuf;

/// Learns a grasp model (contact models per link in contact, hand-configuration model) from
/// one demonstration and writes it as a versioned JSON model file.
#[derive(Debug, Args)]
pub struct TrainArgs {
    /// The demonstration JSON (hand, object cloud, waypoints from pre-grasp to grasp).
    demonstration: PathBuf,
    /// Where to write the model file.
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
    /// Print nothing on success.
    #[arg(long)]
    quiet: bool,
}

/// Runs the subcommand.
pub fn run(args: &TrainArgs) -> Result<()> {
    let model = train_file(&args.demonstration)?;
    model.write(&args.out)?;
    if !args.quiet {
        let links: Vec<String> = model
            .contacts
            .iter()
            .map(|c| format!("{} ({} contact points)", c.link, c.samples.len()))
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
