//! Candidates that are not held but produced when asked for: a parametric family computed
//! from each candidate's index, or a graspath candidate file read again chunk by chunk. A
//! streamed selection reads them through [`CandidateSource`] so that it never holds them all.

use super::{Candidate, CandidateError, CandidateFile, FamilyLayout};
use std::sync::Arc;

/// Where a task's candidates come from when they are not held (see
/// [`Task::candidate_source`](crate::task::Task::candidate_source)).
#[derive(Debug, Clone, PartialEq)]
pub enum CandidateSource {
    /// A family laid out on the object's shape; its candidates are computed from their index.
    Family(FamilyLayout),
    /// A graspath candidate file, checked and indexed; its candidates are read again from it.
    File(CandidateFile),
}

impl CandidateSource {
    /// How many candidates there are.
    pub fn len(&self) -> usize {
        match self {
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
    pub fn candidate(&self, index: usize) -> Result<Option<Candidate>, CandidateError> {
        match self {
            Self::Family(family) => Ok(family.candidate(index)),
            Self::File(file) => file.candidate(index),
        }
    }

    /// Every candidate, in order.
    pub fn all(&self) -> Result<Vec<Candidate>, CandidateError> {
        match self {
            Self::Family(family) => Ok(family.all()),
            Self::File(file) => file.all(),
        }
    }
}
