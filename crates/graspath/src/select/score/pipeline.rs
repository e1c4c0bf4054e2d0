//! Scoring as a pipeline: the candidates are produced (computed or read) on a thread of their
//! own while every worker of the rayon pool takes the next group of them, scores it and hands
//! its results on; one worker at a time consumes the results in candidate order (writes them
//! out, ranks them alone, frees them) while the others keep scoring. So production and
//! consumption overlap with scoring instead of holding the workers up, and no worker waits for
//! the slowest group of a chunk before starting the next one: the only serial part left is
//! what the caller does after the last result.
//!
//! At most [`IN_FLIGHT`] candidates are scored or being scored and not yet consumed, and at most
//! three chunks of candidates are read ahead of them, so the memory held stays bounded whatever
//! the number of candidates.
//!
//! Called from inside a rayon worker (a placement map scores its placements in parallel, each
//! on a worker), the pipeline would take over the pool from inside it: there the chunks are
//! scored in turn instead, each in parallel, and consumed on the calling worker. The results
//! are the same either way (each candidate's score depends on nothing but the candidate and
//! the setup).

use super::STREAM_CHUNK;
use crate::grasp::{Candidate, CandidateError, CandidateSource};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::convert::Infallible;
use std::sync::mpsc::{sync_channel, Receiver};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};

/// How many candidates may be taken for scoring and not yet consumed: enough for every worker to
/// find work while the consumer writes a large block of results out, few enough that their full
/// scores (series and motions) take little memory.
pub const IN_FLIGHT: usize = 4 * STREAM_CHUNK;

/// What scores a group of candidates: one result per candidate, in order.
pub(super) type Score<'a, T> = dyn Fn(&[Arc<Candidate>]) -> Vec<T> + Sync + 'a;

/// Candidates that can be scored in order, chunk by chunk.
pub trait CandidateChunks: Sync {
    /// Why the candidates cannot be produced (a file that can no longer be read).
    type Error: Send;

    /// How many candidates there are.
    fn count(&self) -> usize;

    /// Calls `consume` with the candidates in order, at most `size` (≥ 1) at a time; stops at
    /// the first error.
    fn for_each_chunk<E: From<Self::Error>>(
        &self,
        size: usize,
        consume: impl FnMut(&[Arc<Candidate>]) -> Result<(), E>,
    ) -> Result<(), E>;
}

impl CandidateChunks for [Arc<Candidate>] {
    type Error = Infallible;

    fn count(&self) -> usize {
        self.len()
    }

    fn for_each_chunk<E: From<Infallible>>(
        &self,
        size: usize,
        consume: impl FnMut(&[Arc<Candidate>]) -> Result<(), E>,
    ) -> Result<(), E> {
        self.chunks(size.max(1)).try_for_each(consume)
    }
}

impl CandidateChunks for CandidateSource {
    type Error = CandidateError;

    fn count(&self) -> usize {
        self.len()
    }

    fn for_each_chunk<E: From<CandidateError>>(
        &self,
        size: usize,
        consume: impl FnMut(&[Arc<Candidate>]) -> Result<(), E>,
    ) -> Result<(), E> {
        CandidateSource::for_each_chunk(self, size, consume)
    }
}

/// Scores `candidates` in groups of `group` with `score` (one result per candidate, in order)
/// and calls `consume` with every result in candidate order; stops at the first error of the
/// candidates or of `consume`. Through the pipeline when called from outside the rayon pool
/// with more than one chunk of candidates; else chunk by chunk.
pub(super) fn score_in_order<C, E, T: Send>(
    candidates: &C,
    group: usize,
    score: &Score<'_, T>,
    consume: impl FnMut(T) -> Result<(), E> + Send,
) -> Result<(), E>
where
    C: CandidateChunks + ?Sized,
    E: From<C::Error> + Send,
{
    let group = group.max(1);
    if rayon::current_thread_index().is_some() || candidates.count() <= STREAM_CHUNK {
        chunk_by_chunk(candidates, group, score, consume)
    } else {
        pipelined(candidates, group, score, consume)
    }
}

/// Each chunk scored in parallel, its results handed on once the whole chunk is scored.
fn chunk_by_chunk<C, E, T: Send>(
    candidates: &C,
    group: usize,
    score: &Score<'_, T>,
    mut consume: impl FnMut(T) -> Result<(), E>,
) -> Result<(), E>
where
    C: CandidateChunks + ?Sized,
    E: From<C::Error>,
{
    candidates.for_each_chunk(STREAM_CHUNK, |chunk| -> Result<(), E> {
        let scores: Vec<Vec<T>> = chunk.par_chunks(group).map(score).collect();
        scores.into_iter().flatten().try_for_each(&mut consume)
    })
}

/// Why production stopped early.
enum Halt<F> {
    /// The candidates cannot be produced.
    Source(F),
    /// The workers stopped taking candidates (a `consume` failed, or scoring panicked).
    WorkersGone,
}

impl<F> From<F> for Halt<F> {
    fn from(error: F) -> Self {
        Halt::Source(error)
    }
}

/// A chunk of candidates from the producing thread, or why there is none.
type Produced<F> = Result<Vec<Arc<Candidate>>, F>;

/// What the workers share, under one lock.
struct State<E, T> {
    /// The chunk being cut into groups, and where the next group starts in it.
    chunk: Vec<Arc<Candidate>>,
    next_in_chunk: usize,
    /// No chunk is left to cut (or the run stops).
    exhausted: bool,
    /// Groups handed to workers so far; the next group's index.
    taken: usize,
    /// Groups scored but not yet consumed, by index.
    ready: BTreeMap<usize, Vec<T>>,
    /// The next group to consume, and how many are consumed.
    consumed: usize,
    /// Whether a worker is consuming (only one does at a time, in group order).
    consuming: bool,
    /// How many workers wait for room.
    waiting: usize,
    /// The first error (of the candidates or of `consume`), or a panic: the run stops.
    failure: Option<Stop<E>>,
}

/// Why the run stops early.
enum Stop<E> {
    Failed(E),
    Panicked,
}

/// The pipeline's shared parts.
struct Pipeline<'a, F, E, K, T> {
    state: Mutex<State<E, T>>,
    /// Signalled when groups are consumed or the run stops (a worker may wait for room).
    room: Condvar,
    /// The producing thread's chunks; one worker at a time fetches the next.
    chunks: Mutex<Receiver<Produced<F>>>,
    /// The caller's `consume`, called by the worker on duty.
    consume: Mutex<K>,
    group: usize,
    window: usize,
    score: &'a Score<'a, T>,
    /// The caller's span, the parent of the workers' `hand on results`.
    phase: tracing::Span,
}

/// The pipeline: the candidates are produced on a thread of their own, and every worker of
/// the rayon pool takes the next group, scores it and leaves its results in a reorder buffer.
/// Whichever worker finds the oldest unconsumed group ready consumes it and every ready group
/// after it, in order, while the others keep scoring; a worker that would run more than
/// [`IN_FLIGHT`] candidates ahead of the consumed ones waits for room. A panic while scoring or
/// consuming stops the run and is raised again on the caller's thread. The producing thread's
/// work is marked by the span `produce candidates`, the consuming by `hand on results`.
fn pipelined<C, E, T: Send>(
    candidates: &C,
    group: usize,
    score: &Score<'_, T>,
    consume: impl FnMut(T) -> Result<(), E> + Send,
) -> Result<(), E>
where
    C: CandidateChunks + ?Sized,
    E: From<C::Error> + Send,
{
    let phase = tracing::Span::current();
    std::thread::scope(|threads| {
        let (send, chunks) = sync_channel::<Produced<C::Error>>(2);
        let parent = phase.clone();
        threads.spawn(move || {
            let _producing = tracing::info_span!(parent: &parent, "produce candidates").entered();
            let produced = candidates.for_each_chunk(STREAM_CHUNK, |chunk| {
                send.send(Ok(chunk.to_vec())).map_err(|_| Halt::WorkersGone)
            });
            if let Err(Halt::Source(error)) = produced {
                // The workers may have stopped already: they need the error no more then.
                let _ = send.send(Err(error));
            }
        });
        // Dropped before the producing thread is joined, even by a panic: a producer waiting
        // to send then stops.
        let pipeline = Pipeline {
            state: Mutex::new(State {
                chunk: Vec::new(),
                next_in_chunk: 0,
                exhausted: false,
                taken: 0,
                ready: BTreeMap::new(),
                consumed: 0,
                consuming: false,
                waiting: 0,
                failure: None,
            }),
            room: Condvar::new(),
            chunks: Mutex::new(chunks),
            consume: Mutex::new(consume),
            group,
            window: (IN_FLIGHT / group).max(2),
            score,
            phase,
        };
        rayon::broadcast(|_| pipeline.work());
        let state = pipeline
            .state
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner);
        match state.failure {
            Some(Stop::Failed(error)) => Err(error),
            // A panic is raised again by `broadcast` before this point.
            Some(Stop::Panicked) | None => Ok(()),
        }
    })
}

impl<F, E, K, T> Pipeline<'_, F, E, K, T>
where
    E: From<F>,
    K: FnMut(T) -> Result<(), E>,
{
    fn lock(&self) -> MutexGuard<'_, State<E, T>> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// One worker's loop: take a group, score it, hand its results on and take the next group
    /// (under one lock), until none is left or the run stops.
    fn work(&self) {
        let _stop_on_panic = StopOnPanic(self);
        let mut next = self.take(self.lock());
        while let Some((index, members)) = next {
            let scores = (self.score)(&members);
            next = self.take(self.hand_on(index, scores));
        }
    }

    /// The next group and its index, once there is room for it; `None` when every candidate is
    /// taken or the run stops.
    fn take<'s>(
        &'s self,
        mut state: MutexGuard<'s, State<E, T>>,
    ) -> Option<(usize, Vec<Arc<Candidate>>)> {
        loop {
            while state.failure.is_none() && state.taken - state.consumed >= self.window {
                state.waiting += 1;
                state = self
                    .room
                    .wait(state)
                    .unwrap_or_else(PoisonError::into_inner);
                state.waiting -= 1;
            }
            if state.failure.is_some() {
                return None;
            }
            if state.next_in_chunk < state.chunk.len() {
                let start = state.next_in_chunk;
                let end = (start + self.group).min(state.chunk.len());
                state.next_in_chunk = end;
                let index = state.taken;
                state.taken += 1;
                return Some((index, state.chunk[start..end].to_vec()));
            }
            if state.exhausted {
                return None;
            }
            drop(state);
            self.fetch_chunk();
            state = self.lock();
        }
    }

    /// Installs the producing thread's next chunk, unless another worker did meanwhile.
    fn fetch_chunk(&self) {
        let chunks = self.chunks.lock().unwrap_or_else(PoisonError::into_inner);
        {
            let state = self.lock();
            if state.next_in_chunk < state.chunk.len() || state.exhausted {
                return;
            }
        }
        // The producing thread has ended when nothing more comes.
        let next = chunks.recv().ok();
        let mut state = self.lock();
        match next {
            Some(Ok(chunk)) => {
                state.chunk = chunk;
                state.next_in_chunk = 0;
            }
            Some(Err(error)) => {
                state.exhausted = true;
                state.failure.get_or_insert(Stop::Failed(E::from(error)));
                self.wake_waiting(&state);
            }
            None => state.exhausted = true,
        }
    }

    /// Leaves a group's results for consumption and, when no other worker is consuming,
    /// consumes every ready group in order (unlocked while `consume` runs). Returns the lock.
    fn hand_on(&self, index: usize, scores: Vec<T>) -> MutexGuard<'_, State<E, T>> {
        let mut state = self.lock();
        if state.failure.is_some() {
            return state;
        }
        state.ready.insert(index, scores);
        if state.consuming {
            return state;
        }
        state.consuming = true;
        loop {
            let mut batch = Vec::new();
            let mut next = state.consumed;
            while let Some(scores) = state.ready.remove(&next) {
                batch.push(scores);
                next += 1;
            }
            if batch.is_empty() || state.failure.is_some() {
                state.consuming = false;
                return state;
            }
            drop(state);
            let consumed = {
                let _handing_on =
                    tracing::info_span!(parent: &self.phase, "hand on results").entered();
                let mut consume = self.consume.lock().unwrap_or_else(PoisonError::into_inner);
                batch
                    .into_iter()
                    .flatten()
                    .try_for_each(|score| (*consume)(score))
            };
            state = self.lock();
            state.consumed = next;
            if let Err(error) = consumed {
                state.failure.get_or_insert(Stop::Failed(error));
            }
            self.wake_waiting(&state);
        }
    }

    /// Wakes the workers waiting for room, if any (a wake-up is a system call).
    fn wake_waiting(&self, state: &State<E, T>) {
        if state.waiting > 0 {
            self.room.notify_all();
        }
    }
}

/// Stops the run when its worker unwinds from a panic, so that no other worker waits for room
/// that the panicking one would have made.
struct StopOnPanic<'p, 'a, F, E, K, T>(&'p Pipeline<'a, F, E, K, T>);

impl<F, E, K, T> Drop for StopOnPanic<'_, '_, F, E, K, T> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            let mut state = self.0.state.lock().unwrap_or_else(PoisonError::into_inner);
            state.failure.get_or_insert(Stop::Panicked);
            state.consuming = false;
            self.0.room.notify_all();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Isometry3;
    use std::sync::atomic::{AtomicUsize, Ordering};

    fn candidates(n: usize) -> Vec<Arc<Candidate>> {
        (0..n)
            .map(|id| {
                Arc::new(Candidate {
                    id,
                    label: format!("c{id}"),
                    object_from_wrist: Isometry3::identity(),
                    log_likelihood: 0.0,
                    contact: None,
                    hand_joints: Vec::new(),
                    width: None,
                })
            })
            .collect()
    }

    /// Work whose cost varies a lot from candidate to candidate (some groups are 50 times
    /// slower than others), so that groups finish out of order.
    fn uneven(id: usize) -> usize {
        let rounds = if id.is_multiple_of(37) { 50_000 } else { 1_000 };
        (0..rounds).fold(id, |acc, k| std::hint::black_box(acc ^ k).rotate_left(1)) ^ id
    }

    fn score(members: &[Arc<Candidate>]) -> Vec<(usize, usize)> {
        members.iter().map(|c| (c.id, uneven(c.id))).collect()
    }

    /// A source that fails after `good` chunks.
    struct Failing {
        held: Vec<Arc<Candidate>>,
        good: usize,
    }

    impl CandidateChunks for Failing {
        type Error = String;

        fn count(&self) -> usize {
            self.held.len()
        }

        fn for_each_chunk<E: From<String>>(
            &self,
            size: usize,
            mut consume: impl FnMut(&[Arc<Candidate>]) -> Result<(), E>,
        ) -> Result<(), E> {
            for (k, chunk) in self.held.chunks(size).enumerate() {
                if k == self.good {
                    return Err(E::from(format!("chunk {k} cannot be read")));
                }
                consume(chunk)?;
            }
            Ok(())
        }
    }

    #[test]
    fn the_pipeline_hands_every_result_on_once_in_order_and_equal_to_chunk_by_chunk() {
        let held = candidates(3 * STREAM_CHUNK + 41);
        for group in [1, 3, 16] {
            let (mut piped, mut chunked) = (Vec::new(), Vec::new());
            let Ok(()) = pipelined::<_, Infallible, _>(&held[..], group, &score, |r| {
                piped.push(r);
                Ok(())
            });
            let Ok(()) = chunk_by_chunk::<_, Infallible, _>(&held[..], group, &score, |r| {
                chunked.push(r);
                Ok(())
            });
            let want: Vec<(usize, usize)> = (0..held.len()).map(|id| (id, uneven(id))).collect();
            assert_eq!(piped, want, "group {group}");
            assert_eq!(chunked, want, "group {group}");
        }
    }

    #[test]
    fn the_pipeline_holds_at_most_its_window_of_results_unconsumed() {
        let held = candidates(20 * STREAM_CHUNK);
        let (scored, consumed, most) = (
            AtomicUsize::new(0),
            AtomicUsize::new(0),
            AtomicUsize::new(0),
        );
        let counting = |members: &[Arc<Candidate>]| {
            let results = score(members);
            let ahead = scored.fetch_add(results.len(), Ordering::SeqCst) + results.len()
                - consumed.load(Ordering::SeqCst);
            most.fetch_max(ahead, Ordering::SeqCst);
            results
        };
        let Ok(()) = pipelined::<_, Infallible, _>(&held[..], 4, &counting, |_| {
            // A slow consumer: the other workers score ahead until the window is full.
            std::hint::black_box((0..20).map(uneven).fold(0, usize::wrapping_add));
            consumed.fetch_add(1, Ordering::SeqCst);
            Ok(())
        });
        assert_eq!(consumed.load(Ordering::SeqCst), held.len());
        let most = most.load(Ordering::SeqCst);
        assert!(most <= IN_FLIGHT, "{most} results were unconsumed at once");
        if rayon::current_num_threads() > 1 {
            // The bound was reached, so it is what held the scorers back.
            assert!(most > IN_FLIGHT / 2, "only {most} results ran ahead");
        }
    }

    #[test]
    fn an_error_of_the_candidates_ends_the_pipeline_after_the_results_before_it() {
        let source = Failing {
            held: candidates(6 * STREAM_CHUNK),
            good: 3,
        };
        let mut seen = Vec::new();
        let result = pipelined::<_, String, _>(&source, 16, &score, |(id, _)| {
            seen.push(id);
            Ok(())
        });
        assert_eq!(result, Err("chunk 3 cannot be read".to_string()));
        assert!(seen.len() <= 3 * STREAM_CHUNK);
        assert_eq!(seen, (0..seen.len()).collect::<Vec<_>>());
    }

    #[test]
    fn an_error_of_consume_stops_the_pipeline_with_it() {
        let source = Failing {
            held: candidates(8 * STREAM_CHUNK),
            good: usize::MAX,
        };
        let mut seen = 0;
        let result = pipelined::<_, String, _>(&source, 16, &score, |(id, _)| {
            if id == 700 {
                return Err(format!("cannot write candidate {id}"));
            }
            seen += 1;
            Ok(())
        });
        assert_eq!(result, Err("cannot write candidate 700".to_string()));
        assert_eq!(seen, 700);
    }

    #[test]
    fn a_panic_while_scoring_is_raised_on_the_caller_without_a_hang() {
        let held = candidates(8 * STREAM_CHUNK);
        let panicking = |members: &[Arc<Candidate>]| {
            assert!(members.iter().all(|c| c.id != 900), "candidate 900 panics");
            score(members)
        };
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            pipelined::<_, Infallible, _>(&held[..], 16, &panicking, |_| Ok(()))
        }));
        let payload = outcome.expect_err("the panic reaches the caller");
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or_default();
        assert!(message.contains("candidate 900 panics"), "{message}");
    }
}
