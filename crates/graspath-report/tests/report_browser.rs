//! The HTML report in a real browser: headless Chromium opens `report.html#selftest`, the page
//! runs its own checks (no errors, the canvas is drawn, every candidate is listed, clicking a row
//! shows that candidate, the animation advances) and writes the results into the DOM, which
//! `--dump-dom` hands back. A screenshot is saved to `target/test-artifacts/report.png`.
//!
//! Skipped with a message when Chromium is not installed, except under CI (`CI` set), where
//! `.ci/run` installs it and its absence is a failure.

use graspath::fsutil::{write_files, Existing};
use graspath::select::select;
use graspath::task::Task;
use graspath_report::render_report;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn chromium() -> Option<PathBuf> {
    let names = ["chromium", "chromium-browser", "google-chrome"];
    let from_env = std::env::var_os("CHROMIUM").map(PathBuf::from);
    let on_path = std::env::var_os("PATH").into_iter().flat_map(|paths| {
        std::env::split_paths(&paths)
            .flat_map(|dir| names.iter().map(move |n| dir.join(n)))
            .collect::<Vec<_>>()
    });
    from_env.into_iter().chain(on_path).find(|p| p.is_file())
}

/// Runs Chromium headless on `url` with extra arguments; returns stdout. Gives up after 180 s.
fn run_chromium(browser: &Path, url: &str, extra: &[&str]) -> String {
    let profile = tempfile::tempdir().unwrap();
    let mut child = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(extra)
        .arg(url)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("chromium starts");
    let mut stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        std::io::Read::read_to_string(&mut stdout, &mut text).ok();
        text
    });
    let started = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if started.elapsed() > Duration::from_secs(180) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish within 180 s on {url}");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    reader.join().unwrap()
}

fn artifacts_dir() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target"));
    target.join("test-artifacts")
}

#[test]
fn the_report_passes_its_self_test_in_headless_chromium() {
    let Some(browser) = chromium() else {
        if std::env::var_os("CI").is_some() {
            panic!("chromium is not installed; .ci/run installs it (apt-get install chromium)");
        }
        eprintln!("skipped: chromium is not installed (apt-get install chromium)");
        return;
    };
    let example =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/pick_and_place_both.yaml");
    let task = Task::load(&example).unwrap();
    let selection = select(&task, &|| {});
    let files = render_report(&task, &selection).unwrap();
    let dir = tempfile::tempdir().unwrap();
    write_files(dir.path(), &files, Existing::Refuse).unwrap();
    let page = dir.path().join("report.html");
    let url = format!("file://{}", page.display());

    let dom = run_chromium(
        &browser,
        &format!("{url}#selftest"),
        &["--virtual-time-budget=8000", "--dump-dom"],
    );
    let start = dom
        .find("<pre id=\"selftest-result\"")
        .unwrap_or_else(|| panic!("no self-test result in the page (DOM {} bytes)", dom.len()));
    let end = start + dom[start..].find("</pre>").expect("a closed result");
    let result = &dom[start..end];
    println!("{result}");
    assert!(
        result.contains("data-passed=\"true\"") && result.contains("SELFTEST PASSED"),
        "the page's self-test failed:\n{result}"
    );
    for check in [
        "PASS animation advances",
        "PASS canvas has drawn pixels",
        "PASS table lists every candidate",
        "PASS clicking a row shows that candidate",
        "PASS no errors",
    ] {
        assert!(result.contains(check), "missing '{check}' in:\n{result}");
    }

    // A screenshot for people (a test artefact), checked to be a drawn page.
    let artifacts = artifacts_dir();
    std::fs::create_dir_all(&artifacts).unwrap();
    let shot = artifacts.join("report.png");
    let _ = std::fs::remove_file(&shot);
    run_chromium(
        &browser,
        &url,
        &[
            "--virtual-time-budget=3000",
            "--window-size=1280,1000",
            &format!("--screenshot={}", shot.display()),
        ],
    );
    let bytes = std::fs::read(&shot).expect("the screenshot was written");
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let reader = decoder.read_info().expect("the screenshot is a PNG");
    assert_eq!((reader.info().width, reader.info().height), (1280, 1000));
    println!("screenshot: {}", shot.display());
}
