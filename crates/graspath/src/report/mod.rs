//! Reports of a selection: JSON of every candidate with every score, the ranked pairs and a
//! summary, written atomically (no partial output on error).

mod json;
mod write;

pub use json::{candidates_json, pairs_json, summary_json};
pub use write::{write_files_atomically, ReportError};
