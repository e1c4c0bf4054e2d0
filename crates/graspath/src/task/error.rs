//! The one error type of tasks: the task (its file or name), the field's path in the task-file
//! schema, what is wrong, and — when another part of graspath found the problem (a URDF that
//! does not load, a candidate file, a cloud) — that error, kept as its cause.

use std::error::Error;
use std::sync::Arc;

/// An error in a task: the file (or the name given to the builder), the field's path (empty for
/// the whole document), what is wrong, and the underlying error when there is one
/// ([`TaskError::cause`]). The message already holds the cause's text, so the cause is not
/// also reported as [`std::error::Error::source`]: an error chain printed in full says it once.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{file}: {}{message}", field_prefix(.field))]
pub struct TaskError {
    /// The task file, or the task's name.
    pub file: String,
    /// The field's path, e.g. `object.pose.xyz`.
    pub field: String,
    /// What is wrong.
    pub message: String,
    /// The error that caused this one (a robot, candidate, model or cloud error), for programs
    /// that want its type (`cause.downcast_ref::<RobotError>()`).
    pub cause: Option<Arc<dyn Error + Send + Sync + 'static>>,
}

impl PartialEq for TaskError {
    /// Equal when the file, field and message are; the causes are not compared.
    fn eq(&self, other: &Self) -> bool {
        (&self.file, &self.field, &self.message) == (&other.file, &other.field, &other.message)
    }
}

fn field_prefix(field: &str) -> String {
    if field.is_empty() || field == "." {
        String::new()
    } else {
        format!("field '{field}': ")
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

    /// An error about `field` of `file` caused by `source`; the message is the source's.
    pub fn caused_by(
        file: impl Into<String>,
        field: impl Into<String>,
        source: impl Error + Send + Sync + 'static,
    ) -> Self {
        Self {
            file: file.into(),
            field: field.into(),
            message: source.to_string(),
            cause: Some(Arc::new(source)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cause_is_kept_and_said_once() {
        let cause = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let err = TaskError::caused_by("t.yaml", "candidates.file", cause);
        assert_eq!(
            err.to_string(),
            "t.yaml: field 'candidates.file': no such file"
        );
        // The whole chain, as an application prints it, names the cause once.
        let mut chain = vec![err.to_string()];
        let mut next = Error::source(&err);
        while let Some(e) = next {
            chain.push(e.to_string());
            next = e.source();
        }
        assert_eq!(chain.join(": ").matches("no such file").count(), 1);
        let kept = err.cause.as_ref().expect("the cause is kept");
        assert!(kept.downcast_ref::<std::io::Error>().is_some());
    }
}
