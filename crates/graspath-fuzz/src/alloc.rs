//! A counting global allocator with two bounds: a single allocation above [`single_limit`]
//! bytes, or live memory above [`total_limit`] bytes, is a finding.
//!
//! Rust on stable cannot turn an allocation failure into a panic (`handle_alloc_error`
//! aborts), and an allocator must not unwind. So when a bound is crossed the allocator does not
//! return: it captures where the request came from (a backtrace, taken with counting switched
//! off for this thread), hands the message to the handler installed by the worker process
//! ([`set_over_limit_handler`]), which writes it beside the input saved before the execution,
//! and exits the worker with a distinctive code. The parent process then records the finding
//! and starts a new worker at the next input. Without a handler (the parent, the replay of a
//! clean input) crossing a bound just passes the request on to the system allocator.
//!
//! While a signal handler captures where its thread is (the watchdog's hang report; the thread
//! may have been interrupted inside `malloc`), that thread's allocations come from a static
//! bump arena and its frees are ignored, so that the handler never re-enters the system
//! allocator's locks. Arena blocks are never freed (the process exits right after a report).
//!
//! Install it in a binary with `#[global_allocator] static A: LimitAlloc = LimitAlloc;`.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// The default bound on one allocation: 1 GiB.
pub const DEFAULT_SINGLE_LIMIT: usize = 1 << 30;
/// The default bound on live (allocated and not yet freed) memory: 4 GiB.
pub const DEFAULT_TOTAL_LIMIT: usize = 4 << 30;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
static SINGLE_LIMIT: AtomicUsize = AtomicUsize::new(DEFAULT_SINGLE_LIMIT);
static TOTAL_LIMIT: AtomicUsize = AtomicUsize::new(DEFAULT_TOTAL_LIMIT);

type Handler = Box<dyn Fn(String) + Send + Sync>;
static HANDLER: OnceLock<Handler> = OnceLock::new();

thread_local! {
    /// Set while this thread reports a finding: its allocations are neither checked nor
    /// reported again.
    static REPORTING: Cell<bool> = const { Cell::new(false) };
    /// Set while this thread runs a signal handler: its allocations come from the arena.
    static IN_HANDLER: Cell<bool> = const { Cell::new(false) };
}

/// The counting allocator (see the module documentation).
pub struct LimitAlloc;

const ARENA_SIZE: usize = 64 << 20;

struct Arena(std::cell::UnsafeCell<[u8; ARENA_SIZE]>);

// SAFETY: disjoint ranges of the arena are handed out through an atomic bump pointer.
unsafe impl Sync for Arena {}

static ARENA: Arena = Arena(std::cell::UnsafeCell::new([0; ARENA_SIZE]));
static ARENA_USED: AtomicUsize = AtomicUsize::new(0);

/// Whether `ptr` is a block of the reporting arena (such blocks are never freed).
fn in_arena(ptr: *mut u8) -> bool {
    let base = ARENA.0.get() as usize;
    (base..base + ARENA_SIZE).contains(&(ptr as usize))
}

/// A block of the reporting arena (null when it is exhausted).
fn arena_alloc(layout: Layout) -> *mut u8 {
    let base = ARENA.0.get() as usize;
    let mut used = ARENA_USED.load(Ordering::Relaxed);
    loop {
        let start = (base + used).next_multiple_of(layout.align()) - base;
        let end = start + layout.size();
        if end > ARENA_SIZE {
            return std::ptr::null_mut();
        }
        match ARENA_USED.compare_exchange(used, end, Ordering::AcqRel, Ordering::Relaxed) {
            // The arena is zero-initialised and never reused, so blocks are zeroed too.
            Ok(_) => return (base + start) as *mut u8,
            Err(now) => used = now,
        }
    }
}

/// Bytes currently allocated through [`LimitAlloc`].
pub fn live_bytes() -> usize {
    LIVE.load(Ordering::Relaxed)
}

/// The highest [`live_bytes`] seen since the last [`reset_peak`].
pub fn peak_bytes() -> usize {
    PEAK.load(Ordering::Relaxed)
}

/// Starts a new peak measurement at the current live size.
pub fn reset_peak() {
    PEAK.store(live_bytes(), Ordering::Relaxed);
}

/// The bound on one allocation (bytes).
pub fn single_limit() -> usize {
    SINGLE_LIMIT.load(Ordering::Relaxed)
}

/// The bound on live memory (bytes).
pub fn total_limit() -> usize {
    TOTAL_LIMIT.load(Ordering::Relaxed)
}

/// Sets both bounds (bytes).
pub fn set_limits(single: usize, total: usize) {
    SINGLE_LIMIT.store(single, Ordering::Relaxed);
    TOTAL_LIMIT.store(total, Ordering::Relaxed);
}

/// Installs the function called (once, then it must not return) when a bound is crossed. It
/// receives a one-line message: the size, the bound and the first frames outside the standard
/// library and this crate.
pub fn set_over_limit_handler(handler: impl Fn(String) + Send + Sync + 'static) {
    let _ = HANDLER.set(Box::new(handler));
}

/// Marks this thread as running a signal handler (its allocations come from the arena and
/// pass unchecked, its frees are ignored) or not.
pub fn set_in_handler(on: bool) {
    let _ = IN_HANDLER.try_with(|r| r.set(on));
}

fn in_handler() -> bool {
    IN_HANDLER.try_with(Cell::get).unwrap_or(false)
}

fn reporting() -> bool {
    REPORTING.try_with(Cell::get).unwrap_or(false) || in_handler()
}

/// The first frames of the current backtrace that belong to the code under test.
pub fn caller_frames(max: usize) -> Vec<String> {
    frames_of_trace(&std::backtrace::Backtrace::force_capture(), max)
}

/// The first frames of a captured backtrace that belong to the code under test (symbols are
/// resolved here, which allocates much more than the capture itself).
pub fn frames_of_trace(trace: &std::backtrace::Backtrace, max: usize) -> Vec<String> {
    let trace = trace.to_string();
    let mut frames = Vec::new();
    for line in trace.lines() {
        let line = line.trim();
        // Frame lines are "N: symbol"; "at file:line" lines follow them.
        let Some((number, symbol)) = line.split_once(": ") else {
            continue;
        };
        if number.parse::<usize>().is_err() {
            continue;
        }
        let symbol = symbol.trim();
        // The allocator's own frames and the standard library are skipped; the first frame
        // of the harness (the target function) ends the caller's part of the stack.
        let skip = [
            "std::",
            "core::",
            "alloc::",
            "<alloc::",
            "<core::",
            "<std::",
            "graspath_fuzz::alloc",
            "<graspath_fuzz::alloc",
            "graspath_fuzz::exec",
            "<graspath_fuzz::exec",
            "__rust",
            "rust_",
            "<unknown>",
            "__restore_rt",
            "rayon_core::",
            "<rayon_core::",
            "rayon::",
            "<rayon::",
            "crossbeam",
        ];
        if skip.iter().any(|s| symbol.starts_with(s))
            || [" as alloc::", " as core::", " as std::"]
                .iter()
                .any(|s| symbol.contains(s))
        {
            continue;
        }
        if symbol.contains("graspath_fuzz") || symbol == "main" || symbol.starts_with("<&dyn") {
            break;
        }
        // Strip the trailing hash `::h0123456789abcdef`.
        let symbol = match symbol.rfind("::h") {
            Some(at) if symbol.len() - at == 19 => &symbol[..at],
            _ => symbol,
        };
        frames.push(symbol.to_string());
        if frames.len() == max {
            break;
        }
    }
    frames
}

/// The frame that identifies a failure (the first one in graspath itself, else the first
/// one), and the frames to print: up to that frame and two of its callers (at most eight,
/// the middle elided).
pub fn key_frames(frames: &[String]) -> (String, String) {
    let key = frames
        .iter()
        .position(|f| f.starts_with("graspath::") || f.starts_with("<graspath::"))
        .unwrap_or(0);
    let end = frames.len().min(key + 3);
    let shown = if end <= 8 {
        frames[..end].to_vec()
    } else {
        let mut v = frames[..3].to_vec();
        v.push("…".to_string());
        v.extend_from_slice(&frames[end - 5..end]);
        v
    };
    (
        frames.get(key).cloned().unwrap_or_default(),
        shown.join(" < "),
    )
}

#[cold]
fn over_limit(size: usize, live: usize) {
    if HANDLER.get().is_none() {
        return;
    }
    let _ = REPORTING.try_with(|r| r.set(true));
    let single = single_limit();
    let what = if size > single {
        format!("allocation of {size} bytes exceeds the single-allocation bound of {single} bytes")
    } else {
        format!(
            "live memory would reach {} bytes, above the bound of {} bytes",
            live.saturating_add(size),
            total_limit()
        )
    };
    let (_, frames) = key_frames(&caller_frames(32));
    let message = if frames.is_empty() {
        what
    } else {
        format!("{what} at {frames}")
    };
    if let Some(handler) = HANDLER.get() {
        handler(message);
    }
    let _ = REPORTING.try_with(|r| r.set(false));
}

#[inline]
fn check(size: usize) {
    let live = LIVE.load(Ordering::Relaxed);
    if (size > SINGLE_LIMIT.load(Ordering::Relaxed)
        || live.saturating_add(size) > TOTAL_LIMIT.load(Ordering::Relaxed))
        && !reporting()
    {
        over_limit(size, live);
    }
}

#[inline]
fn added(size: usize) {
    let now = LIVE.fetch_add(size, Ordering::Relaxed) + size;
    if now > PEAK.load(Ordering::Relaxed) {
        PEAK.store(now, Ordering::Relaxed);
    }
}

// SAFETY: every request is passed unchanged to `System`, except while the thread reports,
// when blocks come from the arena (never freed) — see the module documentation.
unsafe impl GlobalAlloc for LimitAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if in_handler() {
            return arena_alloc(layout);
        }
        check(layout.size());
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            added(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if in_handler() {
            return arena_alloc(layout);
        }
        check(layout.size());
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            added(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        if in_handler() || in_arena(ptr) {
            return;
        }
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if in_handler() {
            // SAFETY: the caller guarantees a valid layout for `new_size`.
            let new_layout = unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) };
            let p = arena_alloc(new_layout);
            if !p.is_null() {
                // SAFETY: both blocks are valid for the copied length and do not overlap.
                unsafe { std::ptr::copy_nonoverlapping(ptr, p, layout.size().min(new_size)) };
            }
            return p;
        }
        if in_arena(ptr) {
            // A block from a report, grown by another thread: move it to the system heap.
            // SAFETY: the caller guarantees a valid layout for `new_size`.
            let new_layout = unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) };
            let p = unsafe { self.alloc(new_layout) };
            if !p.is_null() {
                // SAFETY: both blocks are valid for the copied length and do not overlap.
                unsafe { std::ptr::copy_nonoverlapping(ptr, p, layout.size().min(new_size)) };
            }
            return p;
        }
        if new_size > layout.size() {
            if new_size > SINGLE_LIMIT.load(Ordering::Relaxed) {
                check(new_size);
            } else {
                check(new_size - layout.size());
            }
        }
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
            added(new_size);
        }
        p
    }
}
