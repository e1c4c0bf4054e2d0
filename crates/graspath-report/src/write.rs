//! Atomic file output: everything is rendered first, then each file is written to a temporary
//! name in the target folder and renamed into place.

use std::path::{Path, PathBuf};

/// Writing the report failed.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct ReportError {
    /// The file or folder.
    pub path: String,
    /// What went wrong.
    pub message: String,
}

/// Writes `(name, bytes)` files into `dir` (created if missing). Each file appears whole or not
/// at all; on an error the temporary files are removed.
pub fn write_files_atomically(
    dir: &Path,
    files: &[(String, Vec<u8>)],
) -> Result<Vec<PathBuf>, ReportError> {
    let fail = |path: &Path, e: std::io::Error| ReportError {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    std::fs::create_dir_all(dir).map_err(|e| fail(dir, e))?;
    let mut temporary = Vec::new();
    for (name, bytes) in files {
        let final_path = dir.join(name);
        let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
        if let Err(e) = std::fs::write(&tmp, bytes) {
            for (t, _) in &temporary {
                let _ = std::fs::remove_file(t);
            }
            let _ = std::fs::remove_file(&tmp);
            return Err(fail(&tmp, e));
        }
        temporary.push((tmp, final_path));
    }
    let mut written = Vec::new();
    for (tmp, final_path) in temporary {
        std::fs::rename(&tmp, &final_path).map_err(|e| fail(&final_path, e))?;
        written.push(final_path);
    }
    Ok(written)
}
