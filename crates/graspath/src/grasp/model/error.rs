//! Errors of training, model files and generation; each names the file and the field.

use crate::cloud::CloudError;
use crate::fault::{Classify, ErrorKind};
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
    /// A file could not be read; the operating system's error is the source.
    #[error("{source_name}")]
    Io {
        /// The file.
        source_name: String,
        /// The operating system's error (or the size cap's, [`crate::input::read`]).
        #[source]
        source: std::io::Error,
    },
    /// A file could not be written.
    #[error(transparent)]
    Output(#[from] crate::output_files::OutputError),
    /// A model or candidate file could not be encoded as JSON (not caused by the input).
    #[error("{what}")]
    Encode {
        /// What was encoded: `<model>` or `<candidates>`.
        what: &'static str,
        /// The encoder's error.
        #[source]
        source: serde_json::Error,
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
    #[error("{source_name}: field 'format_version': the file has version {found}, this graspath reads versions 1 to {expected}; retrain the model")]
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
    /// Reads a whole text file (at most [`crate::input::MAX_MODEL_FILE_BYTES`]); the error
    /// names it.
    pub(crate) fn read_text(path: &std::path::Path) -> Result<String, Self> {
        crate::input::read_to_string(path, crate::input::MAX_MODEL_FILE_BYTES).map_err(|source| {
            Self::Io {
                source_name: path.display().to_string(),
                source,
            }
        })
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

impl Classify for ModelError {
    /// A file that cannot be read has its source's kind, a cloud or hand error its own; an
    /// encoder's failure is [`ErrorKind::Internal`]; everything else is [`ErrorKind::Content`].
    fn kind(&self) -> Option<ErrorKind> {
        match self {
            Self::Io { .. } => None,
            Self::Output(e) => e.kind(),
            Self::Cloud(e) => e.kind(),
            Self::Hand(e) => e.kind(),
            Self::Encode { .. } => Some(ErrorKind::Internal),
            Self::Field { .. } | Self::Version { .. } | Self::NoContact { .. } => {
                Some(ErrorKind::Content)
            }
        }
    }

    fn file(&self) -> Option<&str> {
        match self {
            Self::Io { source_name, .. }
            | Self::Field { source_name, .. }
            | Self::Version { source_name, .. }
            | Self::NoContact { source_name, .. } => Some(source_name),
            Self::Output(e) => e.file(),
            Self::Cloud(e) => e.file(),
            Self::Hand(e) => e.file(),
            Self::Encode { .. } => None,
        }
    }

    fn field(&self) -> Option<&str> {
        match self {
            Self::Field { field, .. } => Some(field),
            Self::Version { .. } => Some("format_version"),
            Self::Cloud(e) => e.field(),
            Self::Hand(e) => e.field(),
            _ => None,
        }
    }
}
