//! The one error type of tasks: the task (its file or name), the field's path in the task-file
//! schema, and what is wrong.

/// An error in a task: the file (or the name given to the builder), the field's path (empty for
/// the whole document) and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {}{message}", field_prefix(.field))]
pub struct TaskError {
    /// The task file, or the task's name.
    pub file: String,
    /// The field's path, e.g. `object.pose.xyz`.
    pub field: String,
    /// What is wrong.
    pub message: String,
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
        }
    }
}
