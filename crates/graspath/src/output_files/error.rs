//! Why output could not be written: [`OutputError`] (the output path and what is wrong with
//! it) and whether the caller's choice or the system is at fault.

use std::path::{Path, PathBuf};

/// Output could not be written: the output path and what is wrong with it. Its
/// [`source`](std::error::Error::source) is the operating system's error when writing failed
/// ([`OutputErrorKind::Io`]).
#[derive(Debug)]
pub struct OutputError {
    /// The output path (the file or folder the caller asked for).
    pub path: PathBuf,
    /// What is wrong.
    pub kind: OutputErrorKind,
}

impl std::fmt::Display for OutputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.kind)
    }
}

impl std::error::Error for OutputError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        std::error::Error::source(&self.kind)
    }
}

/// What went wrong with an output path.
#[derive(Debug, thiserror::Error)]
pub enum OutputErrorKind {
    /// The path is a symbolic link.
    #[error("is a symbolic link (to '{}'); output is never written through or over a link: give the real path", .0.display())]
    Symlink(PathBuf),
    /// The path is a device, FIFO or socket.
    #[error("is a {0}, not a regular file or folder; choose another output path")]
    Special(&'static str),
    /// The path is a file where a folder is wanted, or a folder where a file is wanted.
    #[error("is an existing {found}, but the output is a {wanted}; choose another path")]
    WrongKind {
        /// `file` or `folder`: what is there.
        found: &'static str,
        /// `file` or `folder`: what would be written.
        wanted: &'static str,
    },
    /// A regular file exists and replacing was not allowed.
    #[error("the file exists and replacing it was not allowed; choose another path")]
    FileExists,
    /// A non-empty folder exists and replacing was not allowed.
    #[error("the folder exists and is not empty (it holds '{0}') and replacing it was not allowed; choose another folder")]
    FolderNotEmpty(String),
    /// Replacing this folder would delete the working folder, one of its ancestors or the home
    /// folder.
    #[error("refusing to replace {0}; choose a new folder")]
    Protected(&'static str),
    /// The output path is, or holds, an input of the same run (replacing it would delete it).
    #[error("refusing to replace it: it is or holds {}, an input of this run; choose another output", .0.display())]
    HoldsInput(PathBuf),
    /// A component of the path's parent is a file, not a folder.
    #[error("a parent of this path is a file, not a folder; choose another path")]
    ParentNotFolder,
    /// A name in the set of files is not a plain relative path inside the folder.
    #[error("'{0}' is not a relative file name inside the output folder")]
    BadName(String),
    /// The same name twice in the set of files.
    #[error("'{0}' is given twice in the set of files")]
    DuplicateName(String),
    /// An operating-system error while writing; the error is the source.
    #[error("cannot {action}")]
    Io {
        /// What was being done, naming the file involved.
        action: String,
        /// The operating system's error.
        #[source]
        error: std::io::Error,
    },
    /// Replacing an existing folder failed and the old folder could not be put back either.
    #[error("cannot {action}: {error}; the previous contents are kept in '{}'", aside.display())]
    NotRestored {
        /// What was being done.
        action: String,
        /// The first error.
        error: std::io::Error,
        /// Where the previous contents are.
        aside: PathBuf,
    },
    /// The new folder is in place but the previous contents could not be deleted.
    #[error("the new output is in place, but the previous contents, moved to '{}', could not be deleted: {error}", aside.display())]
    OldNotRemoved {
        /// Where the previous contents are.
        aside: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
}

impl OutputError {
    pub(super) fn new(path: &Path, kind: OutputErrorKind) -> Self {
        Self {
            path: path.to_path_buf(),
            kind,
        }
    }

    pub(super) fn io(path: &Path, action: impl Into<String>, error: std::io::Error) -> Self {
        Self::new(
            path,
            OutputErrorKind::Io {
                action: action.into(),
                error,
            },
        )
    }

    /// True when the output path was refused before anything was written (a symbolic link, a
    /// device, an existing file or folder, a bad name): the caller's choice is at fault. False
    /// for an operating-system failure while writing.
    pub fn is_refusal(&self) -> bool {
        !matches!(
            self.kind,
            OutputErrorKind::Io { .. }
                | OutputErrorKind::NotRestored { .. }
                | OutputErrorKind::OldNotRemoved { .. }
        )
    }
}

impl crate::fault::Classify for OutputError {
    /// A refused path ([`OutputError::is_refusal`]) is [`ErrorKind::File`](crate::fault::ErrorKind):
    /// the caller's choice; a failure while writing is [`ErrorKind::Internal`](crate::fault::ErrorKind).
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        Some(if self.is_refusal() {
            crate::fault::ErrorKind::File
        } else {
            crate::fault::ErrorKind::Internal
        })
    }

    fn file(&self) -> Option<&str> {
        self.path.to_str()
    }
}
