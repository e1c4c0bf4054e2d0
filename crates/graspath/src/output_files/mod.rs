//! Writing output — one file or a set of files — so that nothing is ever clobbered by accident
//! or left half-written.
//!
//! The rules, the same for every writer of the library, the CLI and the Python bindings:
//!
//! * An output path that is a symbolic link, a device, a FIFO or a socket is refused: output is
//!   never written through or over them (not even when replacing is allowed).
//! * A single file is written to a fresh temporary file beside the target (same folder, hence
//!   the same file system), flushed to disk, then renamed onto the target. An existing regular
//!   file is replaced only with [`Existing::Replace`]; otherwise it is refused.
//! * A set of files (an output folder) is written into a fresh temporary folder beside the
//!   target, flushed, then moved into place with one rename: all files appear together or none
//!   does, and files of an earlier run never mix with new ones. An existing empty folder is
//!   replaced; an existing non-empty folder only with [`Existing::Replace`], which moves the old
//!   folder aside, renames the new one in and only then deletes the old one (on a failure the
//!   old folder is put back). The current folder, one of its ancestors and the home folder are
//!   never replaced, nor an output path that is or holds an input of the run
//!   ([`check_not_an_input`]).
//! * Missing parent folders are created, and removed again when the write fails. On any error
//!   no temporary file or folder is left behind.
//!
//! Temporary names are hidden and carry the target's name, the process id and a counter:
//! `.NAME.graspath-PID-N.tmp` (and `.NAME.graspath-PID-N.old` for a folder being replaced).
//! Every temporary name is remembered, so that a program stopped by a signal can remove what
//! it leaves ([`remove_temporaries`]; the CLI does on SIGINT, SIGTERM and SIGHUP).

use std::ffi::OsString;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

mod error;
mod folder;

pub use error::{OutputError, OutputErrorKind};
pub use folder::{write_files, FolderWriter};

/// Every temporary file or folder this process made, with, for an old folder moved aside,
/// where it came from.
static TEMPORARIES: Mutex<Vec<(PathBuf, Option<PathBuf>)>> = Mutex::new(Vec::new());

/// Remembers the temporary `path` (and where to put it back, for an old folder moved aside).
fn remember(path: &Path, restore_to: Option<&Path>) {
    let mut temporaries = TEMPORARIES
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    temporaries.retain(|(p, _)| p != path);
    temporaries.push((path.to_path_buf(), restore_to.map(Path::to_path_buf)));
}

/// Removes what this process's writers leave when the process is stopped part-way: every
/// temporary file and folder that still exists, and an old folder moved aside for a
/// replacement is put back where the new one has not yet arrived (else removed). Meant for
/// the moment before the process exits on a signal: writers still running may fail.
pub fn remove_temporaries() {
    let temporaries = TEMPORARIES
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    for (path, restore_to) in temporaries.iter() {
        let Ok(metadata) = std::fs::symlink_metadata(path) else {
            continue;
        };
        if let Some(dir) = restore_to {
            if std::fs::symlink_metadata(dir).is_err() && std::fs::rename(path, dir).is_ok() {
                continue;
            }
        }
        if metadata.is_dir() {
            // A writer may add a file while the folder is removed: try again a few times.
            for _ in 0..5 {
                if std::fs::remove_dir_all(path).is_ok() || !path.exists() {
                    break;
                }
            }
        } else {
            let _ = std::fs::remove_file(path);
        }
    }
}

/// What to do when the output path already holds a regular file (single-file output) or a
/// non-empty folder (folder output).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Existing {
    /// Refuse with [`OutputErrorKind::FileExists`] or [`OutputErrorKind::FolderNotEmpty`].
    #[default]
    Refuse,
    /// Replace it atomically (the CLI's `--force`).
    Replace,
}

impl Existing {
    /// [`Existing::Replace`] when `force` is set, else [`Existing::Refuse`].
    pub fn replace_if(force: bool) -> Self {
        if force {
            Self::Replace
        } else {
            Self::Refuse
        }
    }
}

/// What is at an output path now.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Found {
    Nothing,
    File,
    EmptyFolder,
    /// A folder and the name of one entry in it.
    Folder(String),
}

fn inspect(path: &Path) -> Result<Found, OutputError> {
    // `link/` would name the folder the link points to: the link itself is what is inspected.
    let unslashed: PathBuf = path.components().collect();
    let metadata = match std::fs::symlink_metadata(&unslashed) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Found::Nothing),
        Err(e) if e.kind() == std::io::ErrorKind::NotADirectory => {
            return Err(OutputError::new(path, OutputErrorKind::ParentNotFolder))
        }
        Err(e) => return Err(OutputError::io(path, "inspect the output path", e)),
    };
    let file_type = metadata.file_type();
    if file_type.is_symlink() {
        let target = std::fs::read_link(path).unwrap_or_default();
        return Err(OutputError::new(path, OutputErrorKind::Symlink(target)));
    }
    if file_type.is_file() {
        return Ok(Found::File);
    }
    if file_type.is_dir() {
        let mut entries = std::fs::read_dir(path)
            .map_err(|e| OutputError::io(path, "list the existing folder", e))?;
        return Ok(match entries.next() {
            None => Found::EmptyFolder,
            Some(entry) => Found::Folder(
                entry
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .unwrap_or_else(|_| "?".into()),
            ),
        });
    }
    Err(OutputError::new(
        path,
        OutputErrorKind::Special(special_kind(&file_type)),
    ))
}

#[cfg(unix)]
fn special_kind(file_type: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if file_type.is_block_device() {
        "block device"
    } else if file_type.is_char_device() {
        "character device"
    } else if file_type.is_fifo() {
        "FIFO (named pipe)"
    } else if file_type.is_socket() {
        "socket"
    } else {
        "special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::FileType) -> &'static str {
    "special file"
}

/// Checks, before any work is done, that `path` may receive a single output file: not a link,
/// device or folder, and not an existing file unless `existing` is [`Existing::Replace`].
/// [`write_file`] checks again when it writes.
pub fn check_file_target(path: &Path, existing: Existing) -> Result<(), OutputError> {
    match inspect(path)? {
        Found::Nothing => Ok(()),
        Found::File if existing == Existing::Replace => Ok(()),
        Found::File => Err(OutputError::new(path, OutputErrorKind::FileExists)),
        Found::EmptyFolder | Found::Folder(_) => Err(OutputError::new(
            path,
            OutputErrorKind::WrongKind {
                found: "folder",
                wanted: "file",
            },
        )),
    }
}

/// Checks, before any work is done, that `dir` may receive an output folder: not a link,
/// device or file, and empty or missing unless `existing` is [`Existing::Replace`] (and then
/// not a folder that must never be replaced). [`write_files`] checks again when it writes.
pub fn check_folder_target(dir: &Path, existing: Existing) -> Result<(), OutputError> {
    folder_state(dir, existing).map(|_| ())
}

fn folder_state(dir: &Path, existing: Existing) -> Result<Found, OutputError> {
    let found = inspect(dir)?;
    match &found {
        Found::Nothing | Found::EmptyFolder => {}
        Found::File => {
            return Err(OutputError::new(
                dir,
                OutputErrorKind::WrongKind {
                    found: "file",
                    wanted: "folder",
                },
            ))
        }
        Found::Folder(example) => {
            if existing == Existing::Refuse {
                return Err(OutputError::new(
                    dir,
                    OutputErrorKind::FolderNotEmpty(example.clone()),
                ));
            }
            if let Some(what) = protected(dir) {
                return Err(OutputError::new(dir, OutputErrorKind::Protected(what)));
            }
        }
    }
    Ok(found)
}

/// Refuses an output path that is, or (a folder) holds, one of `inputs` (files or folders the
/// run reads), so that replacing the output (`--force`) never deletes or overwrites an input.
/// Paths are compared after resolving links; inputs that do not exist are ignored (reading
/// them fails on its own).
pub fn check_not_an_input(out: &Path, inputs: &[PathBuf]) -> Result<(), OutputError> {
    let Ok(resolved_out) = std::fs::canonicalize(out) else {
        return Ok(());
    };
    for input in inputs {
        if std::fs::canonicalize(input).is_ok_and(|i| i.starts_with(&resolved_out)) {
            return Err(OutputError::new(
                out,
                OutputErrorKind::HoldsInput(input.clone()),
            ));
        }
    }
    Ok(())
}

/// Why `dir` must never be replaced, if it must not.
fn protected(dir: &Path) -> Option<&'static str> {
    let dir = std::fs::canonicalize(dir).ok()?;
    if dir.parent().is_none() {
        return Some("the root folder");
    }
    if let Ok(cwd) = std::env::current_dir().and_then(std::fs::canonicalize) {
        if cwd == dir {
            return Some("the working folder");
        }
        if cwd.starts_with(&dir) {
            return Some("an ancestor of the working folder");
        }
    }
    let home = std::env::var_os("HOME").map(PathBuf::from)?;
    (std::fs::canonicalize(home).ok()? == dir).then_some("the home folder")
}

/// The folder a path lives in (`.` for a bare name).
fn parent_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Creates the missing ancestors of `dir` (and `dir`), returning the ones created, outermost
/// first, so that a failed write can remove them again.
fn create_missing(dir: &Path, target: &Path) -> Result<Vec<PathBuf>, OutputError> {
    let mut missing = Vec::new();
    let mut current = Some(dir);
    while let Some(d) = current {
        if d.as_os_str().is_empty() || std::fs::symlink_metadata(d).is_ok() {
            break;
        }
        missing.push(d.to_path_buf());
        current = d.parent();
    }
    missing.reverse();
    let mut created = Vec::new();
    for d in missing {
        if let Err(e) = std::fs::create_dir(&d) {
            if e.kind() == std::io::ErrorKind::AlreadyExists {
                continue;
            }
            remove_created(&created);
            return Err(OutputError::io(
                target,
                format!("create the folder '{}'", d.display()),
                e,
            ));
        }
        created.push(d);
    }
    Ok(created)
}

/// Removes folders made by [`create_missing`] (innermost first; only while they are empty).
fn remove_created(created: &[PathBuf]) {
    for d in created.iter().rev() {
        let _ = std::fs::remove_dir(d);
    }
}

/// A fresh hidden name beside `target`: `.NAME.graspath-PID-N.SUFFIX`, created by `make`
/// (which must fail with `AlreadyExists` when the name is taken).
fn fresh<T>(
    target: &Path,
    suffix: &str,
    mut make: impl FnMut(&Path) -> std::io::Result<T>,
) -> std::io::Result<(PathBuf, T)> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = parent_of(target);
    let name = target
        .file_name()
        .map_or_else(|| OsString::from("output"), OsString::from);
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let mut file_name = OsString::from(".");
        file_name.push(&name);
        file_name.push(format!(".graspath-{}-{n}.{suffix}", std::process::id()));
        let path = dir.join(file_name);
        match make(&path) {
            Ok(value) => {
                remember(&path, None);
                return Ok((path, value));
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && n < 1_000_000 => continue,
            Err(e) => return Err(e),
        }
    }
}

/// Flushes a folder's entries (new names, renames) to disk.
fn sync_folder(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        File::open(dir)?.sync_all()
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        Ok(())
    }
}

/// Writes `bytes` to the file `path` (see the module's rules): a symbolic link, device or
/// folder is refused, an existing regular file is replaced only with [`Existing::Replace`],
/// missing parent folders are created. The file appears complete or not at all, and no
/// temporary file is left behind on an error.
pub fn write_file(path: &Path, bytes: &[u8], existing: Existing) -> Result<(), OutputError> {
    check_file_target(path, existing)?;
    let dir = parent_of(path);
    let created = create_missing(&dir, path)?;
    let result = (|| {
        let (temporary, mut file) = fresh(path, "tmp", |p| {
            OpenOptions::new().write(true).create_new(true).open(p)
        })
        .map_err(|e| OutputError::io(path, "create a temporary file beside it", e))?;
        let placed = (|| {
            file.write_all(bytes)
                .and_then(|()| file.sync_all())
                .map_err(|e| OutputError::io(path, "write the temporary file", e))?;
            drop(file);
            place_file(&temporary, path, existing)
        })();
        if placed.is_err() {
            let _ = std::fs::remove_file(&temporary);
        }
        placed?;
        sync_folder(&dir).map_err(|e| OutputError::io(path, "flush its folder", e))
    })();
    if result.is_err() {
        remove_created(&created);
    }
    result
}

/// Moves the complete temporary file onto `path`: a rename when replacing is allowed, else a
/// hard link that fails if `path` appeared meanwhile (falling back to a rename where the file
/// system has no hard links).
fn place_file(temporary: &Path, path: &Path, existing: Existing) -> Result<(), OutputError> {
    if existing == Existing::Refuse {
        match std::fs::hard_link(temporary, path) {
            Ok(()) => {
                let _ = std::fs::remove_file(temporary);
                return Ok(());
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                return Err(match inspect(path) {
                    Err(refused) => refused,
                    Ok(_) => OutputError::new(path, OutputErrorKind::FileExists),
                });
            }
            Err(_) => check_file_target(path, existing)?,
        }
    }
    std::fs::rename(temporary, path)
        .map_err(|e| OutputError::io(path, "rename the temporary file onto it", e))
}

#[cfg(test)]
mod tests;
