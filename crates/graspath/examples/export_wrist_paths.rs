//! Writes the wrist poses a task asks an arm to follow, for a peer implementation to be given
//! exactly the inputs `graspath select` works from (`examples/peers/faces_tracik.py`).
//!
//! ```text
//! cargo run --release -p graspath --example export_wrist_paths -- TASK OUT.npy [ARM]
//! ```
//!
//! `OUT.npy` is a NumPy array of float64, shape `(candidates, samples, 4, 4)`: entry `[c, i]`
//! is `base_from_wrist` (homogeneous, row-major) of candidate `c` (the task's candidate order,
//! the `id` in `candidates.json`) at path sample `i`, in the chain's base frame — the IK targets
//! of `graspath select` (`graspath::select::wrist_trajectory`). `ARM` defaults to the task's
//! first arm.

use graspath::select::wrist_trajectory;
use graspath::task::Task;
use std::io::{BufWriter, Write};
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let ([task_path, out] | [task_path, out, _]) = args.as_slice() else {
        return Err("usage: export_wrist_paths TASK OUT.npy [ARM]".into());
    };
    let task = Task::load(Path::new(task_path))?;
    let arm = match args.get(2) {
        Some(name) => task
            .arms()
            .iter()
            .find(|a| &a.name == name)
            .ok_or_else(|| format!("the task has no arm '{name}'"))?,
        None => &task.arms()[0],
    };
    let samples = task.path().samples.len();
    let mut file = BufWriter::new(std::fs::File::create(out)?);
    write_npy_header(&mut file, &[task.candidate_count(), samples, 4, 4])?;
    for candidate in task.candidates().held().expect("held candidates") {
        let wrists = wrist_trajectory(
            task.path(),
            &arm.world_from_base,
            &candidate.object_from_wrist,
        );
        for base_from_wrist in &wrists {
            let m = base_from_wrist.to_homogeneous();
            for r in 0..4 {
                for c in 0..4 {
                    file.write_all(&m[(r, c)].to_le_bytes())?;
                }
            }
        }
    }
    file.flush()?;
    eprintln!(
        "{out}: {} candidates x {samples} samples, arm {}",
        task.candidate_count(),
        arm.name
    );
    Ok(())
}

/// The header of a version 1.0 `.npy` file of little-endian float64 in C order.
fn write_npy_header(out: &mut impl Write, shape: &[usize]) -> std::io::Result<()> {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    let mut dict = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': ({},), }}",
        dims.join(", ")
    );
    // Magic (6) + version (2) + length (2) + dict + '\n', padded with spaces to 64 bytes.
    let unpadded = 10 + dict.len() + 1;
    dict.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    dict.push('\n');
    out.write_all(b"\x93NUMPY\x01\x00")?;
    out.write_all(&(dict.len() as u16).to_le_bytes())?;
    out.write_all(dict.as_bytes())
}
