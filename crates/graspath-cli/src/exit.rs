//! Exit codes, and the classification of errors into them by their type (never by their text).

use graspath::cloud::CloudError;
use graspath::fsutil::OutputError;
use graspath::geometry::PoseError;
use graspath::grasp::hand::HandError;
use graspath::grasp::model::ModelError;
use graspath::grasp::CandidateError;
use graspath::robot::RobotError;
use graspath::task::TaskError;

/// Success.
pub const SUCCESS: u8 = 0;
/// An internal error: an I/O failure while writing output, or anything unexpected.
pub const INTERNAL: u8 = 1;
/// Bad input: usage (clap's own code), unreadable or invalid files and fields, a refused
/// `--out`.
pub const BAD_INPUT: u8 = 2;
/// `select` selected nothing (no feasible candidate, or no valid pair); the results are
/// written all the same. `--allow-empty` turns it into [`SUCCESS`].
pub const NOTHING_SELECTED: u8 = 3;

/// The table printed by `--help` and in the README.
pub const TABLE: &str = "\
Exit codes:
  0  success
  1  internal error: writing the output failed (I/O), or anything unexpected
  2  bad input: usage, an unreadable or invalid file or field, a refused --out
     (a symbolic link, a device, an existing file or non-empty folder without --force)
  3  select: nothing selected (no feasible candidate; with two arms, no valid pair);
     the results are written all the same; --allow-empty exits 0 instead
  130, 143, 129  stopped by SIGINT (Ctrl-C), SIGTERM or SIGHUP: the run's temporary
     output is removed and nothing is written";

/// Input given on the command line or read from a file or stdin cannot be used. The message
/// names the argument, file, line or field.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct BadInput(pub String);

/// `Err(BadInput(format!(...)))` as an `anyhow::Error`, to return with `?` or `return Err(..)`.
#[macro_export]
macro_rules! bad_input {
    ($($arg:tt)*) => {
        anyhow::Error::new($crate::exit::BadInput(format!($($arg)*)))
    };
}

/// The exit code of a failed run: the first error in the chain (outermost first) whose type
/// says what it is; [`INTERNAL`] when none does.
pub fn code_of(error: &anyhow::Error) -> u8 {
    for cause in error.chain() {
        if let Some(output) = cause.downcast_ref::<OutputError>() {
            return if output.is_refusal() {
                BAD_INPUT
            } else {
                INTERNAL
            };
        }
        if cause.is::<BadInput>()
            || cause.is::<TaskError>()
            || cause.is::<CandidateError>()
            || cause.is::<ModelError>()
            || cause.is::<CloudError>()
            || cause.is::<HandError>()
            || cause.is::<RobotError>()
            || cause.is::<PoseError>()
        {
            return BAD_INPUT;
        }
    }
    INTERNAL
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    #[test]
    fn errors_are_classified_by_type_through_their_context() {
        let input: anyhow::Result<()> = Err(bad_input!("--start: 'x' is not a number"));
        assert_eq!(code_of(&input.context("outer").unwrap_err()), BAD_INPUT);
        let task = TaskError::new("t.yaml", "arms", "unknown arm");
        assert_eq!(code_of(&anyhow::Error::new(task)), BAD_INPUT);
        let io = std::io::Error::other("disk full");
        assert_eq!(code_of(&anyhow::Error::new(io)), INTERNAL);
        let refused = graspath::fsutil::write_file(
            std::path::Path::new("/dev/null"),
            b"",
            graspath::fsutil::Existing::Replace,
        )
        .unwrap_err();
        assert_eq!(code_of(&anyhow::Error::new(refused)), BAD_INPUT);
        assert_eq!(code_of(&anyhow::anyhow!("unexpected")), INTERNAL);
    }
}
