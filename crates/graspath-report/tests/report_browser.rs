//! The HTML report in a real browser: headless Chromium opens `report.html#selftest`, the page
//! runs its own checks (no errors, the canvas is drawn, every candidate is listed, clicking a row
//! shows that candidate, the animation advances) and writes the results into the DOM, which
//! `--dump-dom` hands back; a report of a task in a scene also checks that the scene is drawn,
//! the collision shapes move and a collision is shown with its bodies highlighted. Every report
//! also checks the staging: the "loading" text is shown until the scene is ready and then
//! hidden, the camera as placed on load sees the whole box of the robot and the task, the legend
//! names each arm in its colour, the torso is drawn, and the side panel follows the slider. A
//! task that times motions plays them in real time (each arm at an IK sample when its timed
//! motion reaches it, half a motion second per second at 0.5×, durations shown); one with
//! `timing: false` plays per sample. Screenshots are saved to `target/test-artifacts/report.png`
//! and `report-scene.png`.
//!
//! Skipped with a message when Chromium is not installed, except under CI (`CI` set), where
//! `.ci/run` installs it and its absence is a failure.

use graspath::output_files::{write_files, Existing};
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

/// Writes the report of `task` into `dir` and returns the page's self-test result.
fn self_test(browser: &Path, task: &Task, dir: &Path) -> String {
    let selection = select(task, &|| {}).unwrap();
    let files = render_report(task, &selection, None).unwrap();
    write_files(dir, &files, Existing::Refuse).unwrap();
    let page = dir.join("report.html");
    let url = format!("file://{}", page.display());
    let dom = run_chromium(
        browser,
        &format!("{url}#selftest"),
        &["--virtual-time-budget=8000", "--dump-dom"],
    );
    let start = dom
        .find("<pre id=\"selftest-result\"")
        .unwrap_or_else(|| panic!("no self-test result in the page (DOM {} bytes)", dom.len()));
    let end = start + dom[start..].find("</pre>").expect("a closed result");
    let result = dom[start..end].to_string();
    println!("{result}");
    assert!(
        result.contains("data-passed=\"true\"") && result.contains("SELFTEST PASSED"),
        "the page's self-test failed:\n{result}"
    );
    result
}

fn browser_or_skip() -> Option<PathBuf> {
    let browser = chromium();
    if browser.is_none() {
        if std::env::var_os("CI").is_some() {
            panic!("chromium is not installed; .ci/run installs it (apt-get install chromium)");
        }
        eprintln!("skipped: chromium is not installed (apt-get install chromium)");
    }
    browser
}

/// A task in a scene (Baxter's left arm, a finite table, a wall, a post and a beam that the
/// arm runs into for some grasps, approach and retreat, the Baxter gripper).
const SCENE_TASK: &str = r#"
robot: { builtin: baxter }
arms: left
object:
  pose: { xyz: [0.75, 0.0, -0.10] }
  shape: { box: { size: [0.06, 0.40, 0.10] } }
candidates:
  family: { edge: { count: 11 } }
trajectory:
  samples_per_step: 3
  steps: [ { lift: 0.2 }, { move: [0.0, 0.3, 0.0] }, { place: 0.2 } ]
scene:
  table: { height: -0.15, size: [1.2, 1.6], centre: [0.8, 0.1] }
  obstacles:
    - { name: wall, box: { size: [0.05, 0.6, 0.5] }, pose: { xyz: [1.25, 0.0, 0.1] } }
    - { name: post, cylinder: { radius: 0.03, length: 0.15 }, pose: { xyz: [0.75, -0.26, -0.075] } }
    - { name: beam, capsule: { radius: 0.02, length: 0.4 }, pose: { xyz: [0.6, -0.2, 0.3], rpy_deg: [90, 0, 0] } }
approach: { distance: 0.10, samples: 3 }
retreat: { distance: 0.10, samples: 3 }
gripper: { builtin: baxter }
"#;

#[test]
fn the_report_of_a_scene_passes_its_self_test_in_headless_chromium() {
    let Some(browser) = browser_or_skip() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.yaml");
    std::fs::write(&path, SCENE_TASK).unwrap();
    let task = Task::load(&path).unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let result = self_test(&browser, &task, &out);
    for check in [
        "PASS scene bodies are drawn",
        "PASS collision shapes move with the arm",
        "PASS a collision is shown with its two bodies highlighted",
        "PASS clicking a row shows that candidate",
        "PASS loading text until the scene is ready",
        "PASS camera fits the robot and the task",
        "PASS legend names every arm in its colour",
        "PASS side panel follows the slider",
        "PASS the arm is at each sample when its timed motion reaches it",
        "PASS plays in real time",
        "PASS durations in the table and the side panel",
        "PASS no errors",
    ] {
        assert!(result.contains(check), "missing '{check}' in:\n{result}");
    }
    let url = format!("file://{}", out.join("report.html").display());
    screenshot(&browser, &url, "report-scene.png");
}

#[test]
fn the_report_passes_its_self_test_in_headless_chromium() {
    let Some(browser) = browser_or_skip() else {
        return;
    };
    let example =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/pick_and_place_both.yaml");
    let task = Task::load(&example).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let result = self_test(&browser, &task, dir.path());
    let url = format!("file://{}", dir.path().join("report.html").display());
    assert!(
        !result.contains("scene bodies"),
        "no world in a task without one"
    );
    for check in [
        "PASS animation advances",
        "PASS canvas has drawn pixels",
        "PASS table lists every candidate",
        "PASS clicking a row shows that candidate",
        "PASS loading text until the scene is ready",
        "PASS camera fits the robot and the task",
        "PASS legend names every arm in its colour",
        "PASS torso drawn",
        "PASS side panel follows the slider",
        "PASS the arm is at each sample when its timed motion reaches it",
        "PASS plays in real time",
        "PASS durations in the table and the side panel",
        "PASS no errors",
    ] {
        assert!(result.contains(check), "missing '{check}' in:\n{result}");
    }
    // Both arms are named in the legend (the page's check compares their colours).
    for arm in ["left arm", "right arm"] {
        assert!(result.contains(arm), "the legend lacks '{arm}':\n{result}");
    }

    screenshot(&browser, &url, "report.png");
}

/// A screenshot of `url` for people (a test artefact), checked to be a drawn page.
fn screenshot(browser: &Path, url: &str, name: &str) {
    let artifacts = artifacts_dir();
    std::fs::create_dir_all(&artifacts).unwrap();
    let shot = artifacts.join(name);
    let _ = std::fs::remove_file(&shot);
    run_chromium(
        browser,
        url,
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

#[test]
fn the_report_of_an_untimed_task_plays_per_sample_in_headless_chromium() {
    let Some(browser) = browser_or_skip() else {
        return;
    };
    let example =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/pick_and_place_left.yaml");
    let text = std::fs::read_to_string(&example).unwrap() + "timing: false\n";
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("untimed.yaml");
    std::fs::write(&path, text).unwrap();
    let task = Task::load(&path).unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let result = self_test(&browser, &task, &out);
    for check in [
        "PASS plays per sample",
        "PASS animation advances",
        "PASS side panel follows the slider",
        "PASS no errors",
    ] {
        assert!(result.contains(check), "missing '{check}' in:\n{result}");
    }
    assert!(!result.contains("real time"), "{result}");
}
