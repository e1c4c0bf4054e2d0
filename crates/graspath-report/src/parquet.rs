//! Parquet output of a streamed selection (`graspath select --format parquet`, see
//! docs/streaming.md): `candidates.parquet`, one row per candidate and arm in candidate order,
//! arm by arm, with the scalar fields of its `candidates.json` record and, as `--trajectories`
//! says, its joint motions (row groups are written as the candidates are scored, so memory does
//! not grow with their number); `ranking.parquet`, the ranks, written at the end.
//!
//! Columns keep the JSON records' names and units: `mu_l2` etc. as the index's norms, poses
//! `object_from_wrist` as the 16 entries of the 4 × 4 matrix row by row (object frame, m),
//! joint values in rad (m for prismatic joints). A JSON `null` is a Parquet null. The bytes
//! depend only on the records (no timestamps), so a run is reproducible byte for byte.

use crate::json::{ranked_order, Trajectories};
use arrow_array::builder::{
    BooleanBuilder, FixedSizeListBuilder, Float64Builder, ListBuilder, StringBuilder, UInt64Builder,
};
use arrow_array::{ArrayRef, RecordBatch};
use arrow_schema::{ArrowError, DataType, Field, Schema};
use graspath::select::{Scored, Selection, Streamed};
use parquet::arrow::ArrowWriter;
use parquet::basic::Compression;
use parquet::errors::ParquetError;
use parquet::file::properties::WriterProperties;
use std::io::Write;
use std::sync::Arc;

/// Rows buffered before they are handed to the Parquet writer as one batch.
const BATCH_ROWS: usize = 4096;

/// Rows per row group: bounds what the writer holds before it writes (the writer's default is
/// about a million rows).
const ROW_GROUP_ROWS: usize = 16_384;

/// Why a Parquet file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ParquetOutputError {
    /// The Parquet writer failed (including the underlying file's I/O errors).
    #[error(transparent)]
    Parquet(#[from] ParquetError),
    /// A batch could not be assembled (a bug: the columns are built together).
    #[error(transparent)]
    Arrow(#[from] ArrowError),
}

fn properties() -> WriterProperties {
    WriterProperties::builder()
        .set_compression(Compression::SNAPPY)
        .set_max_row_group_size(ROW_GROUP_ROWS)
        .set_created_by("graspath".to_string())
        .build()
}

fn list_of_lists() -> DataType {
    let inner = DataType::List(Arc::new(Field::new("item", DataType::Float64, true)));
    DataType::List(Arc::new(Field::new("item", inner, true)))
}

fn candidates_schema() -> Schema {
    let f64_field = |name: &str| Field::new(name, DataType::Float64, true);
    Schema::new(vec![
        Field::new("arm", DataType::Utf8, false),
        Field::new("id", DataType::UInt64, false),
        Field::new("label", DataType::Utf8, false),
        Field::new(
            "object_from_wrist",
            DataType::FixedSizeList(Arc::new(Field::new("item", DataType::Float64, true)), 16),
            false,
        ),
        Field::new(
            "contact",
            DataType::FixedSizeList(Arc::new(Field::new("item", DataType::Float64, true)), 3),
            true,
        ),
        f64_field("likelihood"),
        f64_field("log_likelihood"),
        Field::new("feasible", DataType::Boolean, false),
        Field::new("failure_reason", DataType::Utf8, true),
        Field::new("failure_phase", DataType::Utf8, true),
        Field::new("failure_sample", DataType::UInt64, true),
        Field::new("failure_detail", DataType::Utf8, true),
        Field::new("rejected", DataType::Utf8, true),
        f64_field("score"),
        f64_field("mu_l2"),
        f64_field("mu_linf"),
        Field::new("mu_linf_infinite", DataType::Boolean, false),
        f64_field("mu_l1"),
        Field::new("skipped_samples", DataType::UInt64, true),
        f64_field("yoshikawa_at_grasp"),
        f64_field("yoshikawa_penalized_at_grasp"),
        f64_field("inverse_condition_at_grasp"),
        f64_field("inverse_condition_squared_at_grasp"),
        Field::new("feasible_branches", DataType::UInt64, false),
        f64_field("limit_distance_min"),
        Field::new("hugs_limit", DataType::Boolean, true),
        f64_field("clearance"),
        f64_field("self_motion_mu_l2_first_branch"),
        f64_field("self_motion_mu_l2_min"),
        f64_field("self_motion_mu_l2_max"),
        Field::new("joint_trajectory", list_of_lists(), true),
        Field::new("approach_trajectory", list_of_lists(), true),
        Field::new("retreat_trajectory", list_of_lists(), true),
    ])
}

/// The column builders of `candidates.parquet`, in schema order.
struct CandidateColumns {
    arm: StringBuilder,
    id: UInt64Builder,
    label: StringBuilder,
    object_from_wrist: FixedSizeListBuilder<Float64Builder>,
    contact: FixedSizeListBuilder<Float64Builder>,
    likelihood: Float64Builder,
    log_likelihood: Float64Builder,
    feasible: BooleanBuilder,
    failure_reason: StringBuilder,
    failure_phase: StringBuilder,
    failure_sample: UInt64Builder,
    failure_detail: StringBuilder,
    rejected: StringBuilder,
    score: Float64Builder,
    mu_l2: Float64Builder,
    mu_linf: Float64Builder,
    mu_linf_infinite: BooleanBuilder,
    mu_l1: Float64Builder,
    skipped_samples: UInt64Builder,
    yoshikawa_at_grasp: Float64Builder,
    yoshikawa_penalized_at_grasp: Float64Builder,
    inverse_condition_at_grasp: Float64Builder,
    inverse_condition_squared_at_grasp: Float64Builder,
    feasible_branches: UInt64Builder,
    limit_distance_min: Float64Builder,
    hugs_limit: BooleanBuilder,
    clearance: Float64Builder,
    self_motion_first: Float64Builder,
    self_motion_min: Float64Builder,
    self_motion_max: Float64Builder,
    joint_trajectory: ListBuilder<ListBuilder<Float64Builder>>,
    approach_trajectory: ListBuilder<ListBuilder<Float64Builder>>,
    retreat_trajectory: ListBuilder<ListBuilder<Float64Builder>>,
    rows: usize,
}

/// `Some(v)` for a finite value (JSON has no infinities; the records write `null`).
fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

fn append_motion(
    builder: &mut ListBuilder<ListBuilder<Float64Builder>>,
    motion: Option<&[Vec<f64>]>,
) {
    match motion {
        None => builder.append_null(),
        Some(configurations) => {
            for q in configurations {
                builder.values().values().append_slice(q);
                builder.values().append(true);
            }
            builder.append(true);
        }
    }
}

impl CandidateColumns {
    fn new() -> Self {
        let motion = || ListBuilder::new(ListBuilder::new(Float64Builder::new()));
        Self {
            arm: StringBuilder::new(),
            id: UInt64Builder::new(),
            label: StringBuilder::new(),
            object_from_wrist: FixedSizeListBuilder::new(Float64Builder::new(), 16),
            contact: FixedSizeListBuilder::new(Float64Builder::new(), 3),
            likelihood: Float64Builder::new(),
            log_likelihood: Float64Builder::new(),
            feasible: BooleanBuilder::new(),
            failure_reason: StringBuilder::new(),
            failure_phase: StringBuilder::new(),
            failure_sample: UInt64Builder::new(),
            failure_detail: StringBuilder::new(),
            rejected: StringBuilder::new(),
            score: Float64Builder::new(),
            mu_l2: Float64Builder::new(),
            mu_linf: Float64Builder::new(),
            mu_linf_infinite: BooleanBuilder::new(),
            mu_l1: Float64Builder::new(),
            skipped_samples: UInt64Builder::new(),
            yoshikawa_at_grasp: Float64Builder::new(),
            yoshikawa_penalized_at_grasp: Float64Builder::new(),
            inverse_condition_at_grasp: Float64Builder::new(),
            inverse_condition_squared_at_grasp: Float64Builder::new(),
            feasible_branches: UInt64Builder::new(),
            limit_distance_min: Float64Builder::new(),
            hugs_limit: BooleanBuilder::new(),
            clearance: Float64Builder::new(),
            self_motion_first: Float64Builder::new(),
            self_motion_min: Float64Builder::new(),
            self_motion_max: Float64Builder::new(),
            joint_trajectory: motion(),
            approach_trajectory: motion(),
            retreat_trajectory: motion(),
            rows: 0,
        }
    }

    fn push(&mut self, streamed: &Streamed<'_>, trajectories: Trajectories) {
        let score = streamed.score;
        let c = &score.candidate;
        let feasible = score.feasible();
        self.arm.append_value(streamed.arm);
        self.id.append_value(c.id as u64);
        self.label.append_value(&c.label);
        let m = c.object_from_wrist.to_homogeneous();
        for row in 0..4 {
            for col in 0..4 {
                self.object_from_wrist.values().append_value(m[(row, col)]);
            }
        }
        self.object_from_wrist.append(true);
        match c.contact {
            Some(p) => {
                self.contact.values().append_slice(&[p.x, p.y, p.z]);
                self.contact.append(true);
            }
            None => {
                self.contact.values().append_nulls(3);
                self.contact.append(false);
            }
        }
        self.likelihood.append_value(c.log_likelihood.exp());
        self.log_likelihood.append_value(c.log_likelihood);
        self.feasible.append_value(feasible);
        let failure = score.failure.as_ref();
        self.failure_reason
            .append_option(failure.map(|f| f.reason.as_str()));
        self.failure_phase
            .append_option(failure.map(|f| f.phase.as_str()));
        self.failure_sample
            .append_option(failure.map(|f| f.sample as u64));
        self.failure_detail
            .append_option(failure.map(|f| f.detail.as_str()));
        self.rejected
            .append_option(streamed.ranking.rejected.as_deref());
        self.score
            .append_option(streamed.ranking.score.and_then(finite));
        let norms = score.norms;
        self.mu_l2.append_option(norms.map(|n| n.l2));
        self.mu_linf
            .append_option(norms.and_then(|n| finite(n.linf)));
        self.mu_linf_infinite
            .append_value(norms.is_some_and(|n| n.linf.is_infinite()));
        self.mu_l1.append_option(norms.map(|n| n.l1));
        self.skipped_samples
            .append_option(norms.map(|n| n.skipped as u64));
        self.yoshikawa_at_grasp
            .append_option(score.yoshikawa_at_grasp);
        self.yoshikawa_penalized_at_grasp
            .append_option(score.yoshikawa_penalized_at_grasp);
        self.inverse_condition_at_grasp
            .append_option(score.inverse_condition_at_grasp);
        self.inverse_condition_squared_at_grasp
            .append_option(score.inverse_condition_squared_at_grasp);
        self.feasible_branches
            .append_value(score.feasible_branches as u64);
        self.limit_distance_min.append_option(finite(
            score
                .limit_distance
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min),
        ));
        self.hugs_limit
            .append_option(feasible.then(|| score.hugs_limit()));
        self.clearance.append_option(score.clearance);
        let motion = score.self_motion;
        self.self_motion_first
            .append_option(motion.map(|s| s.first_branch_l2));
        self.self_motion_min
            .append_option(motion.map(|s| s.l2_range.0));
        self.self_motion_max
            .append_option(motion.map(|s| s.l2_range.1));
        let keep = trajectories.keeps(feasible);
        append_motion(
            &mut self.joint_trajectory,
            keep.then_some(&score.joint_trajectory[..]),
        );
        append_motion(
            &mut self.approach_trajectory,
            keep.then_some(&score.approach[..]),
        );
        append_motion(
            &mut self.retreat_trajectory,
            keep.then_some(&score.retreat[..]),
        );
        self.rows += 1;
    }

    /// The buffered rows as a batch; the builders start empty again.
    fn batch(&mut self, schema: &Arc<Schema>) -> Result<RecordBatch, ArrowError> {
        self.rows = 0;
        let columns: Vec<ArrayRef> = vec![
            Arc::new(self.arm.finish()),
            Arc::new(self.id.finish()),
            Arc::new(self.label.finish()),
            Arc::new(self.object_from_wrist.finish()),
            Arc::new(self.contact.finish()),
            Arc::new(self.likelihood.finish()),
            Arc::new(self.log_likelihood.finish()),
            Arc::new(self.feasible.finish()),
            Arc::new(self.failure_reason.finish()),
            Arc::new(self.failure_phase.finish()),
            Arc::new(self.failure_sample.finish()),
            Arc::new(self.failure_detail.finish()),
            Arc::new(self.rejected.finish()),
            Arc::new(self.score.finish()),
            Arc::new(self.mu_l2.finish()),
            Arc::new(self.mu_linf.finish()),
            Arc::new(self.mu_linf_infinite.finish()),
            Arc::new(self.mu_l1.finish()),
            Arc::new(self.skipped_samples.finish()),
            Arc::new(self.yoshikawa_at_grasp.finish()),
            Arc::new(self.yoshikawa_penalized_at_grasp.finish()),
            Arc::new(self.inverse_condition_at_grasp.finish()),
            Arc::new(self.inverse_condition_squared_at_grasp.finish()),
            Arc::new(self.feasible_branches.finish()),
            Arc::new(self.limit_distance_min.finish()),
            Arc::new(self.hugs_limit.finish()),
            Arc::new(self.clearance.finish()),
            Arc::new(self.self_motion_first.finish()),
            Arc::new(self.self_motion_min.finish()),
            Arc::new(self.self_motion_max.finish()),
            Arc::new(self.joint_trajectory.finish()),
            Arc::new(self.approach_trajectory.finish()),
            Arc::new(self.retreat_trajectory.finish()),
        ];
        RecordBatch::try_new(schema.clone(), columns)
    }
}

/// `candidates.parquet`, written as the candidates are streamed: [`push`](Self::push) each
/// streamed candidate in order, then [`finish`](Self::finish). Holds at most a batch of rows
/// and one row group's encoded pages.
pub struct CandidatesParquet<W: Write + Send> {
    writer: ArrowWriter<W>,
    schema: Arc<Schema>,
    columns: CandidateColumns,
    trajectories: Trajectories,
}

impl<W: Write + Send> CandidatesParquet<W> {
    /// A writer of `candidates.parquet` to `out`, with the joint motions `trajectories` keeps.
    ///
    /// Errors: the writer cannot start (an I/O error on `out`).
    pub fn new(out: W, trajectories: Trajectories) -> Result<Self, ParquetOutputError> {
        let schema = Arc::new(candidates_schema());
        let writer = ArrowWriter::try_new(out, schema.clone(), Some(properties()))?;
        Ok(Self {
            writer,
            schema,
            columns: CandidateColumns::new(),
            trajectories,
        })
    }

    /// Adds one streamed candidate's row (its `rank` and `pareto` are in `ranking.parquet`).
    ///
    /// Errors: writing a full batch failed.
    pub fn push(&mut self, streamed: &Streamed<'_>) -> Result<(), ParquetOutputError> {
        self.columns.push(streamed, self.trajectories);
        if self.columns.rows >= BATCH_ROWS {
            let batch = self.columns.batch(&self.schema)?;
            self.writer.write(&batch)?;
        }
        Ok(())
    }

    /// Writes the remaining rows and the file's footer, and returns `out`.
    ///
    /// Errors: writing failed.
    pub fn finish(mut self) -> Result<W, ParquetOutputError> {
        if self.columns.rows > 0 {
            let batch = self.columns.batch(&self.schema)?;
            self.writer.write(&batch)?;
        }
        Ok(self.writer.into_inner()?)
    }
}

/// Writes `ranking.parquet` to `out`: one row per eligible candidate and arm, columns `arm`,
/// `id`, `rank`, `score`, `pareto`, best first, arm by arm (the rows of `ranking.jsonl`).
///
/// Errors: writing failed.
pub fn write_ranking_parquet<W: Write + Send, S: Scored>(
    out: W,
    selection: &Selection<S>,
) -> Result<W, ParquetOutputError> {
    let schema = Arc::new(Schema::new(vec![
        Field::new("arm", DataType::Utf8, false),
        Field::new("id", DataType::UInt64, false),
        Field::new("rank", DataType::UInt64, false),
        Field::new("score", DataType::Float64, true),
        Field::new("pareto", DataType::Boolean, false),
    ]));
    let mut writer = ArrowWriter::try_new(out, schema.clone(), Some(properties()))?;
    for arm in &selection.arms {
        for rows in ranked_order(arm).chunks(BATCH_ROWS) {
            let (mut names, mut ids, mut ranks, mut scores, mut pareto) = (
                StringBuilder::new(),
                UInt64Builder::new(),
                UInt64Builder::new(),
                Float64Builder::new(),
                BooleanBuilder::new(),
            );
            for &(rank, i) in rows {
                names.append_value(&arm.arm);
                ids.append_value(arm.scores[i].id() as u64);
                ranks.append_value(rank as u64);
                scores.append_option(arm.rankings[i].score.and_then(finite));
                pareto.append_value(arm.rankings[i].pareto);
            }
            let columns: Vec<ArrayRef> = vec![
                Arc::new(names.finish()),
                Arc::new(ids.finish()),
                Arc::new(ranks.finish()),
                Arc::new(scores.finish()),
                Arc::new(pareto.finish()),
            ];
            writer.write(&RecordBatch::try_new(schema.clone(), columns)?)?;
        }
    }
    Ok(writer.into_inner()?)
}
