//! Helpers shared by the integration tests: locating `../shared` (skipped when absent).

#![allow(dead_code)]

use std::path::PathBuf;

/// The shared folder beside the repository, if present.
pub fn shared_dir() -> Option<PathBuf> {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let candidates = [
        std::env::var_os("GRASPATH_SHARED").map(PathBuf::from),
        Some(manifest.join("../../../shared")),
    ];
    candidates
        .into_iter()
        .flatten()
        .find(|p| p.join("robots/baxter.urdf").is_file())
}

/// A file under the shared folder, or `None` (with a message) when the folder is absent.
pub fn shared_file(relative: &str) -> Option<PathBuf> {
    match shared_dir() {
        Some(dir) => Some(dir.join(relative)),
        None => {
            eprintln!("skipped: ../shared is not present (set GRASPATH_SHARED to point at it)");
            None
        }
    }
}
