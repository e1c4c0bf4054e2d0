//! Exit codes, derived from the library's classification of errors (never from their text),
//! and the one-line message of a failed run.

use graspath::grasp::model::ModelError;
use graspath::output_files::{OutputError, OutputErrorKind};
use graspath::robot::RobotError;

/// Success.
pub(crate) const SUCCESS: u8 = 0;
/// An internal error: an I/O failure while writing output, or anything unexpected.
pub(crate) const INTERNAL: u8 = 1;
/// Bad input: usage (clap's own code), unreadable or invalid files and fields, a refused
/// `--out`.
pub(crate) const BAD_INPUT: u8 = 2;
/// `select` selected nothing (no feasible candidate, or no valid pair); the results are
/// written all the same. `--allow-empty` turns it into [`SUCCESS`].
pub(crate) const NOTHING_SELECTED: u8 = 3;

/// The table printed by `--help` and in the README.
pub(crate) const TABLE: &str = "\
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
pub(crate) struct BadInput(pub String);

/// `Err(BadInput(format!(...)))` as an `anyhow::Error`, to return with `?` or `return Err(..)`.
#[macro_export]
macro_rules! bad_input {
    ($($arg:tt)*) => {
        anyhow::Error::new($crate::exit::BadInput(format!($($arg)*)))
    };
}

/// The exit code of a failed run: [`BAD_INPUT`] when the CLI's own [`BadInput`] or the
/// library's classification ([`graspath::fault_of`]: an unusable file, bad content, a resource
/// limit) says the input is at fault; [`INTERNAL`] otherwise.
pub(crate) fn code_of(error: &anyhow::Error) -> u8 {
    let bad_input = error.chain().any(<dyn std::error::Error>::is::<BadInput>)
        || graspath::fault_of(error.as_ref()).is_some_and(|fault| fault.kind.is_bad_input());
    if bad_input {
        BAD_INPUT
    } else {
        INTERNAL
    }
}

/// The one-line message of a failed run: each error of the chain, outermost first, joined by
/// `": "`. Where a library error says what to do in the library's terms, the line says it with
/// the command line's flags.
pub(crate) fn message(error: &anyhow::Error) -> String {
    error
        .chain()
        .map(|cause| with_flags(cause).unwrap_or_else(|| cause.to_string()))
        .collect::<Vec<_>>()
        .join(": ")
}

/// The message of a library error that the command line has a flag or command for, in the
/// command line's words; `None` for the others.
fn with_flags(error: &(dyn std::error::Error + 'static)) -> Option<String> {
    if let Some(output) = error.downcast_ref::<OutputError>() {
        let path = output.path.display();
        return match &output.kind {
            OutputErrorKind::FileExists => Some(format!(
                "{path}: the file exists; use --force to replace it, or choose another path"
            )),
            OutputErrorKind::FolderNotEmpty(example) => Some(format!(
                "{path}: the folder exists and is not empty (it holds '{example}'); use --force \
                 to replace it and everything in it, or choose another folder"
            )),
            _ => None,
        };
    }
    if let Some(RobotError::MjcfNotUrdf { source_name }) = error.downcast_ref::<RobotError>() {
        return Some(format!(
            "{source_name}: not a valid URDF: this is a MuJoCo MJCF file (root <mujoco>): give \
             it as `robot: {{mjcf: FILE}}` in a task file or `--mjcf FILE` on the command line"
        ));
    }
    if let Some(version @ ModelError::Version { .. }) = error.downcast_ref::<ModelError>() {
        return Some(format!("{version} with `graspath train`"));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;
    use graspath::output_files::Existing;

    #[test]
    fn errors_are_classified_by_type_through_their_context() {
        let input: anyhow::Result<()> = Err(bad_input!("--start: 'x' is not a number"));
        assert_eq!(code_of(&input.context("outer").unwrap_err()), BAD_INPUT);
        let task = graspath::task::TaskError::new("t.yaml", "arms", "unknown arm");
        assert_eq!(code_of(&anyhow::Error::new(task)), BAD_INPUT);
        let io = std::io::Error::other("disk full");
        assert_eq!(code_of(&anyhow::Error::new(io)), INTERNAL);
        let refused = graspath::output_files::write_file(
            std::path::Path::new("/dev/null"),
            b"",
            Existing::Replace,
        )
        .unwrap_err();
        assert_eq!(code_of(&anyhow::Error::new(refused)), BAD_INPUT);
        assert_eq!(code_of(&anyhow::anyhow!("unexpected")), INTERNAL);
    }

    #[test]
    fn the_message_names_the_command_that_retrains_a_model() {
        let version = ModelError::Version {
            source_name: "m.json".into(),
            found: "9".into(),
            expected: 2,
        };
        let library = version.to_string();
        assert!(library.ends_with("; retrain the model"), "{library}");
        assert!(!library.contains("graspath train"), "{library}");
        let error = anyhow::Error::new(version).context("cannot generate");
        assert_eq!(
            message(&error),
            format!("cannot generate: {library} with `graspath train`")
        );
        assert_eq!(code_of(&error), BAD_INPUT);
    }

    #[test]
    fn the_message_names_the_flag_that_replaces_an_output() {
        let dir = std::env::temp_dir().join(format!("graspath-exit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("out.json");
        std::fs::write(&file, b"{}").unwrap();
        let refused =
            graspath::output_files::check_file_target(&file, Existing::Refuse).unwrap_err();
        let error = anyhow::Error::new(refused).context("cannot write");
        assert_eq!(
            message(&error),
            format!(
                "cannot write: {}: the file exists; use --force to replace it, or choose another path",
                file.display()
            )
        );
        assert_eq!(code_of(&error), BAD_INPUT);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
