//! Expanding xacro robot descriptions into URDF text by running the `xacro` program (the ROS
//! `xacro` package, also on PyPI: `pip install xacro`).
//!
//! **xacro runs code.** Its `${...}` expressions are Python, its `<xacro:include>` reads any
//! file the user can read, and its expression sandbox is not a security boundary: only expand
//! files you trust. graspath therefore expands a file only when the user asks for it, by
//! naming a file `*.xacro` ([`is_xacro_path`]); xacro markup inside a file with any other name
//! is refused ([`RobotError::XacroMarkup`]), and markup inside a comment is no markup at all.
//!
//! The program run is the one configured by the `GRASPATH_XACRO` environment variable (a path,
//! or a name looked up on `PATH`), else `xacro` found on `PATH`. Only absolute `PATH` entries
//! are searched, and a Python module is never run by name (`python3 -m xacro` would import a
//! `xacro.py` from the working folder). The run is bounded:
//!
//! * arguments as a list, no shell: the file, then one `NAME:=VALUE` per xacro argument
//!   ([`XacroOptions::args`]; names are checked);
//! * a fresh empty working folder, removed afterwards;
//! * an environment cleared but for [`PASSED_ENVIRONMENT`] (so `$(env VAR)` cannot copy a
//!   secret into the robot), plus `PYTHONSAFEPATH=1`;
//! * `$(find PKG)` is answered from the same package folders as `package://PKG` mesh URIs
//!   ([`MeshResolver`]: the search paths given, `ROS_PACKAGE_PATH`, `AMENT_PREFIX_PATH`, the
//!   file's own folders), through a small `ament_index_python` module written into the
//!   run's folder, so a ROS 2 description expands without a ROS installation;
//! * its own process group, stopped as a whole (every child included) after
//!   [`XacroOptions::timeout`] (default [`TIMEOUT`]) and when the program ends;
//! * standard output capped at [`MAX_OUTPUT_BYTES`], the end of standard error kept for the
//!   message.

use super::collision::MeshResolver;
use super::error::RobotError;
use std::collections::BTreeMap;
use std::ffi::OsString;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// The largest URDF accepted from `xacro` (bytes).
pub(super) const MAX_OUTPUT_BYTES: u64 = 64 << 20;

/// How long `xacro` may run by default before it is stopped (with every process it started).
pub(super) const TIMEOUT: Duration = Duration::from_secs(120);

/// The environment variables passed to `xacro`; every other one is removed. `PATH` and
/// `PYTHONPATH` find the program and its Python packages, the locale keeps its text encoding,
/// and the ROS variables name package folders (they are also what `$(find PKG)` searches).
pub const PASSED_ENVIRONMENT: [&str; 9] = [
    "PATH",
    "PYTHONPATH",
    "LANG",
    "LC_ALL",
    "LC_CTYPE",
    "ROS_PACKAGE_PATH",
    "AMENT_PREFIX_PATH",
    "ROS_DISTRO",
    "ROS_VERSION",
];

/// The longest xacro argument value accepted (bytes).
pub(super) const MAX_ARGUMENT_BYTES: usize = 4096;

/// The most xacro arguments accepted.
pub(super) const MAX_ARGUMENTS: usize = 256;

/// How much of the command's standard error is kept for the message (bytes, the end).
const STDERR_TAIL: usize = 4000;

/// How long the output readers are waited for once the program has been stopped.
const DRAIN_GRACE: Duration = Duration::from_secs(2);

/// The `ament_index_python` stand-in written for each run: `get_package_share_directory`
/// looks for the package in the folders listed (one a line, `KIND<TAB>PATH`) in
/// `GRASPATH_PACKAGE_ROOTS`, in order, with the rules of [`MeshResolver::candidates`].
const AMENT_INDEX_SHIM: &str = r#""""graspath's stand-in for ament_index_python: packages from graspath's search paths."""
import os


class PackageNotFoundError(KeyError):
    pass


def _candidates(name):
    for line in os.environ.get("GRASPATH_PACKAGE_ROOTS", "").split("\n"):
        kind, _, root = line.partition("\t")
        if kind == "search":
            yield os.path.join(root, name)
            yield os.path.join(root, "share", name)
        elif kind == "ros":
            yield os.path.join(root, name)
            if os.path.basename(root) == name:
                yield root
        elif kind == "ament":
            yield os.path.join(root, "share", name)
        elif kind == "ancestor" and os.path.basename(root) == name:
            yield root


def get_package_share_directory(package_name, print_warning=True):
    if "/" in package_name or package_name in ("", ".", ".."):
        raise PackageNotFoundError("'%s' is not a package name" % package_name)
    for folder in _candidates(package_name):
        if os.path.isdir(folder):
            return folder
    raise PackageNotFoundError(
        "package '%s' not found in graspath's package search paths" % package_name
    )


def get_package_prefix(package_name):
    share = get_package_share_directory(package_name)
    parent = os.path.dirname(share)
    return os.path.dirname(parent) if os.path.basename(parent) == "share" else share
"#;

/// How a xacro file is expanded: its arguments, where its packages are found, how long it
/// may take.
#[derive(Debug, Clone, PartialEq)]
pub struct XacroOptions {
    /// xacro arguments (`<xacro:arg name=...>`), passed as `NAME:=VALUE`.
    pub args: BTreeMap<String, String>,
    /// Where `$(find PKG)` looks (the robot's mesh resolver: the same folders as
    /// `package://PKG`). `None`: `ROS_PACKAGE_PATH`, `AMENT_PREFIX_PATH` and the file's folders.
    pub packages: Option<MeshResolver>,
    /// How long the run may take before it is stopped, every process it started included
    /// (default `TIMEOUT`, 120 s).
    pub timeout: Duration,
}

impl Default for XacroOptions {
    fn default() -> Self {
        Self {
            args: BTreeMap::new(),
            packages: None,
            timeout: TIMEOUT,
        }
    }
}

/// Whether `path` names a xacro file: its extension is `xacro` (`arm.xacro`,
/// `arm.urdf.xacro`; any letter case). Only such files are expanded.
pub fn is_xacro_path(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xacro"))
}

/// The `xacro` program to run: `GRASPATH_XACRO` when set (a path, or a name looked up on
/// `PATH`), else `xacro` on `PATH`. Only absolute `PATH` entries are searched. The error says
/// what was looked for.
pub fn find_xacro_program() -> Result<PathBuf, String> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    match std::env::var_os("GRASPATH_XACRO").filter(|p| !p.is_empty()) {
        Some(configured) => find_program(&configured, &path)
            .ok_or_else(|| format!("GRASPATH_XACRO names {configured:?}, which is not a program")),
        None => find_program(&OsString::from("xacro"), &path)
            .ok_or_else(|| "no `xacro` program on PATH".to_string()),
    }
}

/// `name` itself when it contains a `/` (an executable file), else the first executable file
/// `DIR/name` over the absolute entries of `path`.
fn find_program(name: &OsString, path: &OsString) -> Option<PathBuf> {
    let name = PathBuf::from(name);
    if name.components().count() > 1 || name.is_absolute() {
        return is_executable(&name).then_some(name);
    }
    std::env::split_paths(path)
        .filter(|dir| dir.is_absolute())
        .map(|dir| dir.join(&name))
        .find(|candidate| is_executable(candidate))
}

#[cfg(unix)]
fn is_executable(path: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

#[cfg(not(unix))]
fn is_executable(path: &Path) -> bool {
    path.is_file()
}

/// Expands the xacro file `path` with the program [`find_xacro_program`] finds. When there is
/// none, the error is [`RobotError::Xacro`] with the install instruction; when it runs and
/// fails, [`RobotError::XacroFailed`] with its standard error.
pub fn expand_xacro(path: &Path, options: &XacroOptions) -> Result<String, RobotError> {
    let program = find_xacro_program().map_err(|reason| RobotError::Xacro {
        source_name: path.display().to_string(),
        reason,
    })?;
    expand_xacro_with(path, &program, options)
}

/// Expands the xacro file `path` by running `program` (see the module documentation for how
/// the run is bounded).
pub fn expand_xacro_with(
    path: &Path,
    program: &Path,
    options: &XacroOptions,
) -> Result<String, RobotError> {
    let source_name = path.display().to_string();
    let arguments =
        argument_list(&options.args).map_err(|(name, message)| RobotError::XacroArgument {
            source_name: source_name.clone(),
            name,
            message,
        })?;
    if !is_executable(program) {
        return Err(RobotError::Xacro {
            source_name,
            reason: format!("{} is not a program", program.display()),
        });
    }
    let command = format!("{} {}", program.display(), path.display());
    let failed = |failure: RunFailure| match failure {
        RunFailure::Program(message) => RobotError::XacroFailed {
            source_name: source_name.clone(),
            command: command.clone(),
            message,
        },
        RunFailure::Io(action, source) => RobotError::XacroIo {
            source_name: source_name.clone(),
            command: command.clone(),
            action,
            source,
        },
    };
    let refused = |action| move |e| failed(RunFailure::Io(action, e));
    // The file is passed by absolute path: the run's working folder is elsewhere.
    let file = std::path::absolute(path).map_err(refused("cannot locate the file"))?;
    let folder = tempfile::Builder::new()
        .prefix("graspath-xacro-")
        .tempdir()
        .map_err(refused("cannot make its working folder"))?;
    let shim = folder.path().join("python");
    write_shim(&shim).map_err(refused("cannot prepare its working folder"))?;
    let work = folder.path().join("work");
    std::fs::create_dir(&work).map_err(refused("cannot make its working folder"))?;
    let packages = options.packages.clone().unwrap_or_else(|| {
        MeshResolver::from_env(file.parent().unwrap_or(Path::new("/")), Vec::new())
    });
    let mut command = Command::new(program);
    command
        .arg(&file)
        .args(&arguments)
        .current_dir(&work)
        .env_clear()
        .envs(passed_environment(&shim))
        .env("PYTHONSAFEPATH", "1")
        .env("GRASPATH_PACKAGE_ROOTS", package_roots(&packages))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        command.process_group(0);
    }
    let child = command.spawn().map_err(refused("cannot start it"))?;
    run(child, options.timeout).map_err(failed)
}

/// `NAME:=VALUE` for each argument; an error names the argument and what is wrong.
fn argument_list(args: &BTreeMap<String, String>) -> Result<Vec<String>, (String, String)> {
    if args.len() > MAX_ARGUMENTS {
        return Err((
            String::new(),
            format!("{} arguments; at most {MAX_ARGUMENTS}", args.len()),
        ));
    }
    args.iter()
        .map(|(name, value)| {
            let mut chars = name.chars();
            let well_named = chars
                .next()
                .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
                && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
            if !well_named {
                return Err((
                    name.clone(),
                    "an argument name is letters, digits and '_', not starting with a digit".into(),
                ));
            }
            if value.len() > MAX_ARGUMENT_BYTES || value.contains('\0') {
                return Err((
                    name.clone(),
                    format!("a value is at most {MAX_ARGUMENT_BYTES} bytes, with no NUL character"),
                ));
            }
            Ok(format!("{name}:={value}"))
        })
        .collect()
}

/// The variables of [`PASSED_ENVIRONMENT`] that are set, with the stand-in module's folder
/// first on `PYTHONPATH`.
fn passed_environment(shim: &Path) -> Vec<(String, OsString)> {
    let mut out: Vec<(String, OsString)> = PASSED_ENVIRONMENT
        .iter()
        .filter(|name| **name != "PYTHONPATH")
        .filter_map(|name| std::env::var_os(name).map(|v| (name.to_string(), v)))
        .collect();
    let mut python_path = vec![shim.to_path_buf()];
    if let Some(existing) = std::env::var_os("PYTHONPATH") {
        python_path.extend(std::env::split_paths(&existing).filter(|p| p.is_absolute()));
    }
    if let Ok(joined) = std::env::join_paths(python_path) {
        out.push(("PYTHONPATH".into(), joined));
    }
    out
}

/// The package folders of `packages` in [`AMENT_INDEX_SHIM`]'s format, in
/// [`MeshResolver::candidates`]' order.
fn package_roots(packages: &MeshResolver) -> OsString {
    let mut lines = Vec::new();
    let mut push = |kind: &str, root: &Path| {
        if let Some(root) = root.to_str().filter(|r| !r.contains('\n')) {
            lines.push(format!("{kind}\t{root}"));
        }
    };
    for d in &packages.search_paths {
        push("search", d);
    }
    for r in &packages.ros_package_path {
        push("ros", r);
    }
    for p in &packages.ament_prefix_path {
        push("ament", p);
    }
    for ancestor in packages.base_dir.ancestors() {
        push("ancestor", ancestor);
    }
    lines.join("\n").into()
}

fn write_shim(folder: &Path) -> std::io::Result<()> {
    let package = folder.join("ament_index_python");
    std::fs::create_dir_all(&package)?;
    std::fs::write(
        package.join("__init__.py"),
        "from .packages import PackageNotFoundError, get_package_prefix, get_package_share_directory\n",
    )?;
    std::fs::write(package.join("packages.py"), AMENT_INDEX_SHIM)
}

/// Why a run of `xacro` gave no URDF.
enum RunFailure {
    /// What the program did (exit code, time limit, output), with the end of its standard
    /// error.
    Program(String),
    /// A step the operating system refused, and its error.
    Io(&'static str, std::io::Error),
}

/// Waits for `child` (at most `timeout`), stops its process group, and returns its standard
/// output as text, or what went wrong (with the end of its standard error).
fn run(mut child: Child, timeout: Duration) -> Result<String, RunFailure> {
    let (Some(stdout), Some(stderr)) = (child.stdout.take(), child.stderr.take()) else {
        let _ = stop(&mut child);
        return Err(RunFailure::Program("cannot capture its output".into()));
    };
    // Both pipes are drained on their own threads so neither can fill up and stall the child;
    // the results come back over channels so that a pipe held open by an escaped process
    // cannot hold this thread.
    let (out_sender, out_receiver) = mpsc::channel();
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let read = stdout.take(MAX_OUTPUT_BYTES + 1).read_to_end(&mut bytes);
        let _ = out_sender.send(read.map(|_| bytes));
    });
    let (err_sender, err_receiver) = mpsc::channel();
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = stderr.take(MAX_OUTPUT_BYTES).read_to_end(&mut bytes);
        let _ = err_sender.send(bytes);
    });
    let started = Instant::now();
    let waited = loop {
        match has_ended(&mut child) {
            Ok(true) => break Ok(()),
            Ok(false) if started.elapsed() > timeout => {
                break Err(RunFailure::Program(format!(
                    "stopped after {} s",
                    timeout.as_secs_f64()
                )))
            }
            Ok(false) => std::thread::sleep(Duration::from_millis(5)),
            Err(e) => break Err(RunFailure::Io("cannot wait for it", e)),
        }
    };
    // Whatever the program left running is stopped with it; that closes the pipes.
    let status = stop(&mut child);
    let stdout = out_receiver.recv_timeout(DRAIN_GRACE).ok();
    let stderr = err_receiver.recv_timeout(DRAIN_GRACE).unwrap_or_default();
    let stderr = String::from_utf8_lossy(&stderr);
    let tail = tail(stderr.trim());
    waited.map_err(|failure| match failure {
        RunFailure::Program(message) => RunFailure::Program(with_stderr(message, tail)),
        io => io,
    })?;
    let status = status.map_err(|e| RunFailure::Io("cannot wait for it", e))?;
    if !status.success() {
        let code = match status.code() {
            Some(code) => format!("exit code {code}"),
            None => "ended by a signal".to_string(),
        };
        return Err(RunFailure::Program(with_stderr(code, tail)));
    }
    let program = |message: &str| RunFailure::Program(message.to_string());
    match stdout {
        Some(Ok(bytes)) if bytes.len() as u64 > MAX_OUTPUT_BYTES => Err(RunFailure::Program(
            format!("its output is larger than {} MiB", MAX_OUTPUT_BYTES >> 20),
        )),
        Some(Ok(bytes)) => String::from_utf8(bytes).map_err(|_| program("its output is not UTF-8")),
        Some(Err(e)) => Err(RunFailure::Io("cannot read its output", e)),
        None => Err(program(
            "its output stayed open after it ended (a process it started escaped)",
        )),
    }
}

/// Whether `child` has ended, without reaping it: while it is not reaped its process id, and
/// so its process group's id, cannot be taken by another process.
#[cfg(unix)]
fn has_ended(child: &mut Child) -> std::io::Result<bool> {
    let pid: libc::id_t = child.id();
    // SAFETY: `info` is a plain C struct that `waitid` fills in; zeroed, `si_pid` reads 0 when
    // no state change is reported (WNOHANG). WNOWAIT leaves the child to be reaped by `wait`.
    unsafe {
        let mut info: libc::siginfo_t = std::mem::zeroed();
        let done = libc::waitid(
            libc::P_PID,
            pid,
            &mut info,
            libc::WEXITED | libc::WNOHANG | libc::WNOWAIT,
        );
        if done != 0 {
            return Err(std::io::Error::last_os_error());
        }
        Ok(info.si_pid() != 0)
    }
}

#[cfg(not(unix))]
fn has_ended(child: &mut Child) -> std::io::Result<bool> {
    child.try_wait().map(|s| s.is_some())
}

/// Stops `child`'s whole process group (it leads one of its own) and reaps it.
fn stop(child: &mut Child) -> std::io::Result<std::process::ExitStatus> {
    #[cfg(unix)]
    if let Ok(group) = i32::try_from(child.id()) {
        // SAFETY: `kill` takes plain integers and touches no memory of this process. The
        // negative id names the process group that `process_group(0)` gave the child; the
        // child is not reaped yet (`has_ended` does not reap), so that id is still its group's.
        unsafe {
            libc::kill(-group, libc::SIGKILL);
        }
    }
    #[cfg(not(unix))]
    let _ = child.kill();
    child.wait()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xacro_files_are_named_by_their_extension_only() {
        assert!(is_xacro_path(Path::new("arm.xacro")));
        assert!(is_xacro_path(Path::new("dir/arm.urdf.XACRO")));
        assert!(!is_xacro_path(Path::new("arm.urdf")));
        assert!(!is_xacro_path(Path::new("xacro")));
        assert!(!is_xacro_path(Path::new("arm.xacro.urdf")));
    }

    #[test]
    fn programs_are_found_on_absolute_path_entries_only() {
        let dir = tempfile::tempdir().unwrap();
        let program = dir.path().join("xacro");
        std::fs::write(&program, "#!/bin/sh\n").unwrap();
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&program, std::fs::Permissions::from_mode(0o755)).unwrap();
        }
        let name = OsString::from("xacro");
        let absolute = std::env::join_paths([dir.path()]).unwrap();
        assert_eq!(find_program(&name, &absolute), Some(program.clone()));
        // A relative entry is skipped, even one that leads to the program from here.
        let cwd = std::env::current_dir().unwrap();
        let mut up = PathBuf::new();
        for _ in cwd.components().skip(1) {
            up.push("..");
        }
        let relative_dir = up.join(dir.path().strip_prefix("/").unwrap());
        assert!(relative_dir.join("xacro").is_file());
        let relative = std::env::join_paths([relative_dir.as_path(), Path::new("")]).unwrap();
        assert_eq!(find_program(&name, &relative), None);
        // A path is taken as it is, when it is an executable file.
        assert_eq!(
            find_program(&program.clone().into_os_string(), &OsString::new()),
            Some(program)
        );
        assert_eq!(
            find_program(&dir.path().join("none").into_os_string(), &absolute),
            None
        );
    }

    #[test]
    fn argument_names_and_values_are_checked() {
        let args = |pairs: &[(&str, &str)]| -> BTreeMap<String, String> {
            pairs
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect()
        };
        assert_eq!(
            argument_list(&args(&[("dof", "7"), ("_x1", "a b:=c")])).unwrap(),
            vec!["_x1:=a b:=c".to_string(), "dof:=7".to_string()]
        );
        for bad in ["", "1dof", "a-b", "a:=b", "--inorder", "é"] {
            let (name, _) = argument_list(&args(&[(bad, "1")])).unwrap_err();
            assert_eq!(name, bad);
        }
        assert!(argument_list(&args(&[("a", "x\0y")])).is_err());
        let long = "x".repeat(MAX_ARGUMENT_BYTES + 1);
        assert!(argument_list(&args(&[("a", &long)])).is_err());
    }
}
