//! Errors of reading, writing and sampling clouds. Each names the file (or input) and the
//! field, line or element at fault.

use crate::fault::{Classify, ErrorKind};

/// An error from point cloud input, output or sampling.
#[derive(Debug, thiserror::Error)]
pub enum CloudError {
    /// The file could not be read; the operating system's error is the source.
    #[error("{source_name}")]
    Io {
        /// The file.
        source_name: String,
        /// The operating system's error (or the size cap's, [`crate::input::read`]).
        #[source]
        source: std::io::Error,
    },
    /// The file could not be written.
    #[error(transparent)]
    Output(#[from] crate::output_files::OutputError),
    /// A writer failed to encode the cloud in memory (not caused by the input).
    #[error("{what}")]
    Encode {
        /// The writer, e.g. `<ply writer>`.
        what: &'static str,
        /// The writer's error.
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// The file is malformed.
    #[error("{source_name}: {location}: {message}")]
    Parse {
        /// The file.
        source_name: String,
        /// Where: a line, a header keyword, an element or a field.
        location: String,
        /// What is wrong.
        message: String,
    },
    /// A required field (property) is missing.
    #[error("{source_name}: no field '{field}' (fields present: {present})")]
    MissingField {
        /// The file.
        source_name: String,
        /// The missing field, e.g. `x` or `normal_x`.
        field: String,
        /// The fields the file has, comma-separated.
        present: String,
    },
    /// The cloud has no point.
    #[error("{source_name}: the cloud has no points")]
    Empty {
        /// The file.
        source_name: String,
    },
    /// Every point has a NaN or infinite coordinate.
    #[error("{source_name}: all {count} points have NaN or infinite coordinates")]
    AllInvalid {
        /// The file.
        source_name: String,
        /// How many points were read.
        count: usize,
    },
    /// The file extension is not one of the supported formats.
    #[error("{source_name}: unknown format (expected .{expected})")]
    UnknownFormat {
        /// The file.
        source_name: String,
        /// The supported extensions.
        expected: String,
    },
    /// A count in a file or an option exceeds a documented limit.
    #[error("{source_name}: {field}: {count} exceeds the limit of {limit}")]
    TooLarge {
        /// The file (or input).
        source_name: String,
        /// The header keyword, element or option holding the count.
        field: String,
        /// The count found.
        count: u64,
        /// The limit ([`super::MAX_CLOUD_POINTS`] or [`super::MAX_MESH_TRIANGLES`]).
        limit: usize,
    },
    /// An outlier-removal option is invalid (see [`super::OutlierOptions`]).
    #[error("outlier removal: {field}: {message}")]
    BadFilter {
        /// The option, e.g. `max_range` or `statistical.neighbours`.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// Outlier removal left no point.
    #[error("{source_name}: no point is left after outlier removal ({report})")]
    AllFiltered {
        /// The file.
        source_name: String,
        /// What each step removed.
        report: super::CloudReport,
    },
    /// A primitive or sampling option is invalid.
    #[error("{field}: {message}")]
    BadOption {
        /// The option, e.g. `box.size` or `points`.
        field: String,
        /// What is wrong.
        message: String,
    },
}

impl CloudError {
    /// The error with a file named: a [`CloudError::BadOption`] (which names only the option)
    /// becomes a [`CloudError::Parse`] at `source_name`, field `prefix` + the option. Other
    /// errors already name their file and are returned unchanged.
    pub fn in_file(self, source_name: &str, prefix: &str) -> Self {
        match self {
            Self::BadOption { field, message } => Self::Parse {
                source_name: source_name.to_string(),
                location: format!("{prefix}{field}"),
                message,
            },
            other => other,
        }
    }

    pub(crate) fn io(source_name: &str, source: std::io::Error) -> Self {
        Self::Io {
            source_name: source_name.to_string(),
            source,
        }
    }

    pub(crate) fn parse(
        source_name: &str,
        location: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Self::Parse {
            source_name: source_name.to_string(),
            location: location.into(),
            message: message.into(),
        }
    }
}

impl Classify for CloudError {
    /// A file that cannot be read has its source's kind; a count over a limit is
    /// [`ErrorKind::Limit`]; a writer's failure is [`ErrorKind::Internal`]; everything else is
    /// [`ErrorKind::Content`].
    fn kind(&self) -> Option<ErrorKind> {
        match self {
            Self::Io { .. } => None,
            Self::Output(e) => e.kind(),
            Self::Encode { .. } => Some(ErrorKind::Internal),
            Self::TooLarge { .. } => Some(ErrorKind::Limit),
            _ => Some(ErrorKind::Content),
        }
    }

    fn file(&self) -> Option<&str> {
        match self {
            Self::Io { source_name, .. }
            | Self::Parse { source_name, .. }
            | Self::MissingField { source_name, .. }
            | Self::Empty { source_name }
            | Self::AllInvalid { source_name, .. }
            | Self::UnknownFormat { source_name, .. }
            | Self::TooLarge { source_name, .. }
            | Self::AllFiltered { source_name, .. } => Some(source_name),
            Self::Output(e) => e.file(),
            Self::Encode { .. } | Self::BadFilter { .. } | Self::BadOption { .. } => None,
        }
    }

    fn field(&self) -> Option<&str> {
        match self {
            Self::Parse { location, .. } => Some(location),
            Self::MissingField { field, .. }
            | Self::TooLarge { field, .. }
            | Self::BadFilter { field, .. }
            | Self::BadOption { field, .. } => Some(field),
            _ => None,
        }
    }
}
