//! The parent process of a fuzzing campaign, and the two worker modes it starts.
//!
//! For each target the parent starts a worker (this executable with `--worker`) on a range of
//! input indices. Inputs are a pure function of `(seed, target, index)`, so a worker can be
//! restarted anywhere. The worker reports progress and caught panics on its stdout; when it
//! dies (allocation bound, watchdog, signal) the parent reads the input that was running from
//! the *current* file and the finding from the *death* file, records it, and starts a new
//! worker at the next index. Findings are de-duplicated by signature; each new one is saved
//! under `<findings>/<target>/` and minimised by delta debugging, every candidate replayed in a
//! fresh process (`--replay`), so that aborts and hangs minimise like panics.

use crate::exec::{read_current, Executor, Failure, Kind, EXIT_PANIC};
use crate::known::{known, KnownFinding};
use crate::minimise::ddmin;
use crate::targets::{generate_input, Ctx, Target};
use anyhow::{bail, Context, Result};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// How a campaign runs.
#[derive(Debug, Clone)]
pub struct Settings {
    /// The campaign seed.
    pub seed: u64,
    /// Executions per target (with `seconds`, whichever ends first).
    pub execs: Option<u64>,
    /// Wall time per target (s).
    pub seconds: Option<f64>,
    /// Use each target's CI-slice execution count.
    pub ci_slice: bool,
    /// Where findings and the summary go.
    pub findings: PathBuf,
    /// Time limit of one execution (ms).
    pub timeout_ms: u64,
    /// Time budget for minimising each new finding (s); 0 disables minimisation.
    pub minimise_seconds: f64,
    /// Bound on one allocation (bytes).
    pub single_limit: usize,
    /// Bound on live memory (bytes).
    pub total_limit: usize,
    /// This executable (the worker).
    pub exe: PathBuf,
    /// The directory of the current-input, death and panic files shared with the workers
    /// (under [`crate::targets::scratch_root`]).
    pub work: PathBuf,
}

/// One distinct finding of a target.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FindingReport {
    /// The target.
    pub target: String,
    /// The kind.
    pub kind: Kind,
    /// The de-duplication key.
    pub signature: String,
    /// The first message seen.
    pub message: String,
    /// How many inputs reproduced it.
    pub count: u64,
    /// The index of the first such input.
    pub first_index: u64,
    /// The input as found.
    pub reproducer: PathBuf,
    /// The minimised input, when minimisation ran and reproduced the finding.
    pub minimised: Option<PathBuf>,
    /// The minimised input's length (bytes).
    pub minimised_len: Option<usize>,
    /// The known-findings entry that covers it.
    pub known: Option<KnownFinding>,
}

/// The result of one target.
#[derive(Debug, Clone, serde::Serialize)]
pub struct TargetReport {
    /// The target.
    pub target: String,
    /// Executions.
    pub execs: u64,
    /// Wall time (s), without minimisation.
    pub seconds: f64,
    /// Executions per second.
    pub execs_per_second: f64,
    /// Distinct findings.
    pub findings: Vec<FindingReport>,
}

/// The result of a campaign (written to `<findings>/summary.json`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Summary {
    /// The campaign seed.
    pub seed: u64,
    /// Time limit per execution (ms).
    pub timeout_ms: u64,
    /// Bound on one allocation (bytes).
    pub single_limit: usize,
    /// Bound on live memory (bytes).
    pub total_limit: usize,
    /// Per target.
    pub targets: Vec<TargetReport>,
}

fn fnv(text: &str) -> u32 {
    let mut h: u32 = 0x811c_9dc5;
    for b in text.bytes() {
        h ^= u32::from(b);
        h = h.wrapping_mul(0x0100_0193);
    }
    h
}

fn work_dir(settings: &Settings) -> PathBuf {
    settings.work.clone()
}

fn limits_args(settings: &Settings) -> Vec<String> {
    vec![
        "--seed".into(),
        settings.seed.to_string(),
        "--timeout-ms".into(),
        settings.timeout_ms.to_string(),
        "--single-limit".into(),
        settings.single_limit.to_string(),
        "--total-limit".into(),
        settings.total_limit.to_string(),
        "--findings".into(),
        settings.findings.display().to_string(),
        "--work".into(),
        settings.work.display().to_string(),
    ]
}

/// Runs one input of `target` in a fresh process; the failure it reproduces, if any.
pub fn replay(settings: &Settings, target: &Target, input: &[u8]) -> Result<Option<Failure>> {
    let work = work_dir(settings);
    let stem = format!("replay-{}-{}", target.name, std::process::id());
    let input_path = work.join(format!("{stem}.in"));
    let death = work.join(format!("{stem}.death"));
    std::fs::write(&input_path, input)?;
    let _ = std::fs::remove_file(&death);
    let child = Command::new(&settings.exe)
        .args(["--target", target.name, "--replay"])
        .arg(&input_path)
        .arg("--death")
        .arg(&death)
        .args(limits_args(settings))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .with_context(|| format!("cannot start {}", settings.exe.display()))?;
    let pid = child.id();
    let status = child.wait_with_output()?;
    cleanup_child_dir(pid);
    if status.status.success() {
        return Ok(None);
    }
    let failure = std::fs::read_to_string(&death)
        .ok()
        .and_then(|t| Failure::from_record(&t))
        .unwrap_or_else(|| crash_failure(&status.status, &String::from_utf8_lossy(&status.stderr)));
    Ok(Some(failure))
}

/// Replays a hang recorded without its place, up to twice; the first failure that says more
/// (a hang with frames, or a bound crossed on the way).
fn refine_hang(settings: &Settings, target: &Target, input: &[u8]) -> Option<Failure> {
    (0..2).find_map(|_| {
        let failure = replay(settings, target, input).ok()??;
        (failure.signature != "hang").then(|| Failure {
            message: format!("{} (on replay of a hang)", failure.message),
            ..failure
        })
    })
}

fn crash_failure(status: &std::process::ExitStatus, stderr: &str) -> Failure {
    use std::os::unix::process::ExitStatusExt;
    let how = match (status.code(), status.signal()) {
        (Some(code), _) => format!("exit code {code}"),
        (None, Some(signal)) => format!("signal {signal}"),
        _ => "unknown status".to_string(),
    };
    let last = stderr
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("")
        .trim();
    let cause = if stderr.contains("has overflowed its stack") {
        "stack overflow"
    } else {
        how.as_str()
    };
    Failure {
        kind: Kind::Crash,
        signature: format!("crash ({cause})"),
        message: crate::exec::one_line(&format!("the process died ({how}): {last}")),
    }
}

/// Removes leftover per-process work directories of workers that could not clean up.
fn cleanup_child_dir(pid: u32) {
    let _ = std::fs::remove_dir_all(Ctx::dir_of(pid));
}

struct Recorder<'a> {
    settings: &'a Settings,
    target: &'a Target,
    findings: BTreeMap<String, (FindingReport, Vec<u8>)>,
}

impl Recorder<'_> {
    fn record(&mut self, failure: Failure, index: u64, input: Vec<u8>) -> Result<()> {
        if let Some((report, _)) = self.findings.get_mut(&failure.signature) {
            report.count += 1;
            return Ok(());
        }
        let dir = self.settings.findings.join(self.target.name);
        std::fs::create_dir_all(&dir)?;
        let stem = format!("{}-{:08x}", failure.kind.name(), fnv(&failure.signature));
        let reproducer = dir.join(format!("{stem}.{}", self.target.extension));
        std::fs::write(&reproducer, &input)?;
        std::fs::write(
            dir.join(format!("{stem}.txt")),
            format!(
                "target: {}\nkind: {}\nsignature: {}\nmessage: {}\nindex: {index} (seed {})\n",
                self.target.name,
                failure.kind.name(),
                failure.signature,
                failure.message,
                self.settings.seed
            ),
        )?;
        let known = known(self.target.name, &failure.signature, &failure.message).copied();
        self.findings.insert(
            failure.signature.clone(),
            (
                FindingReport {
                    target: self.target.name.to_string(),
                    kind: failure.kind,
                    signature: failure.signature,
                    message: failure.message,
                    count: 1,
                    first_index: index,
                    reproducer,
                    minimised: None,
                    minimised_len: None,
                    known,
                },
                input,
            ),
        );
        Ok(())
    }
}

/// Runs one target's campaign (workers, restarts, minimisation).
pub fn run_target(settings: &Settings, target: &Target) -> Result<TargetReport> {
    let work = work_dir(settings);
    std::fs::create_dir_all(&work)?;
    let current = work.join(format!("current-{}", target.name));
    let death = work.join(format!("death-{}", target.name));
    let end = if settings.ci_slice {
        target.ci_execs
    } else {
        settings.execs.unwrap_or(u64::MAX)
    };
    let budget = settings.seconds.map(Duration::from_secs_f64);
    let stall = Duration::from_millis(settings.timeout_ms * 3) + Duration::from_secs(60);
    let started = Instant::now();
    let mut recorder = Recorder {
        settings,
        target,
        findings: BTreeMap::new(),
    };
    let mut next = 0u64;
    while next < end {
        let remaining = match budget {
            Some(b) if started.elapsed() >= b => break,
            Some(b) => Some(b - started.elapsed()),
            None => None,
        };
        let _ = std::fs::remove_file(&death);
        let _ = std::fs::remove_file(&current);
        let mut command = Command::new(&settings.exe);
        command
            .args(["--target", target.name, "--worker"])
            .args(["--start", &next.to_string(), "--end", &end.to_string()])
            .args(limits_args(settings))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        if let Some(r) = remaining {
            command.args(["--deadline-ms", &r.as_millis().to_string()]);
        }
        let mut child = command
            .spawn()
            .with_context(|| format!("cannot start {}", settings.exe.display()))?;
        let pid = child.id();
        let (sender, lines) = mpsc::channel::<String>();
        let stdout = child.stdout.take().context("worker stdout")?;
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                if sender.send(line).is_err() {
                    break;
                }
            }
        });
        let mut stderr_pipe = child.stderr.take().context("worker stderr")?;
        let stderr_reader = std::thread::spawn(move || {
            let mut text = String::new();
            let _ = std::io::Read::read_to_string(&mut stderr_pipe, &mut text);
            text
        });
        let mut finished = None;
        let mut stalled = false;
        loop {
            match lines.recv_timeout(stall) {
                Ok(line) => {
                    let mut parts = line.split_whitespace();
                    let tag = parts.next().unwrap_or("");
                    let number: u64 = parts.next().and_then(|n| n.parse().ok()).unwrap_or(next);
                    match tag {
                        "P" => next = number,
                        "D" => finished = Some(number),
                        "F" => {
                            let stem = work.join(format!("panic-{}-{number}", target.name));
                            let input =
                                std::fs::read(stem.with_extension("in")).unwrap_or_default();
                            let record = std::fs::read_to_string(stem.with_extension("rec"))
                                .unwrap_or_default();
                            let _ = std::fs::remove_file(stem.with_extension("in"));
                            let _ = std::fs::remove_file(stem.with_extension("rec"));
                            if let Some(failure) = Failure::from_record(&record) {
                                recorder.record(failure, number, input)?;
                            }
                        }
                        _ => {}
                    }
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    stalled = true;
                    let _ = child.kill();
                    break;
                }
            }
        }
        let status = child.wait()?;
        let stderr = stderr_reader.join().unwrap_or_default();
        cleanup_child_dir(pid);
        if let (Some(done), true) = (finished, status.success()) {
            next = done;
            break;
        }
        // The worker died: the input it was running is in the current file.
        let Some((index, input)) = read_current(&current) else {
            bail!(
                "the {} worker stopped before its first execution ({status}): {}",
                target.name,
                stderr.trim()
            );
        };
        let failure = if stalled {
            Failure {
                kind: Kind::Hang,
                signature: "hang".into(),
                message: format!("the worker stopped reporting for {} s", stall.as_secs()),
            }
        } else {
            std::fs::read_to_string(&death)
                .ok()
                .and_then(|t| Failure::from_record(&t))
                .unwrap_or_else(|| crash_failure(&status, &stderr))
        };
        let failure = if failure.signature == "hang" {
            // The watchdog could not see where the execution was (the thread may have been
            // interrupted inside the allocator): replay it to learn more.
            refine_hang(settings, target, &input).unwrap_or(failure)
        } else {
            failure
        };
        recorder.record(failure, index, input)?;
        next = index + 1;
    }
    let seconds = started.elapsed().as_secs_f64();
    let mut findings = Vec::new();
    for (_, (mut report, input)) in std::mem::take(&mut recorder.findings) {
        if settings.minimise_seconds > 0.0 {
            let deadline = Instant::now() + Duration::from_secs_f64(settings.minimise_seconds);
            let signature = report.signature.clone();
            let minimised = ddmin(
                &input,
                deadline,
                |candidate| matches!(replay(settings, target, candidate), Ok(Some(f)) if f.signature == signature),
            );
            if matches!(replay(settings, target, &minimised), Ok(Some(f)) if f.signature == signature)
            {
                let path = report
                    .reproducer
                    .with_extension(format!("min.{}", target.extension));
                std::fs::write(&path, &minimised)?;
                report.minimised_len = Some(minimised.len());
                report.minimised = Some(path);
            }
        }
        findings.push(report);
    }
    Ok(TargetReport {
        target: target.name.to_string(),
        execs: next,
        seconds,
        execs_per_second: next as f64 / seconds.max(1e-9),
        findings,
    })
}

/// Prints one target's report.
pub fn print_report(out: &mut impl Write, report: &TargetReport) -> std::io::Result<()> {
    let known = report.findings.iter().filter(|f| f.known.is_some()).count();
    writeln!(
        out,
        "{:<16} {:>10} execs {:>9.1} s {:>9.0} exec/s  {} findings ({} known)",
        report.target,
        report.execs,
        report.seconds,
        report.execs_per_second,
        report.findings.len(),
        known
    )?;
    for f in &report.findings {
        let status = match &f.known {
            Some(k) => format!("known: {}", k.issue),
            None => "NEW".to_string(),
        };
        let file = f.minimised.as_ref().unwrap_or(&f.reproducer);
        writeln!(
            out,
            "    [{status}] {} ×{} — {}\n        {}",
            f.kind.name(),
            f.count,
            f.message,
            file.display()
        )?;
    }
    out.flush()
}

/// Runs the campaign over `targets` and writes `<findings>/summary.json`.
pub fn run(settings: &Settings, targets: &[&'static Target]) -> Result<Summary> {
    std::fs::create_dir_all(&settings.findings)?;
    std::fs::create_dir_all(&settings.work)?;
    let mut reports = Vec::new();
    let stdout = std::io::stdout();
    for target in targets {
        let report = run_target(settings, target)?;
        print_report(&mut stdout.lock(), &report)?;
        reports.push(report);
    }
    let summary = Summary {
        seed: settings.seed,
        timeout_ms: settings.timeout_ms,
        single_limit: settings.single_limit,
        total_limit: settings.total_limit,
        targets: reports,
    };
    std::fs::write(
        settings.findings.join("summary.json"),
        serde_json::to_vec_pretty(&summary)?,
    )?;
    let _ = std::fs::remove_dir_all(work_dir(settings));
    Ok(summary)
}

/// The worker: executes inputs `start..end` of `target` (or until `deadline`), printing
/// `P next` progress lines, `F index` for each caught panic (input and record saved in the
/// work directory) and `D next` at the end.
pub fn worker_main(
    settings: &Settings,
    target: &Target,
    start: u64,
    end: u64,
    deadline: Option<Duration>,
) -> Result<()> {
    let started = Instant::now();
    let work = work_dir(settings);
    let ctx = Ctx::new().context("cannot create the work directory")?;
    let mut executor = Executor::new(
        &work.join(format!("current-{}", target.name)),
        &work.join(format!("death-{}", target.name)),
        Duration::from_millis(settings.timeout_ms),
    )?;
    ctx.warm_up(target);
    let corpus = (target.seeds)(&ctx);
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let mut last = Instant::now();
    let mut index = start;
    while index < end {
        if deadline.is_some_and(|d| started.elapsed() >= d) {
            break;
        }
        let input = generate_input(target, &corpus, settings.seed, index);
        if let Some(failure) = executor.execute(target, &ctx, index, &input) {
            let stem = work.join(format!("panic-{}-{index}", target.name));
            std::fs::write(stem.with_extension("in"), &input)?;
            std::fs::write(stem.with_extension("rec"), failure.to_record())?;
            writeln!(out, "F {index}")?;
        }
        index += 1;
        if last.elapsed() >= Duration::from_millis(250) {
            writeln!(out, "P {index}")?;
            out.flush()?;
            last = Instant::now();
        }
    }
    writeln!(out, "D {index}")?;
    out.flush()?;
    Ok(())
}

/// Replays one input file; returns the process exit code (0: no finding; [`EXIT_PANIC`]: a
/// panic, recorded in `death`; fatal findings exit from inside the oracles).
pub fn replay_main(
    settings: &Settings,
    target: &Target,
    input: &Path,
    death: &Path,
) -> Result<i32> {
    let bytes = std::fs::read(input).with_context(|| format!("cannot read {}", input.display()))?;
    let ctx = Ctx::new().context("cannot create the work directory")?;
    let mut executor = Executor::new(
        &input.with_extension("current"),
        death,
        Duration::from_millis(settings.timeout_ms),
    )?;
    ctx.warm_up(target);
    Ok(match executor.execute(target, &ctx, 0, &bytes) {
        None => 0,
        Some(failure) => {
            std::fs::write(death, failure.to_record())?;
            EXIT_PANIC
        }
    })
}
