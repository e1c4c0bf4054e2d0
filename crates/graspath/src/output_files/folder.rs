//! Output folders: a set of files written into a fresh temporary folder beside the target and
//! moved into place with one rename ([`write_files`], [`FolderWriter`]).

use super::*;

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
pub(super) fn replace_folder(staging: &Path, dir: &Path) -> Result<(), OutputError> {
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
