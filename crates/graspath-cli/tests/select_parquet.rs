//! `graspath select --format parquet`: every row of `candidates.parquet` equals the same
//! candidate's `candidates.jsonl` record field by field (the JSON record is the oracle: another
//! writer, read back by another reader), `ranking.parquet` equals `ranking.jsonl`, the files
//! are the same bytes at one and two threads, and the trajectories are kept as `--trajectories`
//! says.

use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, UInt64Type};
use arrow_array::{Array, RecordBatch};
use arrow_schema::DataType;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use serde_json::{json, Map, Value};
use std::path::Path;

mod common;

use common::{example, faces_task, read_lines};

/// `graspath select` as [`common::select`], with `--allow-empty`.
fn select(task: &Path, out: &Path, extra: &[&str], threads: &str) {
    let mut args = vec!["--allow-empty"];
    args.extend(extra);
    common::select(task, out, &args, threads);
}

/// One cell of a column as JSON (null for a null cell).
fn cell(column: &dyn Array, row: usize) -> Value {
    if column.is_null(row) {
        return Value::Null;
    }
    match column.data_type() {
        DataType::Utf8 => json!(column.as_string::<i32>().value(row)),
        DataType::UInt64 => json!(column.as_primitive::<UInt64Type>().value(row)),
        DataType::Float64 => json!(column.as_primitive::<Float64Type>().value(row)),
        DataType::Boolean => json!(column.as_boolean().value(row)),
        DataType::FixedSizeList(..) => {
            let values = column.as_fixed_size_list().value(row);
            Value::Array((0..values.len()).map(|k| cell(&values, k)).collect())
        }
        DataType::List(_) => {
            let values = column.as_list::<i32>().value(row);
            Value::Array((0..values.len()).map(|k| cell(&values, k)).collect())
        }
        other => panic!("unexpected column type {other}"),
    }
}

/// Every row of a Parquet file as a JSON object keyed by column name.
fn read_parquet(path: &Path) -> Vec<Map<String, Value>> {
    let file = std::fs::File::open(path).unwrap();
    let reader = ParquetRecordBatchReaderBuilder::try_new(file)
        .unwrap()
        .build()
        .unwrap();
    let mut rows = Vec::new();
    for batch in reader {
        let batch: RecordBatch = batch.unwrap();
        let schema = batch.schema();
        for row in 0..batch.num_rows() {
            let mut record = Map::new();
            for (field, column) in schema.fields().iter().zip(batch.columns()) {
                record.insert(field.name().clone(), cell(column.as_ref(), row));
            }
            rows.push(record);
        }
    }
    rows
}

/// What the Parquet row of a `candidates.jsonl` record must hold: its scalars under the
/// column names (nested objects flattened, the pose's rows concatenated; a left-out field is
/// null) and its motions (a left-out motion is empty or null).
fn expected_row(record: &Value) -> Map<String, Value> {
    let field = |name: &str| record.get(name).cloned().unwrap_or(Value::Null);
    let mut row = Map::new();
    for name in [
        "arm",
        "id",
        "label",
        "contact",
        "likelihood",
        "log_likelihood",
        "feasible",
        "rejected",
        "score",
        "mu_l2",
        "mu_linf",
        "mu_linf_infinite",
        "mu_l1",
        "mu_rms",
        "skipped_samples",
        "yoshikawa_at_grasp",
        "yoshikawa_penalized_at_grasp",
        "inverse_condition_at_grasp",
        "inverse_condition_squared_at_grasp",
        "feasible_branches",
        "limit_distance_min",
        "hugs_limit",
        "clearance",
        "torque_margin",
        "payload_capacity",
        "dynamic_manipulability",
        "duration",
        "approach_duration",
        "carry_duration",
        "retreat_duration",
        "spline_deviation",
        "limit_excursion",
    ] {
        row.insert(name.into(), field(name));
    }
    let rows = field("object_from_wrist");
    let flat: Vec<Value> = rows
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|r| r.as_array().unwrap().clone())
        .collect();
    row.insert("object_from_wrist".into(), Value::Array(flat));
    let failure = field("failure");
    for (column, key) in [
        ("failure_reason", "reason"),
        ("failure_phase", "phase"),
        ("failure_sample", "sample"),
        ("failure_detail", "detail"),
        ("failure_joint", "joint"),
    ] {
        row.insert(
            column.into(),
            failure.get(key).cloned().unwrap_or(Value::Null),
        );
    }
    let motion = field("self_motion");
    for (column, key) in [
        ("self_motion_mu_l2_first_branch", "mu_l2_first_branch"),
        ("self_motion_mu_l2_min", "mu_l2_min"),
        ("self_motion_mu_l2_max", "mu_l2_max"),
    ] {
        row.insert(
            column.into(),
            motion.get(key).cloned().unwrap_or(Value::Null),
        );
    }
    row
}

/// A motion column's value, with null and a left-out field both read as "no motion".
fn motion(value: Option<&Value>) -> Vec<Value> {
    value.and_then(Value::as_array).cloned().unwrap_or_default()
}

fn check_parquet_equals_jsonl(task: &Path, dir: &Path, trajectories: &str) {
    let (lines_out, parquet_out) = (dir.join("jsonl"), dir.join("parquet"));
    let args = |format: &'static str| ["--format", format, "--trajectories", trajectories];
    select(task, &lines_out, &args("jsonl"), "2");
    select(task, &parquet_out, &args("parquet"), "2");
    let records = read_lines(&lines_out.join("candidates.jsonl"));
    let rows = read_parquet(&parquet_out.join("candidates.parquet"));
    assert_eq!(rows.len(), records.len());
    for (row, record) in rows.iter().zip(&records) {
        let mut scalars = row.clone();
        for name in [
            "joint_trajectory",
            "approach_trajectory",
            "retreat_trajectory",
        ] {
            let stored = scalars.remove(name);
            assert_eq!(
                motion(stored.as_ref()),
                motion(record.get(name)),
                "{name} of {} {}",
                record["arm"],
                record["id"]
            );
        }
        assert_eq!(
            scalars,
            expected_row(record),
            "candidate {} {}",
            record["arm"],
            record["id"]
        );
    }
    let ranking: Vec<Value> = read_parquet(&parquet_out.join("ranking.parquet"))
        .into_iter()
        .map(Value::Object)
        .collect();
    assert_eq!(ranking, read_lines(&lines_out.join("ranking.jsonl")));
    for name in ["summary.json", "pairs.json"] {
        assert_eq!(
            std::fs::read(lines_out.join(name)).ok(),
            std::fs::read(parquet_out.join(name)).ok(),
            "{name}"
        );
    }
}

#[test]
fn one_arm_rows_equal_the_jsonl_records_across_batches() {
    // 4500 candidates: more than one batch of rows (4096) is written.
    let dir = tempfile::tempdir().unwrap();
    let task = faces_task(dir.path(), 4500, 6);
    check_parquet_equals_jsonl(&task, dir.path(), "feasible");
}

#[test]
fn two_arm_rows_with_every_motion_equal_the_jsonl_records() {
    let dir = tempfile::tempdir().unwrap();
    check_parquet_equals_jsonl(&example("pick_and_place_both.yaml"), dir.path(), "all");
}

#[test]
fn parquet_files_are_the_same_bytes_at_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let task = faces_task(dir.path(), 300, 6);
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    select(&task, &one, &["--format", "parquet"], "1");
    select(&task, &two, &["--format", "parquet"], "2");
    for name in ["candidates.parquet", "ranking.parquet", "summary.json"] {
        assert!(
            std::fs::read(one.join(name)).unwrap() == std::fs::read(two.join(name)).unwrap(),
            "{name} differs between one and two threads"
        );
    }
    // No motions with --trajectories none: the three columns are null in every row.
    let none = dir.path().join("none");
    select(
        &task,
        &none,
        &["--format", "parquet", "--trajectories", "none"],
        "2",
    );
    for row in read_parquet(&none.join("candidates.parquet")) {
        assert_eq!(row["joint_trajectory"], Value::Null);
    }
}
