//! A graspath candidate file (JSON or CSV) checked whole once and then read again chunk by
//! chunk, so that a streamed selection never holds its candidates: memory grows with the
//! number of candidates only by the index, one position per [`INDEX_STRIDE`] candidates.

use super::rows::{changed, scan_file, scan_from, Flow, Resume, Row, ScanError};
use super::{check_file, Candidate, CandidateError};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// Every how many candidates a [`CandidateFile`] remembers where to start reading again:
/// fetching one candidate reads at most this many records.
pub const INDEX_STRIDE: usize = 64;

/// A graspath candidate file, checked whole and indexed ([`CandidateFile::index`]): its
/// candidates are read again from the file when asked for, in chunks
/// ([`CandidateFile::for_each_chunk`]) or one by one ([`CandidateFile::candidate`]). They are
/// the candidates [`read_candidates`](super::read_candidates) reads, in the same order.
#[derive(Debug, Clone, PartialEq)]
pub struct CandidateFile {
    path: PathBuf,
    stamp: Stamp,
    len: usize,
    max_log_likelihood: f64,
    /// Where candidate `k · INDEX_STRIDE` starts, for each `k`.
    marks: Vec<Resume>,
}

/// What tells that a file changed after it was checked: its length (bytes) and modification
/// time.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Stamp {
    len: u64,
    modified: Option<SystemTime>,
}

impl Stamp {
    fn of(path: &Path) -> Result<Self, CandidateError> {
        let metadata = std::fs::metadata(path).map_err(|e| CandidateError {
            file: path.display().to_string(),
            location: "file".into(),
            message: format!("cannot read: {e}"),
        })?;
        Ok(Self {
            len: metadata.len(),
            modified: metadata.modified().ok(),
        })
    }
}

impl CandidateFile {
    /// Whether `path` can be indexed: a regular file, which can be read more than once (a pipe
    /// or device cannot; read it whole with [`read_candidates`](super::read_candidates)).
    pub fn can_index(path: &Path) -> bool {
        std::fs::metadata(path).is_ok_and(|m| m.is_file())
    }

    /// Reads the file once, checking every candidate as
    /// [`read_candidates`](super::read_candidates) does (the same errors), and remembers how
    /// many there are, their largest log-likelihood and where every [`INDEX_STRIDE`]-th
    /// starts. Nothing else is kept.
    pub fn index(path: &Path) -> Result<Self, CandidateError> {
        if !Self::can_index(path) {
            return Err(CandidateError {
                file: path.display().to_string(),
                location: "file".into(),
                message: "is not a regular file, so it cannot be read in chunks".into(),
            });
        }
        let stamp = Stamp::of(path)?;
        let mut len = 0;
        let mut max_log_likelihood = f64::NEG_INFINITY;
        let mut marks = Vec::new();
        check_file(path, |row: Row| {
            if row.index.is_multiple_of(INDEX_STRIDE) {
                marks.push(row.resume);
            }
            len += 1;
            max_log_likelihood = max_log_likelihood.max(row.candidate.log_likelihood);
        })?;
        let file = Self {
            path: path.to_path_buf(),
            stamp,
            len,
            max_log_likelihood,
            marks,
        };
        file.check_unchanged()?;
        Ok(file)
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// How many candidates the file holds (at least one).
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the file holds no candidate (never: such a file is refused).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The largest natural log-likelihood of the file's candidates.
    pub fn max_log_likelihood(&self) -> f64 {
        self.max_log_likelihood
    }

    /// Reads the candidates again in file order and calls `consume` with them, at most `size`
    /// (≥ 1) at a time; stops at the first error. Only one chunk is held at a time. A file
    /// that changed since it was indexed is an error.
    pub fn for_each_chunk<E: From<CandidateError>>(
        &self,
        size: usize,
        mut consume: impl FnMut(Vec<Candidate>) -> Result<(), E>,
    ) -> Result<(), E> {
        self.check_unchanged()?;
        let size = size.max(1);
        let mut chunk = Vec::with_capacity(size.min(self.len));
        let mut read = 0;
        scan_file(&self.path, &mut |row: Row| {
            if row.index >= self.len {
                return Err(E::from(self.changed()));
            }
            read += 1;
            chunk.push(row.candidate);
            if chunk.len() == size {
                let full = std::mem::replace(&mut chunk, Vec::with_capacity(size));
                consume(full)?;
            }
            Ok(Flow::Continue)
        })
        .map_err(|e| match e {
            ScanError::File(e) => E::from(e),
            ScanError::Sink(e) => e,
        })?;
        if read != self.len {
            return Err(E::from(self.changed()));
        }
        if chunk.is_empty() {
            Ok(())
        } else {
            consume(chunk)
        }
    }

    /// The candidate at position `index` in file order (`None` past the end), read from the
    /// file: at most [`INDEX_STRIDE`] records are parsed.
    pub fn candidate(&self, index: usize) -> Result<Option<Candidate>, CandidateError> {
        if index >= self.len {
            return Ok(None);
        }
        self.check_unchanged()?;
        let k = index / INDEX_STRIDE;
        let mut found = None;
        scan_from(
            &self.path,
            &self.marks[k],
            k * INDEX_STRIDE,
            &mut |row: Row| {
                if row.index == index {
                    found = Some(row.candidate);
                    return Ok(Flow::Stop);
                }
                Ok(Flow::Continue)
            },
        )
        .map_err(ScanError::into_file)?;
        found.map(Some).ok_or_else(|| self.changed())
    }

    /// Every candidate, in file order.
    pub fn all(&self) -> Result<Vec<Candidate>, CandidateError> {
        let mut all = Vec::with_capacity(self.len);
        self.for_each_chunk(self.len, |chunk| -> Result<(), CandidateError> {
            all.extend(chunk);
            Ok(())
        })?;
        Ok(all)
    }

    fn check_unchanged(&self) -> Result<(), CandidateError> {
        if Stamp::of(&self.path)? == self.stamp {
            Ok(())
        } else {
            Err(self.changed())
        }
    }

    fn changed(&self) -> CandidateError {
        changed::<std::convert::Infallible>(&self.path).into_file()
    }
}
