//! The one error type of tasks: the task (its file or name), the field's path in the task-file
//! schema, what is wrong, and — when another part of graspath found the problem (a URDF that
//! does not load, a candidate file, a cloud) or the task file cannot be read — that error, kept
//! as its source.

use crate::fault::{Classify, ErrorKind};
use std::error::Error;
use std::fmt;
use std::sync::Arc;

/// An error in a task: the file (or the name given to the builder), the field's path (empty for
/// the whole document), what is wrong, and the underlying error when there is one
/// ([`TaskError::cause`]), which is its [`source`](std::error::Error::source): the message does
/// not repeat it, an error chain printed in full (`{:#}` of `anyhow`, [`crate::fault::Chain`]) says
/// it once.
#[derive(Debug, Clone)]
pub struct TaskError {
    /// The task file, or the task's name.
    pub file: String,
    /// The field's path, e.g. `object.pose.xyz`.
    pub field: String,
    /// What is wrong; empty when the cause says it all.
    pub message: String,
    /// The error that caused this one (a robot, candidate, model or cloud error, or the
    /// operating system's when the task file cannot be read), for programs that want its type
    /// (`cause.downcast_ref::<RobotError>()`).
    pub cause: Option<Arc<dyn Error + Send + Sync + 'static>>,
}

impl fmt::Display for TaskError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if !(self.field.is_empty() || self.field == ".") {
            write!(f, ": field '{}'", self.field)?;
        }
        if !self.message.is_empty() {
            write!(f, ": {}", self.message)?;
        }
        Ok(())
    }
}

impl Error for TaskError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        self.cause.as_deref().map(|e| e as &(dyn Error + 'static))
    }
}

impl PartialEq for TaskError {
    /// Equal when the file, field, message and the cause's message are.
    fn eq(&self, other: &Self) -> bool {
        let cause = |e: &Self| {
            e.cause
                .as_ref()
                .map(|c| crate::fault::Chain(&**c).to_string())
        };
        (&self.file, &self.field, &self.message) == (&other.file, &other.field, &other.message)
            && cause(self) == cause(other)
    }
}

impl TaskError {
    /// An error about `field` of `file`.
    pub fn new(
        file: impl Into<String>,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Self {
            file: file.into(),
            field: field.into(),
            message: message.into(),
            cause: None,
        }
    }

    /// An error about `field` of `file` caused by `source`, which says what is wrong.
    pub fn caused_by(
        file: impl Into<String>,
        field: impl Into<String>,
        source: impl Error + Send + Sync + 'static,
    ) -> Self {
        Self::with_source(file, field, "", source)
    }

    /// An error about `field` of `file`: `message`, caused by `source`.
    pub fn with_source(
        file: impl Into<String>,
        field: impl Into<String>,
        message: impl Into<String>,
        source: impl Error + Send + Sync + 'static,
    ) -> Self {
        Self {
            file: file.into(),
            field: field.into(),
            message: message.into(),
            cause: Some(Arc::new(source)),
        }
    }
}

impl Classify for TaskError {
    /// With a cause, the cause's kind; a field under `limits.` is [`ErrorKind::Limit`];
    /// everything else is [`ErrorKind::Content`].
    fn kind(&self) -> Option<ErrorKind> {
        if self.cause.is_some() {
            None
        } else if self.field.starts_with("limits.") {
            Some(ErrorKind::Limit)
        } else {
            Some(ErrorKind::Content)
        }
    }

    fn file(&self) -> Option<&str> {
        Some(&self.file)
    }

    fn field(&self) -> Option<&str> {
        (!(self.field.is_empty() || self.field == ".")).then_some(self.field.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cause_is_kept_and_said_once() {
        let cause = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let err = TaskError::caused_by("t.yaml", "candidates.file", cause);
        assert_eq!(err.to_string(), "t.yaml: field 'candidates.file'");
        // The whole chain, as an application prints it, names the cause once.
        let chain = crate::fault::Chain(&err).to_string();
        assert_eq!(chain, "t.yaml: field 'candidates.file': no such file");
        let kept = err.cause.as_ref().expect("the cause is kept");
        assert!(kept.downcast_ref::<std::io::Error>().is_some());
        let read =
            TaskError::with_source("t.yaml", "", "cannot read", std::io::Error::other("disk"));
        assert_eq!(
            crate::fault::Chain(&read).to_string(),
            "t.yaml: cannot read: disk"
        );
    }
}
