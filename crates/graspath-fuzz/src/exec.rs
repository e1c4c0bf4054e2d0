//! One execution under the three oracles, inside a worker process.
//!
//! * **panic**: the target runs under `catch_unwind`; a panic hook records the message and
//!   location (from any thread, e.g. a rayon worker), and the input is saved by the worker.
//! * **hang**: a watchdog thread checks every 20 ms how long the current execution has run;
//!   past the time limit it interrupts the executing thread with `SIGUSR1`, whose handler
//!   records where that thread is (the first frames of the code under test, for the
//!   signature), then writes the finding to the death file and exits the process with
//!   [`EXIT_HANG`] (a running thread cannot be stopped safely). If the handler cannot finish
//!   within a second (it allocates, and the thread may have been interrupted inside the
//!   allocator), the finding is written without the frames.
//! * **allocation**: the counting allocator ([`crate::alloc`]) calls the handler installed
//!   here, which writes the finding to the death file and exits with [`EXIT_ALLOC`].
//!
//! Before each execution the input is written to the *current* file (`[index u64][len
//! u64][bytes]`, one positioned write), so that whatever ends the process — a bound, the
//! watchdog, a stack overflow, an abort, the kernel's OOM killer — the parent knows which input
//! did it.

use crate::targets::{Ctx, Target};
use std::fs::File;
use std::os::unix::fs::FileExt;
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Exit code of a worker stopped by an allocation bound.
pub const EXIT_ALLOC: i32 = 86;
/// Exit code of a worker stopped by the watchdog.
pub const EXIT_HANG: i32 = 87;
/// Exit code of a replay whose input panicked.
pub const EXIT_PANIC: i32 = 85;

/// What kind of failure a finding is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A panic (caught).
    Panic,
    /// An allocation above a bound.
    Alloc,
    /// An execution longer than the time limit.
    Hang,
    /// The process died otherwise (signal, abort, stack overflow).
    Crash,
}

impl Kind {
    /// The lower-case name used in files and messages.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Panic => "panic",
            Kind::Alloc => "alloc",
            Kind::Hang => "hang",
            Kind::Crash => "crash",
        }
    }

    /// The kind named `name`.
    pub fn parse(name: &str) -> Option<Self> {
        [Kind::Panic, Kind::Alloc, Kind::Hang, Kind::Crash]
            .into_iter()
            .find(|k| k.name() == name)
    }
}

/// One failure: its kind, a signature for de-duplication (where it happened), and the full
/// one-line message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Failure {
    /// The kind.
    pub kind: Kind,
    /// `panic at src/file.rs:12`, `alloc at graspath::cloud::pcd::read_pcd_bytes`, `hang`.
    pub signature: String,
    /// The message, one line.
    pub message: String,
}

impl Failure {
    /// The three-line form written to death files.
    pub fn to_record(&self) -> String {
        format!(
            "{}\n{}\n{}\n",
            self.kind.name(),
            self.signature,
            one_line(&self.message)
        )
    }

    /// Parses [`Failure::to_record`].
    pub fn from_record(text: &str) -> Option<Self> {
        let mut lines = text.lines();
        Some(Self {
            kind: Kind::parse(lines.next()?)?,
            signature: lines.next()?.to_string(),
            message: lines.next().unwrap_or("").to_string(),
        })
    }
}

/// `text` on one line (newlines and tabs replaced by spaces), at most 600 characters.
pub fn one_line(text: &str) -> String {
    let flat: String = text
        .chars()
        .map(|c| {
            if c == '\n' || c == '\t' || c == '\r' {
                ' '
            } else {
                c
            }
        })
        .collect();
    match flat.char_indices().nth(600) {
        Some((at, _)) => format!("{}…", &flat[..at]),
        None => flat,
    }
}

static LAST_PANIC: Mutex<Option<(String, String)>> = Mutex::new(None);

/// Where the interrupted thread was, as set by [`on_sigusr1`] (a leaked, unresolved
/// backtrace).
static HANG_TRACE: std::sync::atomic::AtomicPtr<std::backtrace::Backtrace> =
    std::sync::atomic::AtomicPtr::new(std::ptr::null_mut());

extern "C" fn on_sigusr1(_: libc::c_int) {
    // Not async-signal-safe, but close: the stack is only walked here (its few allocations
    // come from the reporting arena, never from malloc, whose lock the interrupted code may
    // hold); symbols are resolved by the watchdog thread. The process exits right after, and
    // the watchdog waits at most a second.
    crate::alloc::set_in_handler(true);
    let trace = Box::new(std::backtrace::Backtrace::force_capture());
    HANG_TRACE.store(Box::into_raw(trace), Ordering::Release);
    // The interrupted code resumes until the watchdog exits: back to the system heap.
    crate::alloc::set_in_handler(false);
}

/// Interrupts `thread` and returns where it is (the first frames of the code under test).
fn frames_of(thread: libc::pthread_t) -> Option<String> {
    // SAFETY: installing a handler for SIGUSR1, which nothing else in this process uses, and
    // signalling a thread that is alive (the executing thread, blocked in the execution).
    unsafe {
        let handler: extern "C" fn(libc::c_int) = on_sigusr1;
        libc::signal(libc::SIGUSR1, handler as libc::sighandler_t);
        libc::pthread_kill(thread, libc::SIGUSR1);
    }
    let waited = Instant::now();
    while waited.elapsed() < Duration::from_secs(1) {
        let p = HANG_TRACE.load(Ordering::Acquire);
        if !p.is_null() {
            // SAFETY: the pointer comes from Box::into_raw in the handler and is read once;
            // it is leaked (the handler's arena memory must not reach `free`).
            let trace: &std::backtrace::Backtrace = unsafe { &*p };
            return Some(crate::alloc::frames_of_trace(trace, 32).join("\n"));
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    None
}

/// A path shortened to what identifies it: from the crate directory on
/// (`graspath/src/cloud/pcd.rs`, `pcd-rs-0.13.0/src/reader.rs`).
fn short_path(file: &str) -> String {
    let parts: Vec<&str> = file.split('/').collect();
    match parts.iter().rposition(|p| *p == "src") {
        Some(i) if i > 0 => parts[i - 1..].join("/"),
        _ => file.to_string(),
    }
}

/// Installs the panic hook that records (instead of printing) the last panic.
pub fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let mut location = info
            .location()
            .map(|l| format!("{}:{}", short_path(l.file()), l.line()))
            .unwrap_or_else(|| "unknown location".into());
        // A panic located in the standard library (capacity overflow, a failed allocation
        // size computation) is identified by the code that called it.
        if ["alloc/", "core/", "std/"]
            .iter()
            .any(|p| location.starts_with(p))
        {
            if let Some(caller) = crate::alloc::caller_frames(1).first() {
                location = format!("{location} in {caller}");
            }
        }
        let payload = info.payload();
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "non-string panic payload".into());
        if let Ok(mut last) = LAST_PANIC.lock() {
            *last = Some((location, message));
        }
    }));
}

/// The worker-side executor: current-input file, death file and watchdog.
pub struct Executor {
    current: File,
    started_ms: Arc<AtomicU64>,
    epoch: Instant,
    buffer: Vec<u8>,
}

fn write_death(path: &Path, failure: &Failure) {
    let _ = std::fs::write(path, failure.to_record());
}

impl Executor {
    /// Sets up the oracles: `current` receives each input before it runs, `death` the finding
    /// that ends the process; executions longer than `timeout` are hangs.
    pub fn new(current: &Path, death: &Path, timeout: Duration) -> std::io::Result<Self> {
        let _ = std::fs::remove_file(death);
        let current = File::create(current)?;
        install_panic_hook();
        let death_for_alloc: PathBuf = death.to_path_buf();
        crate::alloc::set_over_limit_handler(move |message| {
            let signature = match message.split_once(" at ") {
                Some((_, frames)) => {
                    let list: Vec<String> = frames.split(" < ").map(str::to_string).collect();
                    let key = crate::alloc::key_frames(&list).0;
                    match list.first() {
                        Some(first) if *first != key => format!("alloc at {first} in {key}"),
                        _ => format!("alloc at {key}"),
                    }
                }
                None => "alloc".to_string(),
            };
            write_death(
                &death_for_alloc,
                &Failure {
                    kind: Kind::Alloc,
                    signature,
                    message,
                },
            );
            std::process::exit(EXIT_ALLOC);
        });
        let started_ms = Arc::new(AtomicU64::new(0));
        let epoch = Instant::now();
        let watched = Arc::clone(&started_ms);
        let death_for_hang = death.to_path_buf();
        let limit_ms = timeout.as_millis() as u64;
        // SAFETY: pthread_self has no preconditions.
        let executing = unsafe { libc::pthread_self() };
        std::thread::Builder::new()
            .name("watchdog".into())
            .spawn(move || loop {
                std::thread::sleep(Duration::from_millis(20));
                let started = watched.load(Ordering::Acquire);
                let now = epoch.elapsed().as_millis() as u64 + 1;
                if started != 0 && now.saturating_sub(started) > limit_ms {
                    let frames = frames_of(executing).filter(|f| !f.is_empty());
                    let (signature, place) = match &frames {
                        Some(f) => {
                            let list: Vec<String> = f.lines().map(str::to_string).collect();
                            let (key, shown) = crate::alloc::key_frames(&list);
                            (format!("hang in {key}"), format!(" in {shown}"))
                        }
                        None => ("hang".to_string(), String::new()),
                    };
                    write_death(
                        &death_for_hang,
                        &Failure {
                            kind: Kind::Hang,
                            signature,
                            message: format!("no result after {limit_ms} ms (time limit){place}"),
                        },
                    );
                    std::process::exit(EXIT_HANG);
                }
            })?;
        Ok(Self {
            current,
            started_ms,
            epoch,
            buffer: Vec::new(),
        })
    }

    /// Runs `input` (number `index`) on `target`; a caught panic is returned, any other
    /// finding ends the process.
    pub fn execute(
        &mut self,
        target: &Target,
        ctx: &Ctx,
        index: u64,
        input: &[u8],
    ) -> Option<Failure> {
        self.buffer.clear();
        self.buffer.extend_from_slice(&index.to_le_bytes());
        self.buffer
            .extend_from_slice(&(input.len() as u64).to_le_bytes());
        self.buffer.extend_from_slice(input);
        // If the input cannot be saved, a crash would be reported without it: stop instead.
        if let Err(e) = self.current.write_all_at(&self.buffer, 0) {
            eprintln!("graspath-fuzz: cannot save the current input: {e}");
            std::process::exit(2);
        }
        if let Ok(mut last) = LAST_PANIC.lock() {
            *last = None;
        }
        self.started_ms.store(
            self.epoch.elapsed().as_millis() as u64 + 1,
            Ordering::Release,
        );
        let result = std::panic::catch_unwind(AssertUnwindSafe(|| (target.run)(ctx, input)));
        self.started_ms.store(0, Ordering::Release);
        result.err().map(|_| {
            let (location, message) = LAST_PANIC
                .lock()
                .ok()
                .and_then(|mut l| l.take())
                .unwrap_or_else(|| ("unknown location".into(), "panic".into()));
            Failure {
                kind: Kind::Panic,
                signature: format!("panic at {location}"),
                message: one_line(&format!("panic at {location}: {message}")),
            }
        })
    }
}

/// Reads a current-input file: the index and the bytes of the input that was running.
pub fn read_current(path: &Path) -> Option<(u64, Vec<u8>)> {
    let bytes = std::fs::read(path).ok()?;
    let index = u64::from_le_bytes(bytes.get(0..8)?.try_into().ok()?);
    let len = u64::from_le_bytes(bytes.get(8..16)?.try_into().ok()?) as usize;
    Some((index, bytes.get(16..16 + len)?.to_vec()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_round_trip() {
        let f = Failure {
            kind: Kind::Alloc,
            signature: "alloc at graspath::x".into(),
            message: "allocation of 5 bytes\nsecond line".into(),
        };
        let back = Failure::from_record(&f.to_record()).unwrap();
        assert_eq!(back.kind, Kind::Alloc);
        assert_eq!(back.signature, f.signature);
        assert_eq!(back.message, "allocation of 5 bytes second line");
    }

    #[test]
    fn short_paths_keep_the_crate() {
        assert_eq!(
            short_path("/root/.cargo/registry/src/index/pcd-rs-0.13.0/src/reader.rs"),
            "pcd-rs-0.13.0/src/reader.rs"
        );
        assert_eq!(
            short_path("crates/graspath/src/cloud/pcd.rs"),
            "graspath/src/cloud/pcd.rs"
        );
    }
}
