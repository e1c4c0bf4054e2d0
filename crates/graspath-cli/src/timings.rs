//! `--timings`: where a run's time went, phase by phase. The library and the commands mark
//! their phases as `tracing` spans (target `graspath…`); this subscriber times every entry of
//! those spans — the wall clock, the CPU time of the whole process and that of the thread
//! that entered it — and prints one line per phase on stderr when the run ends. The process's
//! CPU time over its wall time is how many threads were busy in a phase: 1.0 in a serial
//! phase, up to the thread count in a parallel one. Nothing is timed, and the spans cost a
//! check each, when `--timings` is not given.

use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};
use tracing::span::{Attributes, Id, Record};
use tracing::{Event, Metadata, Subscriber};
use tracing_core::span::Current;

/// The CPU time used so far by the whole process (`thread: false`) or by the calling thread;
/// `None` where the system does not tell it.
#[cfg(unix)]
fn cpu_time(thread: bool) -> Option<Duration> {
    let clock = if thread {
        libc::CLOCK_THREAD_CPUTIME_ID
    } else {
        libc::CLOCK_PROCESS_CPUTIME_ID
    };
    let mut now = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `now` is a valid, writable timespec for the duration of the call.
    let status = unsafe { libc::clock_gettime(clock, &mut now) };
    (status == 0).then(|| {
        Duration::new(
            u64::try_from(now.tv_sec).unwrap_or(0),
            u32::try_from(now.tv_nsec).unwrap_or(0),
        )
    })
}

#[cfg(not(unix))]
fn cpu_time(_thread: bool) -> Option<Duration> {
    None
}

/// A point in time on the three clocks.
#[derive(Debug, Clone, Copy)]
struct Stamp {
    wall: Instant,
    process: Option<Duration>,
    thread: Option<Duration>,
}

impl Stamp {
    fn now() -> Self {
        Self {
            wall: Instant::now(),
            process: cpu_time(false),
            thread: cpu_time(true),
        }
    }
}

/// What one phase took, over all its entries (a CPU time is `None` once a clock failed).
#[derive(Debug, Clone)]
struct Phase {
    /// How deep the phase's first span was nested in other phases.
    depth: usize,
    /// Whether the phase was entered on the thread that installed the timings (the command's).
    on_command_thread: bool,
    entries: u64,
    wall: Duration,
    process: Option<Duration>,
    thread: Option<Duration>,
}

impl Phase {
    fn new(depth: usize) -> Self {
        Self {
            depth,
            on_command_thread: false,
            entries: 0,
            wall: Duration::ZERO,
            process: Some(Duration::ZERO),
            thread: Some(Duration::ZERO),
        }
    }
}

/// Adds the time from `start` to `end` to `total`.
fn add(total: &mut Option<Duration>, start: Option<Duration>, end: Option<Duration>) {
    *total = total
        .zip(start.zip(end))
        .map(|(total, (s, e))| total + e.saturating_sub(s));
}

/// The phases seen so far, in the order they were first entered.
#[derive(Debug, Default)]
struct Phases {
    order: Vec<String>,
    by_name: HashMap<String, Phase>,
}

/// A span's phase name (the span's name, and its `arm` field when it has one) and how deep it
/// is nested in other spans (its parent's depth plus one).
#[derive(Debug, Clone)]
struct PhaseName {
    name: String,
    depth: usize,
    /// The span's metadata, for [`Subscriber::current_span`].
    metadata: &'static Metadata<'static>,
}

/// A phase a thread is in.
#[derive(Debug)]
struct OpenPhase {
    span: u64,
    name: PhaseName,
    entered: Stamp,
}

thread_local! {
    /// The phases this thread is in, innermost last.
    static OPEN: RefCell<Vec<OpenPhase>> = const { RefCell::new(Vec::new()) };
}

/// A live span: its phase and how many handles to it are open.
#[derive(Debug)]
struct LiveSpan {
    name: PhaseName,
    handles: usize,
}

/// The `tracing` subscriber behind `--timings`.
#[derive(Debug, Default)]
pub(crate) struct Timings {
    next_id: AtomicU64,
    /// Each live span, until its last handle is closed.
    names: Mutex<HashMap<u64, LiveSpan>>,
    phases: Arc<Mutex<Phases>>,
    /// The thread that installed the timings: the command's own.
    command_thread: Option<std::thread::ThreadId>,
}

/// Collects the `arm` field of a span into its phase name.
struct ArmField<'a>(&'a mut String);

impl tracing::field::Visit for ArmField<'_> {
    fn record_debug(&mut self, field: &tracing::field::Field, value: &dyn std::fmt::Debug) {
        if field.name() == "arm" {
            self.0.push_str(&format!(" (arm {value:?})"));
        }
    }

    fn record_str(&mut self, field: &tracing::field::Field, value: &str) {
        if field.name() == "arm" {
            self.0.push_str(&format!(" (arm '{value}')"));
        }
    }
}

impl Subscriber for Timings {
    fn enabled(&self, metadata: &Metadata<'_>) -> bool {
        metadata.is_span() && metadata.target().starts_with("graspath")
    }

    fn new_span(&self, attributes: &Attributes<'_>) -> Id {
        let id = self.next_id.fetch_add(1, Ordering::Relaxed) + 1;
        let mut name = attributes.metadata().name().to_string();
        attributes.record(&mut ArmField(&mut name));
        let parent = match attributes.parent() {
            Some(parent) => Some(parent.into_u64()),
            None if attributes.is_contextual() => {
                OPEN.with(|open| open.borrow().last().map(|phase| phase.span))
            }
            None => None,
        };
        let mut names = self.names.lock().unwrap_or_else(PoisonError::into_inner);
        let depth = parent
            .and_then(|p| names.get(&p))
            .map_or(0, |parent| parent.name.depth + 1);
        let name = PhaseName {
            name,
            depth,
            metadata: attributes.metadata(),
        };
        names.insert(id, LiveSpan { name, handles: 1 });
        Id::from_u64(id)
    }

    fn record(&self, _: &Id, _: &Record<'_>) {}

    fn record_follows_from(&self, _: &Id, _: &Id) {}

    fn event(&self, _: &Event<'_>) {}

    fn current_span(&self) -> Current {
        OPEN.with(|open| match open.borrow().last() {
            Some(phase) => Current::new(Id::from_u64(phase.span), phase.name.metadata),
            None => Current::none(),
        })
    }

    fn enter(&self, span: &Id) {
        let id = span.into_u64();
        let Some(name) = self
            .names
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .get(&id)
            .map(|live| live.name.clone())
        else {
            return;
        };
        // Phases are listed in the order they are first entered.
        let mut phases = self.phases.lock().unwrap_or_else(PoisonError::into_inner);
        if !phases.by_name.contains_key(&name.name) {
            phases.order.push(name.name.clone());
            phases
                .by_name
                .insert(name.name.clone(), Phase::new(name.depth));
        }
        drop(phases);
        OPEN.with(|open| {
            open.borrow_mut().push(OpenPhase {
                span: id,
                name,
                entered: Stamp::now(),
            });
        });
    }

    fn exit(&self, span: &Id) {
        let end = Stamp::now();
        let id = span.into_u64();
        let Some(OpenPhase {
            name: PhaseName { name, .. },
            entered: start,
            ..
        }) = OPEN.with(|open| {
            let mut open = open.borrow_mut();
            let at = open.iter().rposition(|phase| phase.span == id)?;
            Some(open.remove(at))
        })
        else {
            return;
        };
        let mut phases = self.phases.lock().unwrap_or_else(PoisonError::into_inner);
        let Some(phase) = phases.by_name.get_mut(&name) else {
            return;
        };
        phase.on_command_thread |= self.command_thread == Some(std::thread::current().id());
        phase.entries += 1;
        phase.wall += end.wall - start.wall;
        add(&mut phase.process, start.process, end.process);
        add(&mut phase.thread, start.thread, end.thread);
    }

    fn clone_span(&self, span: &Id) -> Id {
        if let Some(live) = self
            .names
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .get_mut(&span.into_u64())
        {
            live.handles += 1;
        }
        span.clone()
    }

    fn try_close(&self, span: Id) -> bool {
        let mut names = self.names.lock().unwrap_or_else(PoisonError::into_inner);
        let id = span.into_u64();
        let closed = names.get_mut(&id).is_some_and(|live| {
            live.handles -= 1;
            live.handles == 0
        });
        if closed {
            names.remove(&id);
        }
        closed
    }
}

/// Timings installed for the rest of the process, and what they report.
pub(crate) struct Recorder {
    phases: Arc<Mutex<Phases>>,
    start: Stamp,
}

impl Recorder {
    /// Installs the subscriber for the whole process (every thread); `None` when another one
    /// is installed already.
    pub(crate) fn install() -> Option<Self> {
        let timings = Timings {
            command_thread: Some(std::thread::current().id()),
            ..Timings::default()
        };
        let phases = Arc::clone(&timings.phases);
        tracing::subscriber::set_global_default(timings).ok()?;
        Some(Self {
            phases,
            start: Stamp::now(),
        })
    }

    /// The table of phases, one line each, indented by nesting: wall time, the process's CPU
    /// time, the threads busy on average (CPU over wall), and the CPU time of the threads that
    /// entered the phase; then the whole run, and the part of it outside the phases that score
    /// candidates in parallel.
    pub(crate) fn report(&self) -> String {
        let end = Stamp::now();
        let phases = self.phases.lock().unwrap_or_else(PoisonError::into_inner);
        let seconds = |d: Option<Duration>| match d {
            Some(d) => format!("{:10.3}", d.as_secs_f64()),
            None => format!("{:>10}", "-"),
        };
        let busy = |cpu: Option<Duration>, wall: Duration| match cpu {
            Some(cpu) if wall > Duration::ZERO => {
                format!("{:8.2}", cpu.as_secs_f64() / wall.as_secs_f64())
            }
            _ => format!("{:>8}", "-"),
        };
        let mut out = format!(
            "graspath: timings ({} worker threads)\n  {:<38}{:>8}{:>10}{:>10}{:>8}{:>10}\n",
            rayon::current_num_threads(),
            "phase",
            "entries",
            "wall s",
            "CPU s",
            "busy",
            "own CPU s"
        );
        let mut scoring = Duration::ZERO;
        for name in &phases.order {
            let phase = &phases.by_name[name];
            if phase.depth == 0 && phase.on_command_thread && name.starts_with("score") {
                scoring += phase.wall;
            }
            let label = format!("{}{name}", "  ".repeat(phase.depth));
            out.push_str(&format!(
                "  {label:<38}{:>8}{:>10.3}{}{}{}\n",
                phase.entries,
                phase.wall.as_secs_f64(),
                seconds(phase.process),
                busy(phase.process, phase.wall),
                seconds(phase.thread),
            ));
        }
        let wall = end.wall - self.start.wall;
        let process = end.process.zip(self.start.process).map(|(e, s)| e - s);
        out.push_str(&format!(
            "  {:<38}{:>8}{:>10.3}{}{}\n",
            "whole run",
            "",
            wall.as_secs_f64(),
            seconds(process),
            busy(process, wall),
        ));
        let outside = wall.saturating_sub(scoring);
        out.push_str(&format!(
            "  outside the parallel scoring: {:.3} s, {:.1} % of the wall time\n",
            outside.as_secs_f64(),
            100.0 * outside.as_secs_f64() / wall.as_secs_f64().max(f64::MIN_POSITIVE),
        ));
        out
    }
}
