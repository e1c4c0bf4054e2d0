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
    fn new(path: &Path, kind: OutputErrorKind) -> Self {
        Self {
            path: path.to_path_buf(),
            kind,
        }
    }

    fn io(path: &Path, action: impl Into<String>, error: std::io::Error) -> Self {
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

/// Checks a relative name of the set and returns its components.
fn relative_name(dir: &Path, name: &str) -> Result<PathBuf, OutputError> {
    let relative = Path::new(name);
    let plain = !name.is_empty()
        && relative
            .components()
            .all(|c| matches!(c, Component::Normal(_)));
    if !plain {
        return Err(OutputError::new(
            dir,
            OutputErrorKind::BadName(name.to_string()),
        ));
    }
    Ok(relative.to_path_buf())
}

/// Writes a set of `(relative name, bytes)` files as the folder `dir` (see the module's rules):
/// all files appear together or none does; an existing non-empty folder is replaced as a whole
/// only with [`Existing::Replace`], never merged. Names may contain `/` for subfolders. Returns
/// the paths written, in the order given.
pub fn write_files(
    dir: &Path,
    files: &[(String, Vec<u8>)],
    existing: Existing,
) -> Result<Vec<PathBuf>, OutputError> {
    let mut seen = std::collections::BTreeSet::new();
    for (name, _) in files {
        let relative = relative_name(dir, name)?;
        if !seen.insert(relative) {
            return Err(OutputError::new(
                dir,
                OutputErrorKind::DuplicateName(name.clone()),
            ));
        }
    }
    let mut folder = FolderWriter::begin(dir, existing)?;
    for (name, bytes) in files {
        folder.write(name, bytes)?;
    }
    folder.finish()
}

/// An output folder written file by file, for output too large to render in memory (streamed
/// results): the files are created in a fresh temporary folder beside `dir`, and
/// [`finish`](Self::finish) moves that folder into place with the rules of [`write_files`] (all
/// files appear together or none does). Dropped without `finish` (an error, a panic), it
/// deletes the temporary folder and the parent folders it created.
#[derive(Debug)]
pub struct FolderWriter {
    dir: PathBuf,
    found: Found,
    parent: PathBuf,
    created: Vec<PathBuf>,
    staging: PathBuf,
    folders: std::collections::BTreeSet<PathBuf>,
    names: Vec<PathBuf>,
    done: bool,
}

impl FolderWriter {
    /// Checks `dir` (see [`check_folder_target`]), creates its missing parent folders and the
    /// temporary folder beside it.
    pub fn begin(dir: &Path, existing: Existing) -> Result<Self, OutputError> {
        let found = folder_state(dir, existing)?;
        let parent = parent_of(dir);
        let created = create_missing(&parent, dir)?;
        let staging = match fresh(dir, "tmp", |p| std::fs::create_dir(p)) {
            Ok((path, ())) => path,
            Err(e) => {
                remove_created(&created);
                return Err(OutputError::io(
                    dir,
                    "create a temporary folder beside it",
                    e,
                ));
            }
        };
        let mut folders = std::collections::BTreeSet::new();
        folders.insert(staging.clone());
        Ok(Self {
            dir: dir.to_path_buf(),
            found,
            parent,
            created,
            staging,
            folders,
            names: Vec::new(),
            done: false,
        })
    }

    /// Creates the new file `name` (relative; may contain `/` for subfolders) in the temporary
    /// folder and returns it for writing. A name given twice is refused.
    pub fn create(&mut self, name: &str) -> Result<File, OutputError> {
        let dir = &self.dir;
        let relative = relative_name(dir, name)?;
        if self.names.contains(&relative) {
            return Err(OutputError::new(
                dir,
                OutputErrorKind::DuplicateName(name.to_string()),
            ));
        }
        let file = self.staging.join(&relative);
        let action = || format!("write '{}' in the temporary folder", relative.display());
        let mut sub = relative.parent();
        if sub.is_some_and(|s| !s.as_os_str().is_empty()) {
            std::fs::create_dir_all(file.parent().unwrap_or(&self.staging))
                .map_err(|e| OutputError::io(dir, action(), e))?;
        }
        while let Some(s) = sub.filter(|s| !s.as_os_str().is_empty()) {
            self.folders.insert(self.staging.join(s));
            sub = s.parent();
        }
        let opened = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&file)
            .map_err(|e| OutputError::io(dir, action(), e))?;
        self.names.push(relative);
        Ok(opened)
    }

    /// Writes the whole new file `name` (see [`create`](Self::create)).
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<(), OutputError> {
        let mut file = self.create(name)?;
        file.write_all(bytes).map_err(|e| {
            OutputError::io(
                &self.dir,
                format!("write '{name}' in the temporary folder"),
                e,
            )
        })
    }

    /// Flushes every file to disk and moves the folder into place (replacing an old non-empty
    /// folder only when [`begin`](Self::begin) was given [`Existing::Replace`]). Returns the
    /// paths written, in the order they were created.
    pub fn finish(mut self) -> Result<Vec<PathBuf>, OutputError> {
        let dir = self.dir.clone();
        self.sync_staged()
            .map_err(|e| OutputError::io(&dir, "flush the temporary folder", e))?;
        match self.found {
            Found::Folder(_) => replace_folder(&self.staging, &dir)?,
            _ => std::fs::rename(&self.staging, &dir)
                .map_err(|e| OutputError::io(&dir, "rename the temporary folder onto it", e))?,
        }
        self.done = true;
        sync_folder(&self.parent)
            .map_err(|e| OutputError::io(&dir, "flush its parent folder", e))?;
        Ok(self.names.iter().map(|n| dir.join(n)).collect())
    }

    /// Flushes every file and folder of the temporary folder to disk, all at once: a file
    /// system that commits its journal on each flush (ext4) can then commit them together,
    /// instead of waiting for one commit per file in turn.
    fn sync_staged(&self) -> std::io::Result<()> {
        let files = self
            .names
            .iter()
            .map(|name| (self.staging.join(name), false));
        let folders = self.folders.iter().map(|folder| (folder.clone(), true));
        let staged: Vec<(PathBuf, bool)> = files.chain(folders).collect();
        // At most this many flushes run at once (a report has a few dozen files).
        const AT_ONCE: usize = 8;
        let flush_share = |first: usize| {
            staged
                .iter()
                .skip(first)
                .step_by(AT_ONCE)
                .try_for_each(|(path, is_folder)| {
                    if *is_folder {
                        sync_folder(path)
                    } else {
                        File::open(path).and_then(|f| f.sync_all())
                    }
                })
        };
        std::thread::scope(|scope| {
            // A share whose thread cannot be started is flushed here instead.
            let workers: Vec<_> = (0..AT_ONCE.min(staged.len()))
                .map(|first| {
                    std::thread::Builder::new()
                        .spawn_scoped(scope, move || flush_share(first))
                        .map_err(|_| first)
                })
                .collect();
            workers.into_iter().try_for_each(|worker| match worker {
                Ok(thread) => thread
                    .join()
                    .unwrap_or_else(|p| std::panic::resume_unwind(p)),
                Err(first) => flush_share(first),
            })
        })
    }
}

impl Drop for FolderWriter {
    fn drop(&mut self) {
        if !self.done {
            let _ = std::fs::remove_dir_all(&self.staging);
            remove_created(&self.created);
        }
    }
}

/// Moves the old folder aside, the new one in, then deletes the old one; puts the old one back
/// when the new one cannot be moved in.
fn replace_folder(staging: &Path, dir: &Path) -> Result<(), OutputError> {
    let (aside, ()) = fresh(dir, "old", |p| std::fs::create_dir(p))
        .map_err(|e| OutputError::io(dir, "reserve a name to move the old folder to", e))?;
    remember(&aside, Some(dir));
    // Renaming a folder onto an empty folder replaces it.
    if let Err(e) = std::fs::rename(dir, &aside) {
        let _ = std::fs::remove_dir(&aside);
        return Err(OutputError::io(dir, "move the old folder aside", e));
    }
    if let Err(error) = std::fs::rename(staging, dir) {
        let action = "rename the temporary folder onto it".to_string();
        return Err(match std::fs::rename(&aside, dir) {
            Ok(()) => OutputError::io(dir, action, error),
            Err(_) => OutputError::new(
                dir,
                OutputErrorKind::NotRestored {
                    action,
                    error,
                    aside,
                },
            ),
        });
    }
    std::fs::remove_dir_all(&aside)
        .map_err(|error| OutputError::new(dir, OutputErrorKind::OldNotRemoved { aside, error }))
}

#[cfg(test)]
mod tests;
