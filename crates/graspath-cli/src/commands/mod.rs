//! One module per subcommand.

pub mod demo;
pub mod export_mjcf;
pub mod generate;
pub mod ik;
pub mod kinematics;
pub mod map;
pub mod select;
pub mod train;

use graspath::fsutil::{check_not_an_input, OutputError};
use graspath::task::{Task, TaskFile};
use std::path::{Path, PathBuf};

/// Refuses an `--out` that is or holds the task file or a file or folder the task reads
/// (`--force` would delete it).
pub fn check_out_spares_task_inputs(
    out: &Path,
    task_path: &Path,
    file: &TaskFile,
) -> Result<(), OutputError> {
    let base_dir = task_path.parent().unwrap_or(Path::new(""));
    let mut inputs = vec![task_path.to_path_buf()];
    inputs.extend(file.input_paths().into_iter().map(|p| base_dir.join(p)));
    check_not_an_input(out, &inputs)
}

/// Refuses an `--out` that is or holds one of `inputs`.
pub fn check_out_spares(out: &Path, inputs: &[&Path]) -> Result<(), OutputError> {
    let inputs: Vec<PathBuf> = inputs.iter().map(|p| p.to_path_buf()).collect();
    check_not_an_input(out, &inputs)
}

/// Prints the task's plausibility warnings (values that are probably mistakes) to stderr, one
/// line each: `graspath: warning: TASK: FIELD: MESSAGE`.
pub fn print_warnings(title: &str, task: &Task) {
    for warning in task.warnings() {
        eprintln!("graspath: warning: {title}: {warning}");
    }
}
