//! `graspath export-mjcf`: the task's world (arms, gripper, object, table, obstacles) as an
//! MJCF model for MuJoCo (see `docs/simulation.md`).

use anyhow::{Context, Result};
use clap::Args;
use graspath::output_files::{write_file, Existing};
use graspath::physics::{world_mjcf, WorldOptions};
use graspath::task::{Task, TaskFile};
use std::path::PathBuf;

/// Writes the task's world as one MJCF file, and prints what the model approximates.
#[derive(Debug, Args)]
pub(crate) struct ExportMjcfArgs {
    /// The task file (YAML or JSON).
    task: PathBuf,
    /// The MJCF file to write.
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
    /// Replace an existing file.
    #[arg(long)]
    force: bool,
    /// Simulation time step (s).
    #[arg(long, value_name = "S", default_value_t = WorldOptions::default().timestep)]
    timestep: f64,
    /// Sliding friction of the fingers and the object.
    #[arg(long, value_name = "MU", default_value_t = WorldOptions::default().friction)]
    friction: f64,
    /// Largest force of each finger (N).
    #[arg(long, value_name = "N", default_value_t = WorldOptions::default().grip_force)]
    grip_force: f64,
    /// The object's density when the task gives no mass (kg/m³).
    #[arg(long, value_name = "KG_M3", default_value_t = WorldOptions::default().object_density)]
    object_density: f64,
    /// Carry the arms' own weight outside the motors (MuJoCo `gravcomp`): a gravity-assist
    /// spring or counterbalance, such as Baxter's shoulder spring.
    #[arg(long)]
    arm_gravity_compensation: bool,
}

/// Runs `graspath export-mjcf`.
pub(crate) fn run(args: &ExportMjcfArgs) -> Result<()> {
    let existing = Existing::replace_if(args.force);
    let file = TaskFile::load(&args.task).context("cannot use the task file")?;
    super::check_out_spares_task_inputs(&args.out, &args.task, &file)?;
    let title = args.task.display().to_string();
    let base_dir = args.task.parent().map(PathBuf::from).unwrap_or_default();
    let task = Task::from_file(&file, &title, &base_dir).context("cannot use the task file")?;
    super::print_warnings(&title, &task);
    let options = WorldOptions {
        timestep: args.timestep,
        friction: args.friction,
        grip_force: args.grip_force,
        object_density: args.object_density,
        arm_gravity_compensation: args.arm_gravity_compensation,
        ..WorldOptions::default()
    };
    let world = world_mjcf(&task, &options).map_err(|e| crate::bad_input!("{title}: {e}"))?;
    write_file(&args.out, world.xml.as_bytes(), existing)?;
    for note in &world.notes {
        eprintln!("graspath: note: {note}");
    }
    eprintln!("graspath: wrote {}", args.out.display());
    Ok(())
}
