//! Every URDF of the `example-robot-data` package (PyPI; Gepetto/LAAS: 69 files of arms,
//! hands, humanoids and quadrupeds) loads, or is refused with a reason a user can act on. None
//! may be refused for xacro text in a comment: xacro-generated URDFs keep such comments, and
//! 11 of these files have them (`<xacro:` in TALOS, TIAGo Pro, Bolt, finger_edu, ...). The
//! table of outcomes is printed (`--nocapture`) and recorded in TESTING.md.
//!
//! Needs `GRASPATH_ROBOT_DATA` (see `tests/robot_data.rs`); skips without it, except in CI.

mod common;

use graspath::robot::{RobotError, RobotSource};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn urdf_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            urdf_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "urdf") {
            out.push(path);
        }
    }
}

#[test]
fn every_example_robot_data_urdf_loads_or_is_refused_with_a_reason() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let share = data.parent().and_then(Path::parent).unwrap().to_path_buf();
    let mut files = Vec::new();
    urdf_files(&data, &mut files);
    assert!(files.len() >= 60, "only {} URDFs found", files.len());
    let mut loaded = 0;
    let mut with_xacro_comments = 0;
    let mut refused: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for path in &files {
        let relative = path.strip_prefix(&data).unwrap().display().to_string();
        let text = std::fs::read_to_string(path).unwrap();
        if text.contains("<xacro:") {
            with_xacro_comments += 1;
        }
        let source = RobotSource::Urdf {
            path: path.clone(),
            search_paths: vec![share.clone()],
            xacro_args: Default::default(),
        };
        match source.load() {
            Ok(model) => {
                // Every link can be reached from the model: a chain from the first link to
                // each other one builds or names why not.
                assert!(!model.link_names().is_empty(), "{relative}: no links");
                loaded += 1;
            }
            Err(e) => {
                assert!(
                    !matches!(e, RobotError::XacroMarkup { .. } | RobotError::Xacro { .. }),
                    "{relative}: refused as xacro: {e}"
                );
                let message = e.to_string();
                assert!(
                    message.contains(&relative) || message.contains(path.to_str().unwrap()),
                    "{relative}: the refusal does not name the file: {message}"
                );
                // The parser's own words (`custom: missing field ...`) tell a user nothing.
                assert!(
                    !message.contains("custom:"),
                    "{relative}: refused in the parser's words: {message}"
                );
                refused.entry(message).or_default().push(relative);
            }
        }
    }
    println!(
        "example-robot-data: {} URDFs, {loaded} loaded, {} refused; {with_xacro_comments} carry xacro text in comments",
        files.len(),
        files.len() - loaded
    );
    for (message, files) in &refused {
        println!("refused ({}): {message}", files.len());
    }
    assert!(with_xacro_comments > 0, "the corpus has no xacro comments");
}
