//! The task-file reference in the docs lists exactly the spellings the loader reads: each
//! setting's commented alternatives (`mode: twist  # twist (default) | translation | rotation`)
//! are compared with its spelling table.

use graspath::grasp::{GraspFormat, GraspFrame};
use graspath::manipulability::{IndexMeasure, JacobianRows, Norm, NormSamples};
use graspath::spelling::Spelled;
use graspath::task::Redundancy;
use std::path::Path;

/// The first word of each `|`-separated alternative in the comment of the reference line
/// `  {key}: ...  # a | b | c`, continued on the comment-only lines below it.
fn documented_alternatives(doc: &str, key: &str) -> Vec<String> {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../docs")
            .join(doc),
    )
    .unwrap_or_else(|e| panic!("docs/{doc}: {e}"));
    let lines: Vec<&str> = text.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.trim_start().starts_with(&format!("{key}:")) && l.contains('#'))
        .unwrap_or_else(|| panic!("docs/{doc} has no commented reference line for `{key}:`"));
    let mut comment = lines[start].split_once('#').unwrap().1.to_string();
    for line in &lines[start + 1..] {
        match line.trim_start().strip_prefix('#') {
            Some(rest) => {
                comment.push(' ');
                comment.push_str(rest);
            }
            None => break,
        }
    }
    comment
        .split('|')
        .filter_map(|alternative| {
            let word: String = alternative
                .trim_start()
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            (!word.is_empty()).then_some(word)
        })
        .collect()
}

fn check<T: Spelled>(doc: &str, key: &str) {
    assert_eq!(
        documented_alternatives(doc, key),
        T::names(),
        "docs/{doc}: `{key}`"
    );
}

#[test]
fn the_task_file_reference_lists_every_spelling() {
    check::<IndexMeasure>("task-file.md", "measure");
    check::<NormSamples>("task-file.md", "over");
    check::<Norm>("task-file.md", "norm");
    check::<GraspFormat>("grasp-files.md", "format");
    check::<GraspFrame>("grasp-files.md", "frame");
    assert_eq!(
        documented_alternatives("task-file.md", "mode"),
        JacobianRows::MODES
    );
    // The reference lists the default first, so the order differs from the table's.
    let mut redundancy = documented_alternatives("task-file.md", "redundancy");
    redundancy.sort();
    let mut names = Redundancy::names();
    names.sort();
    assert_eq!(redundancy, names, "docs/task-file.md: `redundancy`");
}

#[test]
fn aliases_are_documented_beside_their_value() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/grasp-files.md"),
    )
    .unwrap();
    for format in GraspFormat::ALL {
        for alias in format.aliases() {
            assert!(
                text.contains(&format!("{} ({alias})", format.as_str())),
                "{alias}"
            );
        }
    }
}
