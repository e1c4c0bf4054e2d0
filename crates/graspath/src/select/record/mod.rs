//! The candidate record: every per-candidate output column declared once — its name, type,
//! unit, meaning and how it is filled — in [`COLUMNS`]. `candidates.json`, `candidates.jsonl`,
//! `candidates.parquet`, the numpy columns of Python's `Selection.arrays()` and
//! `select_batch`, and the column table of `docs/candidate-record.md` are all read off this
//! list: adding a column is one declaration here plus its computation in scoring.
//!
//! A column's value for one candidate and arm ([`Row`]) is a [`Cell`]. Each output writes cells
//! its own way: JSON and Parquet write a value that is not finite as `null` (JSON has no
//! infinity; an infinite `mu_linf` has the `mu_linf_infinite` flag beside it), numpy keeps it
//! and writes what is absent as NaN.

use super::rank::Ranking;
use super::score::CandidateScore;

mod columns;
mod json;

pub use columns::COLUMNS;
pub use json::{json_fields, json_name, JsonField, JsonRecord};

/// Which candidates' joint motions (`joint_trajectory`, `approach_trajectory`,
/// `retreat_trajectory`; rad or m per joint and sample) an output's records carry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Trajectories {
    /// None: the three fields are left out of every record.
    None,
    /// Only feasible candidates' (the fields are left out of an infeasible candidate's record).
    Feasible,
    /// Every candidate's (an infeasible candidate has no motion: `joint_trajectory: []`, and
    /// the approach and retreat are left out). `candidates.json` has always been written so.
    #[default]
    All,
}

impl Trajectories {
    /// Whether a candidate's motions are kept, `feasible` or not.
    pub fn keeps(self, feasible: bool) -> bool {
        match self {
            Self::None => false,
            Self::Feasible => feasible,
            Self::All => true,
        }
    }
}

/// One candidate's scores for one arm, with its ranking: what a record is filled from.
#[derive(Debug, Clone, Copy)]
pub struct Row<'a> {
    /// The arm's name.
    pub arm: &'a str,
    /// The candidate's scores for that arm.
    pub score: &'a CandidateScore,
    /// Its place in the arm's ranking (for a streamed record, only the part that needs no
    /// other candidate: see [`ranking_alone`](super::ranking_alone)).
    pub ranking: &'a Ranking,
    /// Whether the record carries the candidate's joint motions ([`Trajectories::keeps`]).
    pub motions: bool,
}

impl<'a> Row<'a> {
    /// The row of `score` and `ranking` for `arm`, its motions kept as `trajectories` says.
    pub fn new(
        arm: &'a str,
        score: &'a CandidateScore,
        ranking: &'a Ranking,
        trajectories: Trajectories,
    ) -> Self {
        Self {
            arm,
            score,
            ranking,
            motions: trajectories.keeps(score.feasible()),
        }
    }
}

/// A column's value in one row.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell<'a> {
    /// A real number (`None`: absent).
    Float(Option<f64>),
    /// A count or an index (`None`: absent).
    Count(Option<u64>),
    /// A yes/no (`None`: absent).
    Flag(Option<bool>),
    /// A text (`None`: absent).
    Text(Option<&'a str>),
    /// A point (x, y, z) (`None`: absent).
    Point(Option<[f64; 3]>),
    /// A rigid transform as its 4 × 4 homogeneous matrix, row by row.
    Pose([[f64; 4]; 4]),
    /// Two body names.
    Bodies(Option<&'a [String; 2]>),
    /// One value per path sample, `None` where absent (`None` as a whole: no series).
    Samples(Option<&'a [Option<f64>]>),
    /// One value per path sample.
    Floats(&'a [f64]),
    /// Joint configurations, one per sample (`None`: not carried).
    Motion(Option<&'a [Vec<f64>]>),
}

/// How a column is typed: what every output makes of its cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// [`Cell::Float`]: float64.
    Float,
    /// [`Cell::Count`]: an unsigned integer (int64 in numpy, float64 with NaN when nullable).
    Count,
    /// [`Cell::Flag`]: boolean.
    Flag,
    /// [`Cell::Text`]: a string.
    Text,
    /// [`Cell::Point`]: three float64.
    Point,
    /// [`Cell::Pose`]: sixteen float64, the matrix row by row (JSON: four rows of four).
    Pose,
    /// [`Cell::Bodies`]: two strings.
    Bodies,
    /// [`Cell::Samples`] or [`Cell::Floats`]: float64 per path sample.
    Series,
    /// [`Cell::Motion`]: a list of joint configurations (lists of float64).
    Motion,
}

impl Kind {
    /// The type's name in the docs' column table.
    pub fn name(self) -> &'static str {
        match self {
            Self::Float => "float64",
            Self::Count => "uint64",
            Self::Flag => "bool",
            Self::Text => "string",
            Self::Point => "float64 × 3",
            Self::Pose => "float64 × 16",
            Self::Bodies => "string × 2",
            Self::Series => "float64 per sample",
            Self::Motion => "list of float64 per sample",
        }
    }
}

/// What a JSON record does with an absent value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WhenAbsent {
    /// Writes `null`.
    Null,
    /// Leaves the field out.
    Omit,
    /// Leaves the field out when it is absent or an empty list.
    OmitEmpty,
}

/// A group of fields nested under one name in a JSON record (flat in the other outputs, their
/// names prefixed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    /// `failure`: why and where the candidate fails (`null` when feasible).
    Failure,
    /// `self_motion`: what the self-motion search found (left out without one).
    SelfMotion,
}

impl Group {
    /// The group's field name in a JSON record.
    pub fn name(self) -> &'static str {
        match self {
            Self::Failure => "failure",
            Self::SelfMotion => "self_motion",
        }
    }

    /// Whether the group has a value in `row`.
    pub fn present(self, row: &Row<'_>) -> bool {
        match self {
            Self::Failure => row.score.failure.is_some(),
            Self::SelfMotion => row.score.self_motion.is_some(),
        }
    }

    /// What a JSON record does when the group has no value.
    pub fn when_absent(self) -> WhenAbsent {
        match self {
            Self::Failure => WhenAbsent::Null,
            Self::SelfMotion => WhenAbsent::Omit,
        }
    }
}

/// Where a column sits in a JSON record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JsonPlace {
    /// A field of the record, named as the column.
    Top,
    /// A field of a nested group, with its name there.
    In(Group, &'static str),
}

/// The outputs a column is part of (bits of [`Column::outputs`]).
pub mod outputs {
    /// `candidates.json`, the whole document (ranks included).
    pub const JSON: u8 = 1;
    /// `candidates.jsonl`, a line per candidate written as it is scored (no rank).
    pub const JSON_LINES: u8 = 1 << 1;
    /// `candidates.parquet`, a row per candidate written as it is scored (no rank).
    pub const PARQUET: u8 = 1 << 2;
    /// Python's `Selection.arrays()`.
    pub const ARRAYS: u8 = 1 << 3;
    /// Python's `select_batch` (and the Ray layer's rows, read from it).
    pub const BATCH: u8 = 1 << 4;
    /// Both JSON outputs.
    pub const JSON_BOTH: u8 = JSON | JSON_LINES;
    /// Every output written as the candidates are scored, and the JSON document.
    pub const FILES: u8 = JSON | JSON_LINES | PARQUET;
}

/// One per-candidate output column.
#[derive(Debug, Clone, Copy)]
pub struct Column {
    /// The column's name (in JSON, inside its group: [`JsonPlace`]).
    pub name: &'static str,
    /// Its type.
    pub kind: Kind,
    /// Whether it can be absent.
    pub nullable: bool,
    /// Its unit (empty: none).
    pub unit: &'static str,
    /// What it is, in one line.
    pub doc: &'static str,
    /// Where it sits in a JSON record.
    pub json: JsonPlace,
    /// What a JSON record does when it is absent.
    pub json_absent: WhenAbsent,
    /// The outputs it is part of ([`outputs`]).
    pub outputs: u8,
    /// In numpy, where it is absent, the values of this column instead (the ranked index is
    /// `M_T` itself unless the task ranks something else).
    pub numpy_fallback: Option<&'static str>,
    /// Its value in a row.
    pub value: for<'a> fn(&Row<'a>) -> Cell<'a>,
}

impl Column {
    /// Whether the column is part of `output` (one of [`outputs`]).
    pub fn in_output(&self, output: u8) -> bool {
        self.outputs & output != 0
    }
}

/// The column named `name`.
pub fn column_named(name: &str) -> Option<&'static Column> {
    COLUMNS.iter().find(|c| c.name == name)
}

/// `Some(v)` when finite.
fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}
