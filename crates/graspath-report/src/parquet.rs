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

use crate::json::ranked_order;
use arrow_array::builder::{
    BooleanBuilder, FixedSizeListBuilder, Float64Builder, ListBuilder, StringBuilder, UInt64Builder,
};
use arrow_array::{ArrayRef, RecordBatch};
use arrow_schema::{ArrowError, DataType, Field, Schema};
use graspath::select::record::{outputs, Cell, Column, Kind, Row, Trajectories, COLUMNS};
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

/// A list of float64 (nullable items named `item`, as the list builders write them).
fn list_of(item: DataType) -> DataType {
    DataType::List(Arc::new(Field::new("item", item, true)))
}

/// `width` float64 values.
fn fixed_floats(width: i32) -> DataType {
    DataType::FixedSizeList(Arc::new(Field::new("item", DataType::Float64, true)), width)
}

/// The Parquet type of a record column's kind.
fn data_type(kind: Kind) -> DataType {
    match kind {
        Kind::Float => DataType::Float64,
        Kind::Count => DataType::UInt64,
        Kind::Flag => DataType::Boolean,
        Kind::Text => DataType::Utf8,
        Kind::Point => fixed_floats(3),
        Kind::Pose => fixed_floats(16),
        Kind::Bodies => list_of(DataType::Utf8),
        Kind::Series => list_of(DataType::Float64),
        Kind::Motion => list_of(list_of(DataType::Float64)),
    }
}

/// The record's columns that `candidates.parquet` carries, in order.
fn parquet_columns() -> impl Iterator<Item = &'static Column> {
    COLUMNS.iter().filter(|c| c.in_output(outputs::PARQUET))
}

fn candidates_schema() -> Schema {
    Schema::new(
        parquet_columns()
            .map(|c| Field::new(c.name, data_type(c.kind), c.nullable))
            .collect::<Vec<_>>(),
    )
}

/// The builder of one column of `candidates.parquet`.
enum ColumnBuilder {
    Float(Float64Builder),
    Count(UInt64Builder),
    Flag(BooleanBuilder),
    Text(StringBuilder),
    Fixed(FixedSizeListBuilder<Float64Builder>, usize),
    Texts(ListBuilder<StringBuilder>),
    Floats(ListBuilder<Float64Builder>),
    Motion(ListBuilder<ListBuilder<Float64Builder>>),
}

impl ColumnBuilder {
    fn new(kind: Kind) -> Self {
        match kind {
            Kind::Float => Self::Float(Float64Builder::new()),
            Kind::Count => Self::Count(UInt64Builder::new()),
            Kind::Flag => Self::Flag(BooleanBuilder::new()),
            Kind::Text => Self::Text(StringBuilder::new()),
            Kind::Point => Self::Fixed(FixedSizeListBuilder::new(Float64Builder::new(), 3), 3),
            Kind::Pose => Self::Fixed(FixedSizeListBuilder::new(Float64Builder::new(), 16), 16),
            Kind::Bodies => Self::Texts(ListBuilder::new(StringBuilder::new())),
            Kind::Series => Self::Floats(ListBuilder::new(Float64Builder::new())),
            Kind::Motion => Self::Motion(ListBuilder::new(ListBuilder::new(Float64Builder::new()))),
        }
    }

    /// Appends `cell` (of this builder's kind); a value that is not finite as null.
    fn append(&mut self, cell: Cell<'_>) {
        match (self, cell) {
            (Self::Float(b), Cell::Float(v)) => b.append_option(v.and_then(finite)),
            (Self::Count(b), Cell::Count(v)) => b.append_option(v),
            (Self::Flag(b), Cell::Flag(v)) => b.append_option(v),
            (Self::Text(b), Cell::Text(v)) => b.append_option(v),
            (Self::Fixed(b, width), Cell::Point(p)) => {
                append_fixed(b, *width, p.as_ref().map(|p| &p[..]));
            }
            (Self::Fixed(b, width), Cell::Pose(m)) => {
                append_fixed(b, *width, Some(m.as_flattened()));
            }
            (Self::Texts(b), Cell::Bodies(v)) => match v {
                Some(names) => {
                    names.iter().for_each(|n| b.values().append_value(n));
                    b.append(true);
                }
                None => b.append_null(),
            },
            (Self::Floats(b), Cell::Samples(v)) => match v {
                Some(values) => {
                    values
                        .iter()
                        .for_each(|x| b.values().append_option(x.and_then(finite)));
                    b.append(true);
                }
                None => b.append_null(),
            },
            (Self::Floats(b), Cell::Floats(values)) => {
                values
                    .iter()
                    .for_each(|x| b.values().append_option(finite(*x)));
                b.append(true);
            }
            (Self::Motion(b), Cell::Motion(v)) => append_motion(b, v),
            (builder, cell) => unreachable!(
                "a record column's cells are of its kind ({cell:?} in a {} column)",
                builder.kind_name()
            ),
        }
    }

    fn kind_name(&self) -> &'static str {
        match self {
            Self::Float(_) => "float",
            Self::Count(_) => "count",
            Self::Flag(_) => "flag",
            Self::Text(_) => "text",
            Self::Fixed(..) => "fixed-size list",
            Self::Texts(_) => "list of texts",
            Self::Floats(_) => "list of floats",
            Self::Motion(_) => "motion",
        }
    }

    fn finish(&mut self) -> ArrayRef {
        match self {
            Self::Float(b) => Arc::new(b.finish()),
            Self::Count(b) => Arc::new(b.finish()),
            Self::Flag(b) => Arc::new(b.finish()),
            Self::Text(b) => Arc::new(b.finish()),
            Self::Fixed(b, _) => Arc::new(b.finish()),
            Self::Texts(b) => Arc::new(b.finish()),
            Self::Floats(b) => Arc::new(b.finish()),
            Self::Motion(b) => Arc::new(b.finish()),
        }
    }
}

/// `Some(v)` for a finite value (JSON has no infinities; the records write `null`).
fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

fn append_fixed(
    builder: &mut FixedSizeListBuilder<Float64Builder>,
    width: usize,
    values: Option<&[f64]>,
) {
    match values {
        Some(values) => {
            builder.values().append_slice(values);
            builder.append(true);
        }
        None => {
            builder.values().append_nulls(width);
            builder.append(false);
        }
    }
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

/// The column builders of `candidates.parquet`, in schema order.
struct CandidateColumns {
    columns: Vec<(&'static Column, ColumnBuilder)>,
    rows: usize,
}

impl CandidateColumns {
    fn new() -> Self {
        Self {
            columns: parquet_columns()
                .map(|c| (c, ColumnBuilder::new(c.kind)))
                .collect(),
            rows: 0,
        }
    }

    fn push(&mut self, streamed: &Streamed<'_>, trajectories: Trajectories) {
        let row = Row::new(streamed.arm, streamed.score, streamed.ranking, trajectories);
        for (column, builder) in &mut self.columns {
            builder.append((column.value)(&row));
        }
        self.rows += 1;
    }

    /// The buffered rows as a batch; the builders start empty again.
    fn batch(&mut self, schema: &Arc<Schema>) -> Result<RecordBatch, ArrowError> {
        self.rows = 0;
        let columns: Vec<ArrayRef> = self.columns.iter_mut().map(|(_, b)| b.finish()).collect();
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
