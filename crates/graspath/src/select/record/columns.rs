//! [`COLUMNS`]: every per-candidate output column, declared once, in the order of
//! `candidates.parquet`.

use super::*;

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
        "failure_joint",
        Kind::Text,
        "",
        "the joint at fault: its torque limit (torque_limit) or the limit no timing satisfies",
        FILES | ARRAYS | BATCH,
        |r| Cell::Text(r.score.failure.as_ref().and_then(|f| f.joint.as_deref())),
    )
    .in_json(JsonPlace::In(Group::Failure, "joint"), WhenAbsent::Omit),
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
        "the joint configurations along the path, where the output keeps motions",
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
