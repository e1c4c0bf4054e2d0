//! One module per subcommand.

pub(crate) mod demo;
pub(crate) mod export_mjcf;
pub(crate) mod generate;
pub(crate) mod ik;
pub(crate) mod kinematics;
pub(crate) mod map;
pub(crate) mod select;
pub(crate) mod train;

use graspath::output_files::{check_not_an_input, OutputError};
use graspath::task::{Task, TaskFile};
use std::path::{Path, PathBuf};

/// Refuses an `--out` that is or holds the task file or a file or folder the task reads
/// (`--force` would delete it).
pub(crate) fn check_out_spares_task_inputs(
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
pub(crate) fn check_out_spares(out: &Path, inputs: &[&Path]) -> Result<(), OutputError> {
    let inputs: Vec<PathBuf> = inputs.iter().map(|p| p.to_path_buf()).collect();
    check_not_an_input(out, &inputs)
}

/// Prints the task's plausibility warnings (values that are probably mistakes) to stderr, one
/// line each: `graspath: warning: TASK: FIELD: MESSAGE`.
pub(crate) fn print_warnings(title: &str, task: &Task) {
    for warning in task.warnings() {
        eprintln!("graspath: warning: {title}: {warning}");
    }
}
