//! What kind of failure an error is — the one classification of bad input that the `graspath`
//! binary's exit codes and the Python exceptions are derived from — and an error's whole
//! message with its sources.
//!
//! Every module error implements [`Classify`]. An error that only adds context to its source (a
//! file that cannot be read: the operating system's error is the source) has no kind of its own:
//! its kind is its source's. `Error::fault` and `fault_of` (the crate root's) walk an error's
//! [`source`](std::error::Error::source) chain to find the kind, the file and field at fault and
//! the operating system's error kind.

use std::error::Error as StdError;
use std::fmt;
use std::io;

/// What kind of failure an error is. Every kind but [`ErrorKind::Internal`] is bad input: the
/// caller's file, field or option is at fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ErrorKind {
    /// A file that cannot be used as a file: an input file that is missing or cannot be read
    /// (permissions, a folder, a FIFO or device), or an output path that is refused (it exists
    /// and replacing was not allowed, it is a symbolic link or a device).
    File,
    /// Content that cannot be used: a malformed file, a field or option with a bad value, an
    /// unknown name, inputs that do not fit together.
    Content,
    /// A size or count over a documented resource limit (a file's size, a number of samples,
    /// points or placements, the work or memory a task may take).
    Limit,
    /// Not caused by the input: writing output failed, or something unexpected.
    Internal,
}

impl ErrorKind {
    /// True for the kinds that say the input is at fault (all but [`ErrorKind::Internal`]).
    pub fn is_bad_input(self) -> bool {
        !matches!(self, Self::Internal)
    }

    /// The kind of an operating-system error met while reading input: a file larger than the
    /// cap ([`io::ErrorKind::FileTooLarge`]) is [`ErrorKind::Limit`], text that is not UTF-8
    /// ([`io::ErrorKind::InvalidData`]) is [`ErrorKind::Content`], anything else is
    /// [`ErrorKind::File`].
    pub fn of_io(error: &io::Error) -> Self {
        match error.kind() {
            io::ErrorKind::FileTooLarge => Self::Limit,
            io::ErrorKind::InvalidData => Self::Content,
            _ => Self::File,
        }
    }
}

/// What a module error says about itself: its kind, and the file and field at fault when it
/// names them.
pub trait Classify: StdError {
    /// The error's kind, or `None` when it is its source's (an error that names the file and
    /// leaves what went wrong to its source).
    fn kind(&self) -> Option<ErrorKind>;

    /// The file (or input) at fault, as the message names it.
    fn file(&self) -> Option<&str> {
        None
    }

    /// The field, option or location in the file at fault (`object.pose.xyz`, `line 7`,
    /// `box.size[1]`), as the message names it.
    fn field(&self) -> Option<&str> {
        None
    }
}

/// What an error chain says is at fault: the kind, the innermost file and field that an error of
/// the chain names, and the operating system's error kind when the chain holds an I/O error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fault<'a> {
    /// The kind: the outermost error's own, else its source's, and so on.
    pub kind: ErrorKind,
    /// The innermost file an error of the chain names (the most specific one: a task's cloud
    /// file rather than the task file).
    pub file: Option<&'a str>,
    /// The field at fault in [`Fault::file`], when that error names one.
    pub field: Option<&'a str>,
    /// The kind of the first operating-system error in the chain (`NotFound` for a missing
    /// file).
    pub io: Option<io::ErrorKind>,
}

impl<'a> Fault<'a> {
    /// Walks `error` and its sources; `classify` says which of them are graspath errors. An
    /// I/O error gives the kind ([`ErrorKind::of_io`]) only as the source of a graspath error
    /// that left its kind to it. `None` when no error of the chain has a kind.
    pub(crate) fn walk(
        error: &'a (dyn StdError + 'static),
        classify: impl Fn(&'a (dyn StdError + 'static)) -> Option<&'a dyn Classify>,
    ) -> Option<Self> {
        let mut kind = None;
        let mut deferred = false;
        let mut file = None;
        let mut field = None;
        let mut io_kind = None;
        let mut next = Some(error);
        while let Some(e) = next {
            if let Some(c) = classify(e) {
                if kind.is_none() {
                    kind = c.kind();
                    deferred = kind.is_none();
                }
                if let Some(f) = c.file() {
                    file = Some(f);
                    field = c.field();
                }
            } else if let Some(io) = e.downcast_ref::<io::Error>() {
                if kind.is_none() && deferred {
                    kind = Some(ErrorKind::of_io(io));
                }
                io_kind = io_kind.or(Some(io.kind()));
            }
            next = e.source();
        }
        kind.map(|kind| Self {
            kind,
            file,
            field,
            io: io_kind,
        })
    }
}

/// An error's message followed by each of its sources', joined by `": "`: the whole message, as
/// the `graspath` binary prints it.
///
/// ```
/// use graspath::Chain;
/// let read = graspath::robot::UrdfRobot::from_file("missing.urdf".as_ref()).unwrap_err();
/// assert!(Chain(&read).to_string().starts_with("missing.urdf: cannot read: "));
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Chain<'a>(pub &'a dyn StdError);

impl fmt::Display for Chain<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)?;
        let mut next = self.0.source();
        while let Some(e) = next {
            write!(f, ": {e}")?;
            next = e.source();
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, thiserror::Error)]
    #[error("outer.json")]
    struct Outer(#[source] io::Error);

    impl Classify for Outer {
        fn kind(&self) -> Option<ErrorKind> {
            None
        }
        fn file(&self) -> Option<&str> {
            Some("outer.json")
        }
    }

    #[test]
    fn the_kind_comes_from_the_source_when_the_error_has_none() {
        let e = Outer(io::Error::new(io::ErrorKind::NotFound, "no such file"));
        let fault = Fault::walk(&e, |e| e.downcast_ref::<Outer>().map(|o| o as _)).unwrap();
        assert_eq!(fault.kind, ErrorKind::File);
        assert_eq!(fault.file, Some("outer.json"));
        assert_eq!(fault.io, Some(io::ErrorKind::NotFound));
        assert_eq!(Chain(&e).to_string(), "outer.json: no such file");
        let big = Outer(io::Error::new(io::ErrorKind::FileTooLarge, "too large"));
        let fault = Fault::walk(&big, |e| e.downcast_ref::<Outer>().map(|o| o as _)).unwrap();
        assert_eq!(fault.kind, ErrorKind::Limit);
        assert!(ErrorKind::Limit.is_bad_input() && !ErrorKind::Internal.is_bad_input());
        // An I/O error alone (an application's own) is not classified.
        let alone = io::Error::other("disk full");
        assert!(Fault::walk(&alone, |e| e.downcast_ref::<Outer>().map(|o| o as _)).is_none());
    }
}
