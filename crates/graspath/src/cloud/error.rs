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
