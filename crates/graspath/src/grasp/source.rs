//! Where a task's candidates are: held in memory, or produced when asked for — a parametric
//! family computed from each candidate's index, or a graspath candidate file read again chunk
//! by chunk. A streamed selection reads them through [`CandidateSource`] so that it never
//! holds them all.

use super::{Candidate, CandidateError, CandidateFile, FamilyLayout};
use std::borrow::Cow;
use std::ops::Range;
use std::sync::Arc;

/// Where a task's candidates are (see [`Task::candidates`](crate::task::Task::candidates)).
#[derive(Debug, Clone, PartialEq)]
pub enum CandidateSource {
    /// Held in memory, shared with the results that refer to them.
    Held(Vec<Arc<Candidate>>),
    /// A family laid out on the object's shape; its candidates are computed from their index.
    Family(FamilyLayout),
    /// A graspath candidate file, checked and indexed; its candidates are read again from it.
    File(CandidateFile),
}

impl CandidateSource {
    /// How many candidates there are.
    pub fn len(&self) -> usize {
        match self {
            Self::Held(held) => held.len(),
            Self::Family(family) => family.len(),
            Self::File(file) => file.len(),
        }
    }

    /// Whether there is no candidate.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The largest natural log-likelihood of the candidates (`−∞` without any; 0 for a family,
    /// whose candidates are equally likely).
    pub fn max_log_likelihood(&self) -> f64 {
        match self {
            Self::Held(held) => held
                .iter()
                .map(|c| c.log_likelihood)
                .fold(f64::NEG_INFINITY, f64::max),
            Self::Family(family) if family.is_empty() => f64::NEG_INFINITY,
            Self::Family(_) => 0.0,
            Self::File(file) => file.max_log_likelihood(),
        }
    }

    /// Calls `consume` with the candidates in order, at most `size` (≥ 1) at a time, each
    /// chunk computed or read when its turn comes and dropped after its call; stops at the
    /// first error (a file that can no longer be read included).
    pub fn for_each_chunk<E: From<CandidateError>>(
        &self,
        size: usize,
        mut consume: impl FnMut(&[Arc<Candidate>]) -> Result<(), E>,
    ) -> Result<(), E> {
        let size = size.max(1);
        match self {
            Self::Held(held) => held.chunks(size).try_for_each(consume),
            Self::Family(family) => {
                let n = family.len();
                (0..n).step_by(size).try_for_each(|start| {
                    let chunk: Vec<Arc<Candidate>> = (start..n.min(start + size))
                        .filter_map(|k| family.candidate(k).map(Arc::new))
                        .collect();
                    consume(&chunk)
                })
            }
            Self::File(file) => file.for_each_chunk(size, |chunk| {
                let chunk: Vec<Arc<Candidate>> = chunk.into_iter().map(Arc::new).collect();
                consume(&chunk)
            }),
        }
    }

    /// The candidate at position `index` (`None` past the end).
    pub fn candidate(&self, index: usize) -> Result<Option<Arc<Candidate>>, CandidateError> {
        match self {
            Self::Held(held) => Ok(held.get(index).cloned()),
            Self::Family(family) => Ok(family.candidate(index).map(Arc::new)),
            Self::File(file) => Ok(file.candidate(index)?.map(Arc::new)),
        }
    }

    /// Every candidate, in order: borrowed when held, else computed or read all at once.
    pub fn all(&self) -> Result<Cow<'_, [Arc<Candidate>]>, CandidateError> {
        let shared = |all: Vec<Candidate>| Cow::Owned(all.into_iter().map(Arc::new).collect());
        match self {
            Self::Held(held) => Ok(Cow::Borrowed(held)),
            Self::Family(family) => Ok(shared(family.all())),
            Self::File(file) => Ok(shared(file.all()?)),
        }
    }

    /// The candidates at the positions `range` (within `0..len()`), held: the same candidates
    /// (shared when held, else computed or read).
    pub fn held_range(&self, range: Range<usize>) -> Result<Vec<Arc<Candidate>>, CandidateError> {
        match self {
            Self::Held(held) => Ok(held[range].to_vec()),
            _ => range
                .filter_map(|k| self.candidate(k).transpose())
                .collect(),
        }
    }

    /// The candidates when they are held in memory.
    pub fn held(&self) -> Option<&[Arc<Candidate>]> {
        match self {
            Self::Held(held) => Some(held),
            _ => None,
        }
    }
}
