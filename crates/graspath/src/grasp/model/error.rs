//! Errors of training, model files and generation; each names the file and the field.

use crate::cloud::CloudError;
use crate::grasp::hand::HandError;

/// One hand link's nearest approach to the demonstration cloud, for the no-contact error.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkClearance {
    /// The link.
    pub link: String,
    /// Points accepted as contacts.
    pub accepted: usize,
    /// The smallest signed distance from a cloud point to the link (m; negative = inside).
    pub closest: f64,
}

fn clearance_text(links: &[LinkClearance]) -> String {
    links
        .iter()
        .map(|l| {
            format!(
                "'{}' ({} points accepted, closest {:.1} mm)",
                l.link,
                l.accepted,
                l.closest * 1000.0
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// An error from the grasp model.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// A file could not be read or written.
    #[error("{source_name}: {message}")]
    Io {
        /// The file.
        source_name: String,
        /// The operating system's message.
        message: String,
    },
    /// A file is malformed or a field has a bad value.
    #[error("{source_name}: field '{field}': {message}")]
    Field {
        /// The file.
        source_name: String,
        /// The field (JSON path or name).
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A model file of another format version.
    #[error("{source_name}: field 'format_version': the file has version {found}, this graspath reads versions 1 to {expected}; retrain the model with `graspath train`")]
    Version {
        /// The file.
        source_name: String,
        /// The version found.
        found: String,
        /// The newest version supported (every earlier one is read too).
        expected: u32,
    },
    /// A cloud problem.
    #[error(transparent)]
    Cloud(#[from] CloudError),
    /// A hand problem.
    #[error(transparent)]
    Hand(#[from] HandError),
    /// No hand link touches the object in the demonstrated grasp.
    #[error("{source_name}: no hand link is in contact with the object at the grasp (the last waypoint): a link needs {min_points} cloud points within {threshold_mm:.1} mm; links: {}", clearance_text(.links))]
    NoContact {
        /// The demonstration file.
        source_name: String,
        /// Per link: accepted points and closest distance.
        links: Vec<LinkClearance>,
        /// The contact distance δ (mm).
        threshold_mm: f64,
        /// The minimum number of points.
        min_points: usize,
    },
}

impl ModelError {
    /// A read or write failure of `source_name`.
    pub(crate) fn io(source_name: impl Into<String>, e: impl std::fmt::Display) -> Self {
        Self::Io {
            source_name: source_name.into(),
            message: e.to_string(),
        }
    }

    /// Reads a whole text file (at most [`crate::input::MAX_MODEL_FILE_BYTES`]); the error
    /// names it.
    pub(crate) fn read_text(path: &std::path::Path) -> Result<String, Self> {
        crate::input::read_to_string(path, crate::input::MAX_MODEL_FILE_BYTES)
            .map_err(|e| Self::io(path.display().to_string(), e))
    }

    pub(crate) fn field(
        source_name: &str,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Self::Field {
            source_name: source_name.to_string(),
            field: field.into(),
            message: message.into(),
        }
    }
}
