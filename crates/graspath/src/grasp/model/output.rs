//! The candidate file read by the selection command:
//!
//! ```text
//! {"format": "graspath-candidates", "version": 1, "frame": "object",
//!  "candidates": [{"id": 0, "label": "pinch", "object_from_wrist": [[4×4 row-major]],
//!                  "log_likelihood": -12.3, "contact": [x, y, z] | null, "hand_joints": [...]}]}
//! ```
//!
//! Poses in the object (cloud) frame, metres; candidates best first.

use super::{Candidate, ModelError};
use crate::geometry::pose_to_rows;
use serde::Serialize;
use std::path::Path;

/// The `format` string of candidate files.
pub const CANDIDATES_FORMAT: &str = "graspath-candidates";

#[derive(Serialize)]
struct FileOut<'a> {
    format: &'static str,
    version: u32,
    frame: &'static str,
    candidates: Vec<CandidateOut<'a>>,
}

#[derive(Serialize)]
struct CandidateOut<'a> {
    id: usize,
    label: &'a str,
    object_from_wrist: [[f64; 4]; 4],
    log_likelihood: f64,
    contact: Option<[f64; 3]>,
    hand_joints: &'a [f64],
}

/// The candidate file's bytes (pretty-printed JSON, ids in the given order from 0).
pub fn candidates_json(candidates: &[Candidate], label: &str) -> Result<Vec<u8>, ModelError> {
    let file = FileOut {
        format: CANDIDATES_FORMAT,
        version: 1,
        frame: "object",
        candidates: candidates
            .iter()
            .enumerate()
            .map(|(id, c)| CandidateOut {
                id,
                label,
                object_from_wrist: pose_to_rows(&c.object_from_wrist),
                log_likelihood: c.log_likelihood,
                contact: c.contact.map(|p| [p.x, p.y, p.z]),
                hand_joints: &c.hand_joints,
            })
            .collect(),
    };
    let mut bytes = serde_json::to_vec_pretty(&file).map_err(|source| ModelError::Encode {
        what: "<candidates>",
        source,
    })?;
    bytes.push(b'\n');
    Ok(bytes)
}

/// Writes the candidate file atomically.
pub fn write_candidates(
    path: &Path,
    candidates: &[Candidate],
    label: &str,
) -> Result<(), ModelError> {
    let bytes = candidates_json(candidates, label)?;
    crate::output_files::write_file(path, &bytes, crate::output_files::Existing::Replace)?;
    Ok(())
}
