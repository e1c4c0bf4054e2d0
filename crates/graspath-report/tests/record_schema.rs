//! Every per-candidate output carries exactly the columns of the record schema
//! (`graspath::select::record::COLUMNS`): `candidates.json`, `candidates.jsonl` and
//! `candidates.parquet` of a selection whose candidates cover every kind of value (feasible,
//! failing with colliding bodies, self-motion scores, a joint-limit penalty, approach and
//! retreat, a scene's clearance), and the column table of `docs/candidate-record.md`.
//!
//! To rewrite the docs' table after a change to the schema:
//! `GRASPATH_WRITE_DOCS=1 cargo test -p graspath-report --test record_schema`.

use graspath::select::record::{json_name, outputs, Group, JsonPlace, WhenAbsent, COLUMNS};
use graspath::select::record::{Column, Trajectories};
use graspath::select::{select_streaming, Streamed};
use graspath::task::{Task, TaskFile};
use graspath_report::{write_candidate_line, write_candidates_json, CandidatesParquet};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use serde_json::{Map, Value};
use std::collections::BTreeSet;
use std::path::PathBuf;

/// Baxter's left arm on a table, with an approach and a retreat, the self-motion optimised and
/// a joint-limit penalty and the object's weight: every column has a value in some record, and some candidates fail
/// with a collision (bodies named) or out of reach.
const TASK: &str = r#"
robot: { builtin: baxter }
arms: left
object:
  pose: { xyz: [0.75, 0.0, -0.10] }
  shape: { box: { size: [0.06, 0.40, 0.10] } }
  mass: 0.05
candidates:
  family: { edge: { count: 12, depth: 0.02, margin: 0.02 } }
trajectory:
  samples_per_step: 3
  steps:
    - { lift: 0.2, label: pick }
    - { move: [0.0, 0.3, 0.0], label: move }
    - { place: 0.2, label: place }
index: { joint_limit_penalty: true }
ik: { branches: 4, redundancy: optimize }
scene:
  table: { height: -0.15 }
  obstacles:
    - { name: wall, box: { size: [0.05, 0.8, 0.5] }, pose: { xyz: [1.00, 0.3, 0.10] } }
    - { name: post, cylinder: { radius: 0.03, length: 0.6 }, pose: { xyz: [0.62, 0.45, 0.15] } }
gripper: { builtin: baxter }
approach: { distance: 0.10, samples: 3 }
retreat: { distance: 0.10, samples: 3 }
"#;

fn task() -> Task {
    let file = TaskFile::parse(TASK, "schema.yaml", "yaml").expect("the test task parses");
    Task::from_file(&file, "schema.yaml", std::path::Path::new(".")).expect("a valid task")
}

/// The JSON field names of `output`'s columns: each record's top-level keys come from these
/// (a group's name standing for its columns), and its groups' keys from their members.
fn json_keys(output: u8) -> (BTreeSet<String>, BTreeSet<(String, String)>) {
    let mut top = BTreeSet::new();
    let mut grouped = BTreeSet::new();
    for c in COLUMNS.iter().filter(|c| c.in_output(output)) {
        match c.json {
            JsonPlace::Top => {
                top.insert(c.name.to_string());
            }
            JsonPlace::In(group, name) => {
                top.insert(group.name().to_string());
                grouped.insert((group.name().to_string(), name.to_string()));
            }
        }
    }
    (top, grouped)
}

/// Checks one JSON record against the schema of `output`: no key outside it, every key that is
/// never left out present, and the keys in byte order. Returns the record's top-level and
/// grouped keys.
fn check_record(record: &Map<String, Value>, output: u8) -> Vec<String> {
    let (top, grouped) = json_keys(output);
    let keys: Vec<&String> = record.keys().collect();
    let mut seen = Vec::new();
    let groups = [Group::Failure, Group::SelfMotion].map(Group::name);
    for key in &keys {
        assert!(top.contains(*key), "{key} is not a column of the schema");
        if !groups.contains(&key.as_str()) {
            seen.push((*key).clone());
        }
    }
    for c in COLUMNS.iter().filter(|c| c.in_output(output)) {
        if c.json == JsonPlace::Top && c.json_absent == WhenAbsent::Null {
            assert!(
                record.contains_key(c.name),
                "{} is missing: {record:?}",
                c.name
            );
        }
    }
    for group in [Group::Failure, Group::SelfMotion] {
        if let Some(Value::Object(members)) = record.get(group.name()) {
            for key in members.keys() {
                assert!(
                    grouped.contains(&(group.name().to_string(), key.clone())),
                    "{}.{key} is not a column of the schema",
                    group.name()
                );
                seen.push(format!("{}.{key}", group.name()));
            }
        } else if group.when_absent() == WhenAbsent::Null {
            assert_eq!(record.get(group.name()), Some(&Value::Null));
        }
    }
    seen
}

/// Every schema column of `output` under its JSON name (`group.field` inside a group).
fn all_json_names(output: u8) -> BTreeSet<String> {
    COLUMNS
        .iter()
        .filter(|c| c.in_output(output))
        .map(|c| match c.json {
            JsonPlace::Top => c.name.to_string(),
            JsonPlace::In(group, _) => format!("{}.{}", group.name(), json_name(c)),
        })
        .collect()
}

#[test]
fn json_records_carry_exactly_the_schema_columns() {
    let task = task();
    let selection = graspath::select::select(&task, &|| {}).unwrap();
    let mut bytes = Vec::new();
    write_candidates_json(&mut bytes, &selection, Trajectories::All).unwrap();
    let records: Vec<Map<String, Value>> = serde_json::from_slice(&bytes).unwrap();
    assert_eq!(records.len(), 12);
    let mut seen = BTreeSet::new();
    for record in &records {
        seen.extend(check_record(record, outputs::JSON));
    }
    // Over the whole selection every column shows up: the task exercises each one.
    let bodies_seen = records.iter().any(|r| r["failure"].get("bodies").is_some());
    assert!(bodies_seen, "the task has a collision naming its bodies");
    assert_eq!(seen, all_json_names(outputs::JSON));
}

/// Streams the test task, writing `candidates.jsonl` lines and `candidates.parquet`.
fn streamed_outputs(dir: &std::path::Path) -> (Vec<u8>, PathBuf) {
    let task = task();
    let mut lines = Vec::new();
    let parquet_path = dir.join("candidates.parquet");
    let file = std::fs::File::create(&parquet_path).unwrap();
    let mut parquet = CandidatesParquet::new(file, Trajectories::All).unwrap();
    select_streaming::<graspath::grasp::CandidateError>(&task, &|| {}, |streamed: Streamed<'_>| {
        write_candidate_line(&mut lines, &streamed, Trajectories::All).unwrap();
        parquet.push(&streamed).unwrap();
        Ok(())
    })
    .unwrap();
    parquet.finish().unwrap();
    (lines, parquet_path)
}

#[test]
fn streamed_outputs_carry_exactly_the_schema_columns() {
    let dir = tempfile::tempdir().unwrap();
    let (lines, parquet_path) = streamed_outputs(dir.path());
    let mut seen = BTreeSet::new();
    for line in lines.split(|b| *b == b'\n').filter(|l| !l.is_empty()) {
        let record: Map<String, Value> = serde_json::from_slice(line).unwrap();
        seen.extend(check_record(&record, outputs::JSON_LINES));
        assert!(!record.contains_key("rank") && !record.contains_key("pareto"));
    }
    assert_eq!(seen, all_json_names(outputs::JSON_LINES));

    let reader =
        ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&parquet_path).unwrap())
            .unwrap();
    let names: Vec<String> = reader
        .schema()
        .fields()
        .iter()
        .map(|f| f.name().clone())
        .collect();
    let expected: Vec<String> = COLUMNS
        .iter()
        .filter(|c| c.in_output(outputs::PARQUET))
        .map(|c| c.name.to_string())
        .collect();
    assert_eq!(names, expected);
    let rows: usize = reader.build().unwrap().map(|b| b.unwrap().num_rows()).sum();
    assert_eq!(rows, 12);
}

/// The docs' column table, rendered from the schema.
fn docs_table() -> String {
    let mut table = String::from(
        "| column | type | unit | json | jsonl | parquet | arrays | select_batch | meaning |\n\
         |---|---|---|:-:|:-:|:-:|:-:|:-:|---|\n",
    );
    let mark = |c: &Column, output: u8| if c.in_output(output) { "✓" } else { "" };
    for c in COLUMNS {
        let name = match c.json {
            JsonPlace::Top => format!("`{}`", c.name),
            JsonPlace::In(group, field) => {
                format!("`{}` (JSON: `{}.{field}`)", c.name, group.name())
            }
        };
        let nullable = if c.nullable { ", nullable" } else { "" };
        table.push_str(&format!(
            "| {name} | {}{nullable} | {} | {} | {} | {} | {} | {} | {} |\n",
            c.kind.name(),
            c.unit,
            mark(c, outputs::JSON),
            mark(c, outputs::JSON_LINES),
            mark(c, outputs::PARQUET),
            mark(c, outputs::ARRAYS),
            mark(c, outputs::BATCH),
            c.doc.replace('|', "\\|"),
        ));
    }
    table
}

#[test]
fn the_docs_table_is_the_schema() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/candidate-record.md");
    let text = std::fs::read_to_string(&path).unwrap();
    const START: &str = "<!-- columns: generated from the schema -->\n";
    const END: &str = "<!-- end of columns -->";
    let start = text.find(START).expect("the table's start marker") + START.len();
    let end = text.find(END).expect("the table's end marker");
    let table = docs_table();
    if std::env::var_os("GRASPATH_WRITE_DOCS").is_some() {
        let rewritten = format!("{}{table}{}", &text[..start], &text[end..]);
        std::fs::write(&path, rewritten).unwrap();
        return;
    }
    assert!(
        text[start..end] == table,
        "docs/candidate-record.md's table differs from the schema; rewrite it with \
         GRASPATH_WRITE_DOCS=1 cargo test -p graspath-report --test record_schema"
    );
}

#[test]
fn column_names_are_unique_and_numpy_outputs_have_a_numpy_form() {
    let names: BTreeSet<&str> = COLUMNS.iter().map(|c| c.name).collect();
    assert_eq!(names.len(), COLUMNS.len());
    for c in COLUMNS {
        if c.in_output(outputs::ARRAYS) || c.in_output(outputs::BATCH) {
            assert!(
                !matches!(
                    c.kind,
                    graspath::select::record::Kind::Bodies | graspath::select::record::Kind::Motion
                ),
                "{} has no numpy form",
                c.name
            );
        }
        if c.in_output(outputs::BATCH) {
            // The batch's tasks differ in path length: no per-sample column.
            assert_ne!(c.kind, graspath::select::record::Kind::Series, "{}", c.name);
        }
        if let Some(other) = c.numpy_fallback {
            let other = graspath::select::record::column_named(other).expect("a column");
            assert_eq!(other.kind, c.kind);
        }
    }
}
