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
use std::sync::OnceLock;

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

/// `Some(v)` when finite.
fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

/// A column with the usual settings: nullable, at the top of a JSON record, `null` there when
/// absent, no numpy fallback.
const fn column(
    name: &'static str,
    kind: Kind,
    unit: &'static str,
    doc: &'static str,
    outputs: u8,
    value: for<'a> fn(&Row<'a>) -> Cell<'a>,
) -> Column {
    Column {
        name,
        kind,
        nullable: true,
        unit,
        doc,
        json: JsonPlace::Top,
        json_absent: WhenAbsent::Null,
        outputs,
        numpy_fallback: None,
        value,
    }
}

impl Column {
    const fn required(mut self) -> Self {
        self.nullable = false;
        self
    }
    const fn in_json(mut self, place: JsonPlace, absent: WhenAbsent) -> Self {
        self.json = place;
        self.json_absent = absent;
        self
    }
    const fn omitted_when_absent(mut self) -> Self {
        self.json_absent = WhenAbsent::Omit;
        self
    }
    const fn in_numpy_else(mut self, fallback: &'static str) -> Self {
        self.numpy_fallback = Some(fallback);
        self
    }
}

use outputs::{ARRAYS, BATCH, FILES, JSON, JSON_BOTH};

/// Every per-candidate column, in the order of `candidates.parquet` (JSON records list their
/// fields in the byte order of their names: [`json_fields`]).
pub static COLUMNS: &[Column] = &[
    column("arm", Kind::Text, "", "the arm", FILES | BATCH, |r| {
        Cell::Text(Some(r.arm))
    })
    .required(),
    column(
        "id",
        Kind::Count,
        "",
        "the candidate's id",
        FILES | ARRAYS | BATCH,
        |r| Cell::Count(Some(r.score.candidate.id as u64)),
    )
    .required(),
    column(
        "label",
        Kind::Text,
        "",
        "the candidate's label",
        FILES | ARRAYS | BATCH,
        |r| Cell::Text(Some(&r.score.candidate.label)),
    )
    .required(),
    column(
        "object_from_wrist",
        Kind::Pose,
        "m",
        "the wrist's pose in the object frame (the grasp)",
        FILES,
        |r| {
            let m = r.score.candidate.object_from_wrist.to_homogeneous();
            Cell::Pose(std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)])))
        },
    )
    .required(),
    column(
        "contact",
        Kind::Point,
        "m",
        "where the hand touches the object, object frame (from the candidate's source)",
        FILES | ARRAYS,
        |r| Cell::Point(r.score.candidate.contact.map(|p| [p.x, p.y, p.z])),
    ),
    column(
        "likelihood",
        Kind::Float,
        "",
        "the candidate's likelihood, exp(log_likelihood)",
        FILES,
        |r| Cell::Float(Some(r.score.candidate.log_likelihood.exp())),
    ),
    column(
        "log_likelihood",
        Kind::Float,
        "",
        "the candidate's natural log-likelihood",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(Some(r.score.candidate.log_likelihood)),
    ),
    column(
        "feasible",
        Kind::Flag,
        "",
        "whether the arm follows the whole motion from this grasp",
        FILES | ARRAYS | BATCH,
        |r| Cell::Flag(Some(r.score.feasible())),
    )
    .required(),
    column(
        "failure_reason",
        Kind::Text,
        "",
        "why the arm cannot: unreachable, joint_limit, discontinuity, collision, …",
        FILES | ARRAYS | BATCH,
        |r| Cell::Text(r.score.failure.as_ref().map(|f| f.reason.as_str())),
    )
    .in_json(JsonPlace::In(Group::Failure, "reason"), WhenAbsent::Null),
    column(
        "failure_phase",
        Kind::Text,
        "",
        "the failing part of the motion: approach, path or retreat",
        FILES,
        |r| Cell::Text(r.score.failure.as_ref().map(|f| f.phase.as_str())),
    )
    .in_json(JsonPlace::In(Group::Failure, "phase"), WhenAbsent::Null),
    column(
        "failure_sample",
        Kind::Count,
        "",
        "the first failing sample of that part (0: its first)",
        FILES | ARRAYS | BATCH,
        |r| Cell::Count(r.score.failure.as_ref().map(|f| f.sample as u64)),
    )
    .in_json(JsonPlace::In(Group::Failure, "sample"), WhenAbsent::Null),
    column(
        "failure_detail",
        Kind::Text,
        "",
        "the failure in words",
        FILES,
        |r| Cell::Text(r.score.failure.as_ref().map(|f| f.detail.as_str())),
    )
    .in_json(JsonPlace::In(Group::Failure, "detail"), WhenAbsent::Null),
    column(
        "failure_bodies",
        Kind::Bodies,
        "",
        "the two bodies of a collision",
        JSON_BOTH,
        |r| Cell::Bodies(r.score.failure.as_ref().and_then(|f| f.bodies.as_ref())),
    )
    .in_json(JsonPlace::In(Group::Failure, "bodies"), WhenAbsent::Omit),
    column(
        "rejected",
        Kind::Text,
        "",
        "why a feasible candidate is not ranked (the mu0 constraint, a singular path, …)",
        FILES | ARRAYS | BATCH,
        |r| Cell::Text(r.ranking.rejected.as_deref()),
    ),
    column(
        "rank",
        Kind::Count,
        "",
        "1 for the arm's best candidate (absent: not ranked)",
        JSON | ARRAYS | BATCH,
        |r| Cell::Count(r.ranking.rank.map(|v| v as u64)),
    ),
    column(
        "score",
        Kind::Float,
        "index",
        "the ranking score: the norm combined with the likelihood",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.ranking.score),
    ),
    column(
        "pareto",
        Kind::Flag,
        "",
        "on the Pareto front of (likelihood, norm) among ranked candidates",
        JSON,
        |r| Cell::Flag(Some(r.ranking.pareto)),
    ),
    column(
        "mu_l2",
        Kind::Float,
        "index",
        "‖v‖₂ of the ranked per-sample index v over the path",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.score.norms.map(|n| n.l2)),
    ),
    column(
        "mu_linf",
        Kind::Float,
        "1/index",
        "max 1/v over the path (infinite on a singular path)",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.score.norms.map(|n| n.linf)),
    ),
    column(
        "mu_linf_infinite",
        Kind::Flag,
        "",
        "whether mu_linf is infinite (written null in JSON and Parquet)",
        FILES,
        |r| Cell::Flag(Some(r.score.norms.is_some_and(|n| n.linf.is_infinite()))),
    )
    .required(),
    column(
        "mu_l1",
        Kind::Float,
        "s·index",
        "the time integral of v over the path",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.score.norms.map(|n| n.l1)),
    ),
    column(
        "mu_rms",
        Kind::Float,
        "index",
        "the root mean square of v over the path's time (the default ranked norm)",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.score.norms.map(|n| n.rms)),
    ),
    column(
        "skipped_samples",
        Kind::Count,
        "",
        "path samples skipped by the norms (the object still)",
        FILES,
        |r| Cell::Count(r.score.norms.map(|n| n.skipped as u64)),
    ),
    column(
        "m_t",
        Kind::Series,
        "index",
        "the paper's M_T per path sample (null: infeasible, or the object still)",
        JSON_BOTH | ARRAYS,
        |r| Cell::Samples(Some(&r.score.m_t)),
    ),
    column(
        "ranked_index",
        Kind::Series,
        "index",
        "the ranked per-sample index v when it is not M_T itself",
        JSON_BOTH | ARRAYS,
        |r| Cell::Samples(r.score.ranked_values.as_deref()),
    )
    .omitted_when_absent()
    .in_numpy_else("m_t"),
    column(
        "yoshikawa_at_grasp",
        Kind::Float,
        "",
        "Yoshikawa's index of the full J at the grasp configuration",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.score.yoshikawa_at_grasp),
    ),
    column(
        "yoshikawa_penalized_at_grasp",
        Kind::Float,
        "",
        "Yoshikawa's index at the grasp times the joint-limit penalty there",
        FILES | ARRAYS,
        |r| Cell::Float(r.score.yoshikawa_penalized_at_grasp),
    )
    .omitted_when_absent(),
    column(
        "inverse_condition_at_grasp",
        Kind::Float,
        "",
        "σmin/σmax of J at the grasp configuration",
        FILES | ARRAYS,
        |r| Cell::Float(r.score.inverse_condition_at_grasp),
    ),
    column(
        "inverse_condition_squared_at_grasp",
        Kind::Float,
        "",
        "λmin/λmax of J Jᵀ at the grasp configuration (the paper's eq. 12)",
        FILES | ARRAYS,
        |r| Cell::Float(r.score.inverse_condition_squared_at_grasp),
    ),
    column(
        "feasible_branches",
        Kind::Count,
        "",
        "how many distinct feasible IK branches were found",
        FILES,
        |r| Cell::Count(Some(r.score.feasible_branches as u64)),
    )
    .required(),
    column(
        "limit_distance",
        Kind::Series,
        "rad or m",
        "per path sample, how far the joint nearest to a limit is from it",
        JSON_BOTH,
        |r| Cell::Floats(&r.score.limit_distance),
    )
    .in_json(JsonPlace::Top, WhenAbsent::OmitEmpty),
    column(
        "limit_distance_min",
        Kind::Float,
        "rad or m",
        "the path's closest approach to a joint limit",
        FILES | ARRAYS,
        |r| Cell::Float(r.score.limit_distance_min()),
    ),
    column(
        "hugs_limit",
        Kind::Flag,
        "",
        "whether the chosen motion rides a joint limit (feasible candidates)",
        FILES | ARRAYS,
        |r| Cell::Flag(r.score.feasible().then(|| r.score.hugs_limit())),
    ),
    column(
        "clearance",
        Kind::Float,
        "m",
        "the smallest distance to the scene along the motion (tasks with a scene)",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.score.clearance),
    )
    .omitted_when_absent(),
    column(
        "torque_margin",
        Kind::Float,
        "",
        "with the object's mass: the worst 1 − |τ|/τ_max over the motion's samples and joints",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.score.torque_margin),
    )
    .omitted_when_absent(),
    column(
        "payload_capacity",
        Kind::Float,
        "kg",
        "with the object's mass: the largest object mass the chosen motion carries within the \
         effort limits",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.score.payload_capacity),
    )
    .omitted_when_absent(),
    column(
        "dynamic_manipulability",
        Kind::Float,
        "(m/s²)²",
        "with the object's mass or index.measure dynamic: the task's norm of M_D, the squared \
         largest acceleration along the path's tangent within the joints' torque headroom, \
         along the chosen path",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.score.dynamic_manipulability),
    )
    .omitted_when_absent(),
    column(
        "duration",
        Kind::Float,
        "s",
        "when motions are timed: the chosen motion's time-optimal duration (approach, carry and \
         retreat) within the joints' velocity, acceleration and torque limits",
        FILES | ARRAYS | BATCH,
        |r| Cell::Float(r.score.durations.map(|d| d.total())),
    )
    .omitted_when_absent(),
    column(
        "approach_duration",
        Kind::Float,
        "s",
        "when motions are timed: the approach's part of the duration",
        FILES | ARRAYS,
        |r| Cell::Float(r.score.durations.map(|d| d.approach)),
    )
    .omitted_when_absent(),
    column(
        "carry_duration",
        Kind::Float,
        "s",
        "when motions are timed: the carry's part of the duration (grasp to place)",
        FILES | ARRAYS,
        |r| Cell::Float(r.score.durations.map(|d| d.carry)),
    )
    .omitted_when_absent(),
    column(
        "retreat_duration",
        Kind::Float,
        "s",
        "when motions are timed: the retreat's part of the duration",
        FILES | ARRAYS,
        |r| Cell::Float(r.score.durations.map(|d| d.retreat)),
    )
    .omitted_when_absent(),
    column(
        "spline_deviation",
        Kind::Float,
        "rad or m",
        "when motions are timed: the largest distance between the smoothed motion and the \
         straight joint-space segments between its IK samples",
        FILES | ARRAYS,
        |r| Cell::Float(r.score.durations.map(|d| d.spline_deviation)),
    )
    .omitted_when_absent(),
    column(
        "limit_excursion",
        Kind::Float,
        "rad or m",
        "when motions are timed: how far the smoothed motion leaves a joint's range between IK \
         samples that ride a limit (written trajectories are clamped into it)",
        FILES | ARRAYS,
        |r| Cell::Float(r.score.durations.map(|d| d.limit_excursion)),
    )
    .omitted_when_absent(),
    column(
        "self_motion_mu_l2_first_branch",
        Kind::Float,
        "index",
        "with ik.redundancy: optimize, mu_l2 along the first IK branch",
        FILES,
        |r| Cell::Float(r.score.self_motion.map(|s| s.first_branch_l2)),
    )
    .in_json(
        JsonPlace::In(Group::SelfMotion, "mu_l2_first_branch"),
        WhenAbsent::Null,
    ),
    column(
        "self_motion_mu_l2_min",
        Kind::Float,
        "index",
        "the smallest mu_l2 of the motions seen in the self-motion: the traced chains within \
         the joint-step bound, the first branch and the motion kept",
        FILES,
        |r| Cell::Float(r.score.self_motion.map(|s| s.l2_range.0)),
    )
    .in_json(
        JsonPlace::In(Group::SelfMotion, "mu_l2_min"),
        WhenAbsent::Null,
    ),
    column(
        "self_motion_mu_l2_max",
        Kind::Float,
        "index",
        "the largest mu_l2 of the motions seen in the self-motion (the motion kept is smooth \
         in time and may lie below it)",
        FILES,
        |r| Cell::Float(r.score.self_motion.map(|s| s.l2_range.1)),
    )
    .in_json(
        JsonPlace::In(Group::SelfMotion, "mu_l2_max"),
        WhenAbsent::Null,
    ),
    column(
        "joint_trajectory",
        Kind::Motion,
        "rad or m",
        "the joint configurations along the path (with --trajectories)",
        FILES,
        |r| Cell::Motion(r.motions.then_some(&r.score.joint_trajectory[..])),
    )
    .omitted_when_absent(),
    column(
        "approach_trajectory",
        Kind::Motion,
        "rad or m",
        "the joint configurations of the approach, before the grasp",
        FILES,
        |r| Cell::Motion(r.motions.then_some(&r.score.approach[..])),
    )
    .in_json(JsonPlace::Top, WhenAbsent::OmitEmpty),
    column(
        "retreat_trajectory",
        Kind::Motion,
        "rad or m",
        "the joint configurations of the retreat, after the place",
        FILES,
        |r| Cell::Motion(r.motions.then_some(&r.score.retreat[..])),
    )
    .in_json(JsonPlace::Top, WhenAbsent::OmitEmpty),
];

/// The column named `name`.
pub fn column_named(name: &str) -> Option<&'static Column> {
    COLUMNS.iter().find(|c| c.name == name)
}

/// A field of a JSON record: a column, or a group of columns.
#[derive(Debug, Clone, Copy)]
pub enum JsonField {
    /// A column at the top of the record.
    Column(&'static Column),
    /// A nested group and its columns, in the byte order of their names there.
    Group(Group, &'static [&'static Column]),
}

impl JsonField {
    /// The field's name in the record.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Column(c) => c.name,
            Self::Group(g, _) => g.name(),
        }
    }
}

/// The fields of a JSON record in the byte order of their names (how `candidates.json` has
/// always listed them, and `candidates.jsonl` too), with the columns of `output`
/// ([`outputs::JSON`]; any other output is taken as [`outputs::JSON_LINES`]).
pub fn json_fields(output: u8) -> &'static [JsonField] {
    static DOCUMENT: OnceLock<Vec<JsonField>> = OnceLock::new();
    static LINES: OnceLock<Vec<JsonField>> = OnceLock::new();
    let (cell, output) = if output == JSON {
        (&DOCUMENT, JSON)
    } else {
        (&LINES, outputs::JSON_LINES)
    };
    cell.get_or_init(|| {
        let columns = || COLUMNS.iter().filter(|c| c.in_output(output));
        let mut fields: Vec<JsonField> = columns()
            .filter(|c| c.json == JsonPlace::Top)
            .map(JsonField::Column)
            .collect();
        for group in [Group::Failure, Group::SelfMotion] {
            let mut members: Vec<&'static Column> = columns()
                .filter(|c| matches!(c.json, JsonPlace::In(g, _) if g == group))
                .collect();
            members.sort_by_key(|c| json_name(c));
            if !members.is_empty() {
                fields.push(JsonField::Group(group, Vec::leak(members)));
            }
        }
        fields.sort_by_key(JsonField::name);
        fields
    })
}

/// A column's field name in its JSON record (inside its group for a grouped one).
pub fn json_name(column: &Column) -> &'static str {
    match column.json {
        JsonPlace::Top => column.name,
        JsonPlace::In(_, name) => name,
    }
}

impl Cell<'_> {
    /// Whether the cell is absent for a JSON record (`empty` lists too, when `absent` says so).
    pub fn absent_in_json(&self, absent: WhenAbsent) -> bool {
        let missing = match self {
            Self::Float(v) => v.is_none(),
            Self::Count(v) => v.is_none(),
            Self::Flag(v) => v.is_none(),
            Self::Text(v) => v.is_none(),
            Self::Point(v) => v.is_none(),
            Self::Pose(_) => false,
            Self::Bodies(v) => v.is_none(),
            Self::Samples(v) => v.is_none(),
            Self::Floats(v) => absent == WhenAbsent::OmitEmpty && v.is_empty(),
            Self::Motion(v) => {
                v.is_none() || (absent == WhenAbsent::OmitEmpty && v.is_some_and(<[_]>::is_empty))
            }
        };
        missing && absent != WhenAbsent::Null
    }
}

impl serde::Serialize for Cell<'_> {
    /// The cell as JSON: a value that is not finite as `null`.
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let finite_or_null = |v: &f64| finite(*v);
        match self {
            Self::Float(v) => v.and_then(finite).serialize(serializer),
            Self::Count(v) => v.serialize(serializer),
            Self::Flag(v) => v.serialize(serializer),
            Self::Text(v) => v.serialize(serializer),
            Self::Point(v) => v
                .map(|p| p.map(|x| finite_or_null(&x)))
                .serialize(serializer),
            Self::Pose(m) => m.serialize(serializer),
            Self::Bodies(v) => v.serialize(serializer),
            Self::Samples(v) => {
                serializer.collect_seq(v.unwrap_or_default().iter().map(|x| x.and_then(finite)))
            }
            Self::Floats(v) => serializer.collect_seq(v.iter().map(finite_or_null)),
            Self::Motion(v) => v.unwrap_or_default().serialize(serializer),
        }
    }
}

/// One candidate's JSON record for `output` ([`outputs::JSON`] or [`outputs::JSON_LINES`]):
/// serialised, the fields of [`json_fields`] with their cells.
#[derive(Debug, Clone, Copy)]
pub struct JsonRecord<'a> {
    /// The candidate's row.
    pub row: Row<'a>,
    /// Which JSON output.
    pub output: u8,
}

/// The present fields of one group, serialised as a JSON object.
struct JsonGroup<'a> {
    row: Row<'a>,
    members: &'static [&'static Column],
}

impl serde::Serialize for JsonGroup<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let cells: Vec<(&str, Cell<'_>)> = self
            .members
            .iter()
            .map(|c| (json_name(c), (c.value)(&self.row), c.json_absent))
            .filter(|(_, cell, absent)| !cell.absent_in_json(*absent))
            .map(|(name, cell, _)| (name, cell))
            .collect();
        let mut map = serializer.serialize_map(Some(cells.len()))?;
        for (name, cell) in &cells {
            map.serialize_entry(name, cell)?;
        }
        map.end()
    }
}

impl serde::Serialize for JsonRecord<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let fields = json_fields(self.output);
        let mut map = serializer.serialize_map(None)?;
        for field in fields {
            match field {
                JsonField::Column(c) => {
                    let cell = (c.value)(&self.row);
                    if !cell.absent_in_json(c.json_absent) {
                        map.serialize_entry(c.name, &cell)?;
                    }
                }
                JsonField::Group(group, members) => {
                    if group.present(&self.row) {
                        let value = JsonGroup {
                            row: self.row,
                            members,
                        };
                        map.serialize_entry(group.name(), &value)?;
                    } else if group.when_absent() == WhenAbsent::Null {
                        map.serialize_entry(group.name(), &())?;
                    }
                }
            }
        }
        map.end()
    }
}
