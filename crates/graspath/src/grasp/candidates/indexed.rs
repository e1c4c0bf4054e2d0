//! A graspath candidate file (JSON or CSV) checked whole once and then read again chunk by
//! chunk, so that a streamed selection never holds its candidates: memory grows with the
//! number of candidates only by the index, one position and one digest per [`INDEX_STRIDE`]
//! candidates.
//!
//! A file that changes after it was indexed is an error, never a mix of two files: its
//! length, modification time and status-change time are compared before each read, and the
//! candidates read again are compared with the index's digests of what was read the first
//! time (a rewrite in place with the same length and a reset modification time is caught by
//! the status-change time, and by the digests whatever the file system keeps).

use super::rows::{changed, scan_file, scan_from, Flow, Resume, Row, ScanError};
use super::{check_file, Candidate, CandidateError};
use std::hash::Hasher;
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
    /// A digest of candidates `k · INDEX_STRIDE ..` `(k + 1) · INDEX_STRIDE` as first read,
    /// for each `k` ([`Digest`]).
    digests: Vec<u64>,
}

/// A running digest of candidates (every field, bit for bit), to tell that what is read again
/// is what was read before.
#[derive(Default)]
struct Digest(rustc_hash::FxHasher);

impl Digest {
    fn add(&mut self, c: &Candidate) {
        let h = &mut self.0;
        h.write_usize(c.id);
        h.write(c.label.as_bytes());
        h.write_u8(0xff);
        let pose = &c.object_from_wrist;
        for v in pose
            .translation
            .vector
            .iter()
            .chain(pose.rotation.coords.iter())
        {
            h.write_u64(v.to_bits());
        }
        h.write_u64(c.log_likelihood.to_bits());
        for v in c.contact.iter().flat_map(|p| p.coords.iter()) {
            h.write_u64(v.to_bits());
        }
        h.write_usize(c.hand_joints.len());
        for v in &c.hand_joints {
            h.write_u64(v.to_bits());
        }
        h.write_u64(c.width.map_or(u64::MAX, f64::to_bits));
    }

    fn finish(&self) -> u64 {
        self.0.finish()
    }
}

/// Digests candidates in file order, one per [`INDEX_STRIDE`] of them.
#[derive(Default)]
struct StrideDigests {
    current: Digest,
    done: Vec<u64>,
}

impl StrideDigests {
    /// Adds the candidate at `index` (in order from a stride's start); returns the stride's
    /// number and digest when it completes it.
    fn add(&mut self, index: usize, c: &Candidate) -> Option<(usize, u64)> {
        self.current.add(c);
        ((index + 1).is_multiple_of(INDEX_STRIDE)).then(|| self.close(index / INDEX_STRIDE))
    }

    /// Ends the stride `k` (also a last, partial one).
    fn close(&mut self, k: usize) -> (usize, u64) {
        let digest = std::mem::take(&mut self.current).finish();
        self.done.push(digest);
        (k, digest)
    }
}

/// What tells at once that a file changed after it was checked: its length (bytes), its
/// modification time and (Unix) its status-change time.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Stamp {
    len: u64,
    modified: Option<SystemTime>,
    /// The status-change time (seconds, nanoseconds): unlike the modification time, no
    /// program can set it back.
    #[cfg(unix)]
    changed: (i64, i64),
}

impl Stamp {
    fn of(path: &Path) -> Result<Self, CandidateError> {
        let metadata = std::fs::metadata(path).map_err(|e| CandidateError::unreadable(path, e))?;
        Ok(Self {
            len: metadata.len(),
            modified: metadata.modified().ok(),
            #[cfg(unix)]
            changed: {
                use std::os::unix::fs::MetadataExt;
                (metadata.ctime(), metadata.ctime_nsec())
            },
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
        // A folder, FIFO or device is refused by the reading (`crate::input::open`), as by
        // every reader.
        let stamp = Stamp::of(path)?;
        let mut len: usize = 0;
        let mut max_log_likelihood = f64::NEG_INFINITY;
        let mut marks = Vec::new();
        let mut digests = StrideDigests::default();
        check_file(path, |row: Row| {
            if row.index.is_multiple_of(INDEX_STRIDE) {
                marks.push(row.resume);
            }
            digests.add(row.index, &row.candidate);
            len += 1;
            max_log_likelihood = max_log_likelihood.max(row.candidate.log_likelihood);
        })?;
        if !len.is_multiple_of(INDEX_STRIDE) {
            digests.close(len / INDEX_STRIDE);
        }
        let file = Self {
            path: path.to_path_buf(),
            stamp,
            len,
            max_log_likelihood,
            marks,
            digests: digests.done,
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
        let mut digests = StrideDigests::default();
        scan_file(&self.path, &mut |row: Row| {
            if row.index >= self.len {
                return Err(E::from(self.changed()));
            }
            read += 1;
            let mut completed = digests.add(row.index, &row.candidate);
            if read == self.len && !self.len.is_multiple_of(INDEX_STRIDE) {
                completed = Some(digests.close(row.index / INDEX_STRIDE));
            }
            if let Some((k, digest)) = completed {
                if self.digests[k] != digest {
                    return Err(E::from(self.changed()));
                }
            }
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
        let end = ((k + 1) * INDEX_STRIDE).min(self.len);
        let mut found = None;
        let mut digest = Digest::default();
        let mut read = 0;
        // The whole stride is read, to compare it with its digest.
        scan_from(
            &self.path,
            &self.marks[k],
            k * INDEX_STRIDE,
            &mut |row: Row| {
                digest.add(&row.candidate);
                read += 1;
                if row.index == index {
                    found = Some(row.candidate);
                }
                Ok(if row.index + 1 >= end {
                    Flow::Stop
                } else {
                    Flow::Continue
                })
            },
        )
        .map_err(ScanError::into_file)?;
        if read != end - k * INDEX_STRIDE || digest.finish() != self.digests[k] {
            return Err(self.changed());
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The digests alone tell a changed stride (whatever the file system's times say): a
    /// stored digest that differs from what is read is an error for chunks and single
    /// candidates, and only for candidates of that stride.
    #[test]
    fn a_stride_that_reads_differently_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.csv");
        let mut text = String::from("x,y,z,qx,qy,qz,qw\n");
        for i in 0..(2 * INDEX_STRIDE + 5) {
            text.push_str(&format!("{},0,0.05,0,0,0,1\n", i as f64 * 1e-3));
        }
        std::fs::write(&path, text).unwrap();
        let file = CandidateFile::index(&path).unwrap();
        assert_eq!(file.digests.len(), 3);
        let all =
            |f: &CandidateFile| f.for_each_chunk(7, |_| -> Result<(), CandidateError> { Ok(()) });
        assert!(all(&file).is_ok());
        for k in 0..3 {
            let mut tampered = file.clone();
            tampered.digests[k] ^= 1;
            assert!(all(&tampered).is_err(), "stride {k}");
            let first = k * INDEX_STRIDE;
            assert!(tampered.candidate(first).is_err(), "stride {k}");
            let other = ((k + 1) % 3) * INDEX_STRIDE;
            assert!(tampered.candidate(other).is_ok(), "stride {k}");
        }
    }
}
