//! Expanding `.xacro` robot descriptions into URDF text by running the `xacro` command
//! (the ROS `xacro` package, also on PyPI: `pip install xacro`).
//!
//! The command is looked up in this order: the program named by the `GRASPATH_XACRO`
//! environment variable (only it, when set), `xacro` on `PATH`, then `python3 -m xacro`. It is
//! run directly (arguments as a list, no shell) with the file as its one argument; its standard
//! output is the URDF. Output is capped at [`MAX_OUTPUT_BYTES`], the run at [`TIMEOUT`]; on
//! failure the error carries the exit status and the end of the command's standard error.

use super::error::RobotError;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The largest URDF accepted from `xacro` (bytes).
pub const MAX_OUTPUT_BYTES: u64 = 64 << 20;

/// How long `xacro` may run before it is stopped.
pub const TIMEOUT: Duration = Duration::from_secs(120);

/// How much of the command's standard error is kept for the message (bytes, the end).
const STDERR_TAIL: usize = 4000;

/// One way to run xacro: a program and the arguments before the file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct XacroCommand {
    /// The program (a name looked up on `PATH`, or a path).
    pub program: PathBuf,
    /// Arguments placed before the file (`["-m", "xacro"]` for a Python interpreter).
    pub args: Vec<String>,
}

impl XacroCommand {
    /// The commands tried by default, in order (see the module documentation).
    pub fn defaults() -> Vec<XacroCommand> {
        if let Some(program) = std::env::var_os("GRASPATH_XACRO").filter(|p| !p.is_empty()) {
            return vec![XacroCommand {
                program: program.into(),
                args: Vec::new(),
            }];
        }
        vec![
            XacroCommand {
                program: "xacro".into(),
                args: Vec::new(),
            },
            XacroCommand {
                program: "python3".into(),
                args: vec!["-m".into(), "xacro".into()],
            },
        ]
    }

    fn display(&self, file: &Path) -> String {
        let mut words = vec![self.program.display().to_string()];
        words.extend(self.args.iter().cloned());
        words.push(file.display().to_string());
        words.join(" ")
    }
}

/// Expands the xacro file `path` with the first of the [`XacroCommand::defaults`] that is
/// installed.
pub fn expand_xacro(path: &Path) -> Result<String, RobotError> {
    expand_xacro_with(path, &XacroCommand::defaults())
}

/// Expands the xacro file `path` with the first of `commands` that is installed. When none is,
/// the error is [`RobotError::Xacro`] with the install instruction; when one runs and fails,
/// [`RobotError::XacroFailed`] with its standard error.
pub fn expand_xacro_with(path: &Path, commands: &[XacroCommand]) -> Result<String, RobotError> {
    let source_name = path.display().to_string();
    let mut tried = Vec::new();
    for command in commands {
        match run(command, path) {
            Run::Missing => tried.push(command.display(Path::new("FILE"))),
            Run::Failed(message) => {
                return Err(RobotError::XacroFailed {
                    source_name,
                    command: command.display(path),
                    message,
                })
            }
            Run::Done(text) => return Ok(text),
        }
    }
    Err(RobotError::Xacro {
        source_name,
        reason: format!("no xacro command found; tried {}", tried.join(", ")),
    })
}

enum Run {
    /// The program does not exist (or is a Python without the xacro module).
    Missing,
    Failed(String),
    Done(String),
}

fn run(command: &XacroCommand, path: &Path) -> Run {
    let child = Command::new(&command.program)
        .args(&command.args)
        .arg(path)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(child) => child,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Run::Missing,
        Err(e) => return Run::Failed(format!("cannot start: {e}")),
    };
    let (Some(stdout), Some(stderr)) = (child.stdout.take(), child.stderr.take()) else {
        let _ = child.kill();
        let _ = child.wait();
        return Run::Failed("cannot capture its output".into());
    };
    // Both pipes are drained on their own threads so neither can fill up and stall the child.
    let out_reader = std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let read = stdout.take(MAX_OUTPUT_BYTES + 1).read_to_end(&mut bytes);
        read.map(|_| bytes)
    });
    let err_reader = std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = stderr.take(MAX_OUTPUT_BYTES).read_to_end(&mut bytes);
        bytes
    });
    let started = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Ok(status),
            Ok(None) if started.elapsed() > TIMEOUT => {
                let _ = child.kill();
                let _ = child.wait();
                break Err(format!("stopped after {} s", TIMEOUT.as_secs()));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(10)),
            Err(e) => break Err(format!("cannot wait for it: {e}")),
        }
    };
    // The output readers finish once the child has exited (or was killed) and the pipes close;
    // a grandchild holding them open is not waited for beyond the size cap.
    let stdout = out_reader.join().ok();
    let stderr = err_reader.join().unwrap_or_default();
    let stderr = String::from_utf8_lossy(&stderr);
    let tail = tail(stderr.trim());
    let status = match status {
        Ok(status) => status,
        Err(message) => return Run::Failed(with_stderr(message, tail)),
    };
    if !status.success() {
        if command.args.first().is_some_and(|a| a == "-m") && stderr.contains("No module named") {
            return Run::Missing;
        }
        return Run::Failed(with_stderr(format!("exit status {status}"), tail));
    }
    match stdout {
        Some(Ok(bytes)) if bytes.len() as u64 > MAX_OUTPUT_BYTES => Run::Failed(format!(
            "its output is larger than {} MiB",
            MAX_OUTPUT_BYTES >> 20
        )),
        Some(Ok(bytes)) => match String::from_utf8(bytes) {
            Ok(text) => Run::Done(text),
            Err(_) => Run::Failed("its output is not UTF-8".into()),
        },
        Some(Err(e)) => Run::Failed(format!("cannot read its output: {e}")),
        None => Run::Failed("cannot read its output".into()),
    }
}

fn tail(text: &str) -> &str {
    if text.len() <= STDERR_TAIL {
        return text;
    }
    let mut start = text.len() - STDERR_TAIL;
    while !text.is_char_boundary(start) {
        start += 1;
    }
    &text[start..]
}

fn with_stderr(message: String, stderr: &str) -> String {
    if stderr.is_empty() {
        message
    } else {
        format!("{message}; its standard error: {stderr}")
    }
}
