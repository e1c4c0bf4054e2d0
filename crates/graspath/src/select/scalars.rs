//! The scalars of a candidate's scores: what a ranking, the Pareto front, the pairs and the
//! summaries read ([`Scored`]), and the compact record a streamed selection keeps per
//! candidate and arm ([`CandidateScalars`]) instead of the whole [`CandidateScore`].

use super::score::{CandidateScore, MotionDurations, SelfMotionScores};
use crate::failure::{FailureReason, Phase};
use crate::grasp::Candidate;
use crate::manipulability::PathNorms;
use nalgebra::Point3;
use std::sync::Arc;

/// What ranking and summarising read of one candidate's scores for one arm: implemented by
/// the full [`CandidateScore`] (in-memory selection) and by the compact [`CandidateScalars`]
/// (streamed selection), so both are ranked by the same code.
pub trait Scored {
    /// The candidate's id.
    fn id(&self) -> usize;
    /// The candidate's natural log-likelihood.
    fn log_likelihood(&self) -> f64;
    /// Where the hand holds the object, object frame (m) ([`Candidate::grasp_point`]).
    fn grasp_point(&self) -> Point3<f64>;
    /// The norms of the ranked index over the path (when feasible).
    fn norms(&self) -> Option<PathNorms>;
    /// Why the arm cannot follow the whole motion (`None` when feasible).
    fn failure_reason(&self) -> Option<FailureReason>;
    /// The two bodies of a collision failure (`link left_wrist`, `obstacle wall`, `table`,
    /// ...); `None` for any other outcome.
    fn colliding_bodies(&self) -> Option<&[String; 2]>;
    /// The smallest distance to the scene along the motion (m), with a scene.
    fn clearance(&self) -> Option<f64>;
    /// Yoshikawa's index of the full `J` at the grasp.
    fn yoshikawa_at_grasp(&self) -> Option<f64>;
    /// The torque margin along the motion, with a payload.
    fn torque_margin(&self) -> Option<f64>;
    /// How long the timed motion takes (s), when the task times motions.
    fn duration(&self) -> Option<f64>;
    /// The smallest distance (rad or m) of any joint to its limit along the motion, when
    /// feasible.
    fn limit_distance_min(&self) -> Option<f64>;
    /// With `ik.redundancy: optimize`: how `μ_l2` varies over the arm's self-motion.
    fn self_motion(&self) -> Option<SelfMotionScores>;
    /// The candidate itself, when it is held: always by a [`CandidateScore`]; by
    /// [`CandidateScalars`] only for the candidates a summary names.
    fn candidate(&self) -> Option<&Arc<Candidate>>;
    /// Whether IK succeeded along the whole motion.
    fn feasible(&self) -> bool {
        self.failure_reason().is_none()
    }
}

impl Scored for CandidateScore {
    fn id(&self) -> usize {
        self.candidate.id
    }
    fn log_likelihood(&self) -> f64 {
        self.candidate.log_likelihood
    }
    fn grasp_point(&self) -> Point3<f64> {
        self.candidate.grasp_point()
    }
    fn norms(&self) -> Option<PathNorms> {
        self.norms
    }
    fn failure_reason(&self) -> Option<FailureReason> {
        self.failure.as_ref().map(|f| f.reason)
    }
    fn colliding_bodies(&self) -> Option<&[String; 2]> {
        self.failure
            .as_ref()
            .filter(|f| f.reason == FailureReason::Collision)
            .and_then(|f| f.bodies.as_ref())
    }
    fn clearance(&self) -> Option<f64> {
        self.clearance
    }
    fn yoshikawa_at_grasp(&self) -> Option<f64> {
        self.yoshikawa_at_grasp
    }
    fn torque_margin(&self) -> Option<f64> {
        self.torque_margin
    }
    fn duration(&self) -> Option<f64> {
        self.durations.map(|d| d.total())
    }
    fn limit_distance_min(&self) -> Option<f64> {
        CandidateScore::limit_distance_min(self)
    }
    fn self_motion(&self) -> Option<SelfMotionScores> {
        self.self_motion
    }
    fn candidate(&self) -> Option<&Arc<Candidate>> {
        Some(&self.candidate)
    }
}

/// Where and why a candidate fails, without the failure's text and bodies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FailurePoint {
    /// Why.
    pub reason: FailureReason,
    /// In which part of the motion.
    pub phase: Phase,
    /// The first failing sample of that phase.
    pub sample: usize,
}

/// Every scalar of a candidate's scores for one arm — the candidate's id, log-likelihood and
/// grasp point, the norms, the classical indices at the grasp, the clearance, the branch count,
/// the self-motion scores, where it fails and, for a collision, the two bodies — and no
/// per-sample series, motion, failure text or candidate pose: about 250 bytes, what a streamed
/// selection keeps per candidate and arm.
#[derive(Debug, Clone, PartialEq)]
pub struct CandidateScalars {
    /// The candidate's id.
    pub id: usize,
    /// Its natural log-likelihood.
    pub log_likelihood: f64,
    /// Where the hand holds the object, object frame (m).
    pub grasp_point: Point3<f64>,
    /// Where and why it fails (`None`: feasible).
    pub failure: Option<FailurePoint>,
    /// See [`Scored::colliding_bodies`]: held only for collision failures.
    pub colliding_bodies: Option<Box<[String; 2]>>,
    /// See [`CandidateScore::norms`].
    pub norms: Option<PathNorms>,
    /// See [`CandidateScore::yoshikawa_at_grasp`].
    pub yoshikawa_at_grasp: Option<f64>,
    /// See [`CandidateScore::yoshikawa_penalized_at_grasp`].
    pub yoshikawa_penalized_at_grasp: Option<f64>,
    /// See [`CandidateScore::inverse_condition_at_grasp`].
    pub inverse_condition_at_grasp: Option<f64>,
    /// See [`CandidateScore::inverse_condition_squared_at_grasp`].
    pub inverse_condition_squared_at_grasp: Option<f64>,
    /// See [`CandidateScore::clearance`] (m).
    pub clearance: Option<f64>,
    /// See [`CandidateScore::feasible_branches`].
    pub feasible_branches: usize,
    /// See [`CandidateScore::self_motion`].
    pub self_motion: Option<SelfMotionScores>,
    /// See [`CandidateScore::torque_margin`].
    pub torque_margin: Option<f64>,
    /// See [`CandidateScore::payload_capacity`] (kg).
    pub payload_capacity: Option<f64>,
    /// See [`CandidateScore::dynamic_manipulability`] ((m/s²)²).
    pub dynamic_manipulability: Option<f64>,
    /// See [`CandidateScore::durations`].
    pub durations: Option<MotionDurations>,
    /// See [`CandidateScore::limit_distance_min`] (rad or m).
    pub limit_distance_min: Option<f64>,
    /// The candidate, for those a summary names (the best ranked of each arm and the kept
    /// pairs' members; see [`select_streaming`](super::select_streaming)); `None` otherwise.
    pub candidate: Option<Arc<Candidate>>,
}

impl CandidateScalars {
    /// The scalars of `score` (without its candidate).
    pub fn of(score: &CandidateScore) -> Self {
        Self {
            id: score.candidate.id,
            log_likelihood: score.candidate.log_likelihood,
            grasp_point: score.candidate.grasp_point(),
            failure: score.failure.as_ref().map(|f| FailurePoint {
                reason: f.reason,
                phase: f.phase,
                sample: f.sample,
            }),
            colliding_bodies: score.colliding_bodies().cloned().map(Box::new),
            norms: score.norms,
            yoshikawa_at_grasp: score.yoshikawa_at_grasp,
            yoshikawa_penalized_at_grasp: score.yoshikawa_penalized_at_grasp,
            inverse_condition_at_grasp: score.inverse_condition_at_grasp,
            inverse_condition_squared_at_grasp: score.inverse_condition_squared_at_grasp,
            clearance: score.clearance,
            feasible_branches: score.feasible_branches,
            self_motion: score.self_motion,
            torque_margin: score.torque_margin,
            payload_capacity: score.payload_capacity,
            dynamic_manipulability: score.dynamic_manipulability,
            durations: score.durations,
            limit_distance_min: score.limit_distance_min(),
            candidate: None,
        }
    }
}

impl Scored for CandidateScalars {
    fn id(&self) -> usize {
        self.id
    }
    fn log_likelihood(&self) -> f64 {
        self.log_likelihood
    }
    fn grasp_point(&self) -> Point3<f64> {
        self.grasp_point
    }
    fn norms(&self) -> Option<PathNorms> {
        self.norms
    }
    fn failure_reason(&self) -> Option<FailureReason> {
        self.failure.map(|f| f.reason)
    }
    fn colliding_bodies(&self) -> Option<&[String; 2]> {
        self.colliding_bodies.as_deref()
    }
    fn clearance(&self) -> Option<f64> {
        self.clearance
    }
    fn yoshikawa_at_grasp(&self) -> Option<f64> {
        self.yoshikawa_at_grasp
    }
    fn torque_margin(&self) -> Option<f64> {
        self.torque_margin
    }
    fn duration(&self) -> Option<f64> {
        self.durations.map(|d| d.total())
    }
    fn limit_distance_min(&self) -> Option<f64> {
        self.limit_distance_min
    }
    fn self_motion(&self) -> Option<SelfMotionScores> {
        self.self_motion
    }
    fn candidate(&self) -> Option<&Arc<Candidate>> {
        self.candidate.as_ref()
    }
}
