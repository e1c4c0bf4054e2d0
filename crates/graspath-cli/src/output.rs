//! Terminal output: progress bars, the one-screen summary table, `--quiet` and `--json`.

/// `println!` that ignores a closed stdout (e.g. `graspath demo | head`) instead of panicking.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

use clap::Args;
use graspath::defaults;
use graspath::select::{Scored, Selection, NAMED_BEST};
use graspath::task::Task;
use graspath_report::{findings_sentences, nothing_selected};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

/// Writes a command's result (the JSON Lines of `kinematics` and `ik`) to standard output and
/// flushes it. A failure — a full disk, a closed pipe — is an error that says it was standard
/// output that could not be written (exit code 1: writing the output failed).
pub(crate) fn write_result_to_stdout(bytes: &[u8]) -> anyhow::Result<()> {
    use anyhow::Context as _;
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    out.write_all(bytes)
        .and_then(|()| out.flush())
        .context("cannot write the result to standard output")
}

/// Output switches shared by the long-running subcommands.
#[derive(Debug, Clone, Args)]
pub(crate) struct OutputArgs {
    /// Print nothing but errors.
    #[arg(long, conflicts_with = "json")]
    pub quiet: bool,
    /// Print the summary as JSON on stdout (for scripts) instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also log progress as plain lines on stderr every SECONDS (done / total, rate, ETA), for
    /// logs where no progress bar is drawn: batch jobs, CI, Ray workers. Off by default.
    #[arg(long, value_name = "SECONDS", value_parser = positive_seconds)]
    pub progress_every: Option<f64>,
    /// Print where the run's time went on stderr when it ends: per phase (reading the task,
    /// producing, scoring and writing the candidates, ranking, pairing, writing the other
    /// files), the wall time, the CPU time and how many threads were busy on average.
    #[arg(long)]
    pub timings: bool,
}

impl OutputArgs {
    /// Nothing printed but errors (for runs nested in another command's output).
    pub(crate) fn silent() -> Self {
        Self {
            quiet: true,
            json: false,
            progress_every: None,
            timings: false,
        }
    }
}

/// `--progress-every`: a finite number of seconds, at least a millisecond.
/// The longest `--progress-every` interval (s): a week, far beyond any run.
const MAX_PROGRESS_SECONDS: f64 = 7.0 * 24.0 * 3600.0;

/// How many pairs of colliding bodies the summary names (`summary.json` has them all).
const MOST_FREQUENT_COLLISIONS: usize = 3;

fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (0.001..=MAX_PROGRESS_SECONDS).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{text}` is not a number of seconds from 0.001 to {MAX_PROGRESS_SECONDS} (a week)"
        )),
    }
}

/// Progress of a long run over `total` units: a bar on a terminal (stderr; hidden otherwise or
/// with `--quiet`/`--json`) showing the rate and the ETA, and with `--progress-every` plain
/// lines on stderr at that interval and one at the end. `inc` may be called from any thread.
pub(crate) struct Progress {
    bar: ProgressBar,
    log: Option<Arc<ProgressLog>>,
    /// Taken (and stopped) by [`Progress::finish`] or on drop.
    ticker: Mutex<Option<Ticker>>,
}

/// The plain-line side of [`Progress`].
struct ProgressLog {
    title: String,
    unit: &'static str,
    total: u64,
    started: Instant,
    done: AtomicU64,
}

/// The thread that writes a `--progress-every` line on time, also while one long unit (a
/// candidate with a long path) keeps the count from moving: the line then says the run is
/// alive and how long it has taken.
struct Ticker {
    stop: mpsc::Sender<()>,
    thread: std::thread::JoinHandle<()>,
}

impl Ticker {
    fn start(log: Arc<ProgressLog>, every: Duration) -> Self {
        let (stop, stopped) = mpsc::channel::<()>();
        let thread = std::thread::spawn(move || {
            // A message or a dropped sender ends it; a time-out is a line due.
            while let Err(mpsc::RecvTimeoutError::Timeout) = stopped.recv_timeout(every) {
                log.line(log.done.load(Ordering::Relaxed), log.started.elapsed());
            }
        });
        Self { stop, thread }
    }

    fn stop(self) {
        // The thread may have ended already; either way it is joined.
        let _ = self.stop.send(());
        let _ = self.thread.join();
    }
}

impl Progress {
    /// Progress over `total` `unit`s (plural noun, e.g. `candidates`) titled `title`.
    pub(crate) fn new(output: &OutputArgs, total: u64, title: &str, unit: &'static str) -> Self {
        let bar = if output.quiet || output.json || !std::io::stderr().is_terminal() {
            ProgressBar::hidden()
        } else {
            let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
            bar.set_style(
                ProgressStyle::with_template(&format!(
                    "{{msg}} [{{bar:30}}] {{pos}}/{{len}} {unit} ({{per_sec}}, ETA {{eta}})"
                ))
                .expect("valid template")
                .progress_chars("=> "),
            );
            bar.set_message(title.to_string());
            bar
        };
        let log = output.progress_every.map(|_| {
            Arc::new(ProgressLog {
                title: title.to_string(),
                unit,
                total,
                started: Instant::now(),
                done: AtomicU64::new(0),
            })
        });
        let ticker = log
            .as_ref()
            .zip(output.progress_every)
            .map(|(log, seconds)| Ticker::start(Arc::clone(log), Duration::from_secs_f64(seconds)));
        Self {
            bar,
            log,
            ticker: Mutex::new(ticker),
        }
    }

    /// One more unit done.
    pub(crate) fn inc(&self) {
        self.bar.inc(1);
        if let Some(log) = &self.log {
            log.done.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Clears the bar, stops the timed lines and logs the final line.
    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
        self.stop_ticker();
        if let Some(log) = &self.log {
            log.line(log.done.load(Ordering::Relaxed), log.started.elapsed());
        }
    }
}

impl Progress {
    fn stop_ticker(&self) {
        let ticker = match self.ticker.lock() {
            Ok(mut guard) => guard.take(),
            Err(poisoned) => poisoned.into_inner().take(),
        };
        if let Some(ticker) = ticker {
            ticker.stop();
        }
    }
}

impl Drop for Progress {
    /// A run that ends early (an error) stops the timed lines without a final one.
    fn drop(&mut self) {
        self.stop_ticker();
    }
}

impl ProgressLog {
    fn line(&self, done: u64, elapsed: Duration) {
        let seconds = elapsed.as_secs_f64();
        let rate = if seconds > 0.0 {
            done as f64 / seconds
        } else {
            0.0
        };
        let percent = if self.total > 0 {
            100.0 * done as f64 / self.total as f64
        } else {
            100.0
        };
        let eta = if done >= self.total {
            "done".to_string()
        } else if rate > 0.0 {
            format!("ETA {}", clock((self.total - done) as f64 / rate))
        } else {
            "ETA unknown".to_string()
        };
        eprintln!(
            "{}: {done}/{} {} ({percent:.1} %), {rate:.0} {}/s, elapsed {}, {eta}",
            self.title,
            self.total,
            self.unit,
            self.unit,
            clock(seconds)
        );
    }
}

/// A duration in seconds as `1h02m03s`, `2m03s` or `3.4s`.
fn clock(seconds: f64) -> String {
    let whole = seconds.round() as u64;
    let (h, m, s) = (whole / 3600, whole / 60 % 60, whole % 60);
    if h > 0 {
        format!("{h}h{m:02}m{s:02}s")
    } else if m > 0 {
        format!("{m}m{s:02}s")
    } else {
        format!("{seconds:.1}s")
    }
}

fn number(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.4}"),
        Some(_) => "inf".into(),
        None => "-".into(),
    }
}

/// The one-screen summary: per arm the best [`NAMED_BEST`] candidates and the failures by
/// reason.
pub(crate) fn print_summary_table<S: Scored>(
    task: &Task,
    selection: &Selection<S>,
    title: &str,
    elapsed: Duration,
) {
    say!(
        "{title}: {} candidates x {} arm(s), {} samples, {:.3} s",
        task.candidate_count(),
        task.arms().len(),
        task.path().samples.len(),
        elapsed.as_secs_f64()
    );
    for arm in &selection.arms {
        let mut reasons: std::collections::BTreeMap<&str, usize> = Default::default();
        for reason in arm.scores.iter().filter_map(Scored::failure_reason) {
            *reasons.entry(reason.as_str()).or_default() += 1;
        }
        let rejected = arm.rankings.iter().filter(|r| r.rejected.is_some()).count();
        let reasons: Vec<String> = reasons.iter().map(|(r, n)| format!("{n} {r}")).collect();
        // A one-arm robot's chain is named `arm`: "the arm", not "arm arm".
        let arm_name = if arm.arm == "arm" {
            "the arm".to_string()
        } else {
            format!("arm {}", arm.arm)
        };
        say!(
            "  {}: {} feasible, {} rejected by the selection rule{}",
            arm_name,
            arm.feasible_count(),
            rejected,
            if reasons.is_empty() {
                String::new()
            } else {
                format!(", infeasible: {}", reasons.join(", "))
            }
        );
        // What the collisions hit most: the pairs of bodies to move first.
        let colliding = arm.colliding_body_pairs();
        if !colliding.is_empty() {
            let shown: Vec<String> = colliding
                .iter()
                .take(MOST_FREQUENT_COLLISIONS)
                .map(|([a, b], n)| format!("{a} – {b} ({n})"))
                .collect();
            say!("  most frequent collisions: {}", shown.join(", "));
        }
        // In a scene the last column is the clearance from it (m); else Yoshikawa's index.
        let in_scene = task.collisions().is_some();
        // `limit`: the smallest distance of any joint to its limit along the motion (rad).
        say!(
            "    {:>4}  {:>5}  {:<28} {:>10} {:>10} {:>10} {:>10} {:>8}",
            "rank",
            "id",
            "label",
            "score",
            task.selection().norm.field(),
            "mu_linf",
            if in_scene { "clearance" } else { "yoshikawa" },
            "limit"
        );
        let mut ranked: Vec<usize> = (0..arm.rankings.len())
            .filter(|&i| arm.rankings[i].rank.is_some())
            .collect();
        ranked.sort_by_key(|&i| arm.rankings[i].rank);
        // Candidates tied with the best (see `selection.tie_tolerance`) show `=` before their rank.
        let tied_with_best = arm
            .best()
            .map(|b| arm.tied_with(b, task.selection()))
            .unwrap_or_default();
        // The best `NAMED_BEST`: the candidates a streamed selection keeps the labels of.
        for &i in ranked.iter().take(NAMED_BEST) {
            let s = &arm.scores[i];
            let label = s.candidate().map_or("", |c| c.label.as_str());
            let rank = arm.rankings[i].rank.unwrap_or(0);
            let rank = if tied_with_best.contains(&s.id()) {
                format!("={rank}")
            } else {
                rank.to_string()
            };
            say!(
                "    {:>4}  {:>5}  {:<28} {:>10} {:>10} {:>10} {:>10} {:>8}",
                rank,
                s.id(),
                label.chars().take(28).collect::<String>(),
                number(arm.rankings[i].score),
                number(s.norms().map(|n| n.value(task.selection().norm))),
                number(s.norms().map(|n| n.linf)),
                number(if in_scene {
                    s.clearance()
                } else {
                    s.yoshikawa_at_grasp()
                }),
                number(s.limit_distance_min()),
            );
        }
        // How much the arm's redundancy matters for the selected grasp (`ik.redundancy:
        // optimize`): the spread of μ_l2 over its self-motion.
        if let Some(motion) = arm.best().and_then(|b| arm.scores[b].self_motion()) {
            let (low, high) = motion.l2_range;
            if high > 0.0 {
                say!(
                    "  over its self-motion the selected grasp's mu_l2 spans {low:.4} to \
                     {high:.4} ({:.0} % of the largest; the first IK branch: {:.4})",
                    100.0 * (high - low) / high,
                    motion.first_branch_l2
                );
            }
        }
        // A selected grasp whose motion comes this close to a joint limit leaves no margin for
        // the next perception error, and a real controller may fault on it.
        if let Some(best) = arm.best() {
            let s = &arm.scores[best];
            if let Some(d) = s
                .limit_distance_min()
                .filter(|d| *d <= defaults::LIMIT_HUG_DISTANCE)
            {
                say!(
                    "  warning: the selected grasp (id {}) comes within {d:.4} rad of a joint \
                     limit along its motion; ik.limit_margin (default 0.1 rad) keeps the \
                     motions that far inside the limits",
                    s.id()
                );
            }
        }
    }
    for sentence in findings_sentences(task, selection) {
        say!("  {sentence}");
    }
    if selection.colliding_pairs > 0 {
        say!(
            "  {} better pair(s) refused: the two arms would touch along the motion",
            selection.colliding_pairs
        );
    }
    if nothing_selected(selection) {
        if selection.arms.len() >= 2 {
            say!("  nothing selected: no valid pair of grasps");
        } else {
            say!("  nothing selected: no feasible candidate");
        }
    }
}
