//! Errors of reading, writing and sampling clouds. Each names the file (or input) and the
//! field, line or element at fault.

/// An error from point cloud input, output or sampling.
#[derive(Debug, thiserror::Error)]
pub enum CloudError {
    /// The file could not be read or written.
    #[error("{source_name}: {message}")]
    Io {
        /// The file.
        source_name: String,
        /// The operating system's message.
        message: String,
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

    pub(crate) fn io(source_name: &str, error: impl std::fmt::Display) -> Self {
        Self::Io {
            source_name: source_name.to_string(),
            message: error.to_string(),
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
