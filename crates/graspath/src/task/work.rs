//! What a task will cost before it runs: its work in kinematics evaluations
//! ([`WorkEstimate`], bounded by [`Limits::max_work`]) and the memory of its selection held
//! whole (bounded by `limits.max_memory_mib`).

use super::error::TaskError;
use super::sealed::{ArmSetup, Task};
use super::settings::{Limits, Redundancy};

impl Task {
    /// The work estimate of this task in kinematics evaluations (see [`Limits::max_work`]):
    /// the total of [`Task::work_estimate`].
    pub fn work(&self) -> u64 {
        self.work_estimate().total()
    }

    /// An upper bound on the memory (bytes) of this task's selection held whole
    /// ([`select`](crate::select::select)): per arm and candidate, its record and every
    /// sample's joint values (approach, path, retreat), `M_T` and limit distance.
    pub fn selection_memory(&self) -> u64 {
        const RECORD_BYTES: u64 = 1024;
        const VEC_BYTES: u64 = 24;
        let samples = (self.path.samples.len()
            + self.approach.map_or(0, |s| s.samples)
            + self.retreat.map_or(0, |s| s.samples)) as u64;
        let candidates = self.candidate_count() as u64;
        self.arms
            .iter()
            .map(|arm| {
                let per_sample = VEC_BYTES + 8 * arm.chain.dof() as u64 + 16 + 8;
                candidates
                    .saturating_mul(RECORD_BYTES.saturating_add(samples.saturating_mul(per_sample)))
            })
            .fold(0u64, u64::saturating_add)
    }

    /// `Ok` when [`Task::selection_memory`] is within `limits.max_memory_mib`; else an error
    /// that names the limit and the streamed formats that need no such memory. Called before
    /// a selection is held whole (`select --format json`, Python's `select`).
    pub fn check_selection_memory(&self) -> Result<(), TaskError> {
        let bytes = self.selection_memory();
        let limit = self.limits.max_memory_mib.saturating_mul(1 << 20);
        if bytes <= limit {
            return Ok(());
        }
        Err(TaskError::new(
            &self.source_name,
            "limits.max_memory_mib",
            format!(
                "holding the whole selection ({} arm(s) × {} candidates with their joint \
                 trajectories) takes about {} MiB, more than the limit {} MiB: stream it \
                 (JSON Lines or Parquet records, Python `select_batch`) or raise \
                 limits.max_memory_mib",
                self.arms.len(),
                self.candidate_count(),
                bytes >> 20,
                self.limits.max_memory_mib,
            ),
        ))
    }

    /// Whether the two arms' motions are checked against each other (a scene with
    /// `collision.between_arms`, two arms, and bodies for both).
    pub fn checks_arms_against_each_other(&self) -> bool {
        self.collisions
            .as_ref()
            .is_some_and(|c| c.options.between_arms)
            && self.arms.len() >= 2
            && self.arms[0].bodies.is_some()
            && self.arms[1].bodies.is_some()
    }

    /// The work estimate of this task by part, in kinematics evaluations: an upper bound on
    /// scoring (IK along every branch), on the collision checks against the scene, and on
    /// the two-arm pair search when no pair is valid (every pair visited).
    pub fn work_estimate(&self) -> WorkEstimate {
        let samples = self.path.samples.len()
            + self.approach.map_or(0, |s| s.samples)
            + self.retreat.map_or(0, |s| s.samples);
        let candidates = self.candidate_count() as u64;
        let scoring = Limits::work(
            self.arms.len(),
            self.candidate_count(),
            samples,
            self.ik.branches,
            self.ik.ik.max_iterations,
            self.ik.per_sample_iterations,
        );
        let bodies = |arm: &ArmSetup| arm.bodies.as_ref().map_or(0, |b| b.bodies.len()) as u64;
        let scene_bodies = self
            .collisions
            .as_ref()
            .map_or(0, |c| c.scene.bodies().len() as u64);
        // Every moving body and the object against every scene body, at every sample of
        // every branch.
        let collisions = self
            .arms
            .iter()
            .map(|arm| {
                candidates
                    .saturating_mul(self.ik.branches as u64)
                    .saturating_mul(samples as u64)
                    .saturating_mul(bodies(arm).saturating_add(1))
                    .saturating_mul(scene_bodies)
                    / WorkEstimate::COLLISION_PAIRS_PER_EVALUATION
            })
            .fold(0u64, u64::saturating_add);
        let pairs = if self.arms.len() == 2 {
            let visited = candidates.saturating_mul(candidates);
            let between = if self.checks_arms_against_each_other() {
                visited
                    .saturating_mul(samples as u64)
                    .saturating_mul(bodies(&self.arms[0]).saturating_mul(bodies(&self.arms[1])))
                    / WorkEstimate::COLLISION_PAIRS_PER_EVALUATION
            } else {
                0
            };
            (visited / WorkEstimate::PAIR_VISITS_PER_EVALUATION).saturating_add(between)
        } else {
            0
        };
        let per_candidate = |evaluations_per_sample: u64| -> u64 {
            (self.arms.len() as u64)
                .saturating_mul(candidates)
                .saturating_mul(samples as u64)
                .saturating_mul(evaluations_per_sample)
        };
        let self_motion = if self.redundancy == Redundancy::Optimize {
            per_candidate(WorkEstimate::SELF_MOTION_EVALUATIONS_PER_SAMPLE)
        } else {
            0
        };
        let timing = self.timing.as_ref().map_or(0, |t| {
            let per_grid_point = if t.torque_limits {
                WorkEstimate::TIMING_EVALUATIONS_PER_TORQUE_POINT
            } else {
                1
            };
            per_candidate((t.subdivisions as u64).saturating_mul(per_grid_point))
        });
        WorkEstimate {
            scoring,
            self_motion,
            timing,
            collisions,
            pairs,
        }
    }
}

/// A task's work estimate by part, in kinematics evaluations (one forward kinematics and
/// Jacobian of one arm; [`Limits::max_work`]). Each part is an upper bound measured against
/// release builds (BENCHMARKS.md, "Work estimate"): scoring assumes every IK branch runs its
/// whole budget, the self-motion search and the timing every sample at their largest costs,
/// the collision part every body checked against every scene body at every
/// sample, the pair part a search that finds no valid pair and so visits every pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WorkEstimate {
    /// IK and indices: arms × candidates × branches × (grasp iterations + samples × per
    /// sample iterations).
    pub scoring: u64,
    /// With `ik.redundancy: optimize`, the self-motion search: arms × candidates × samples ×
    /// [`WorkEstimate::SELF_MOTION_EVALUATIONS_PER_SAMPLE`].
    pub self_motion: u64,
    /// When motions are timed: arms × candidates × samples × the timing's grid points per
    /// sample, each one evaluation (with torque limits,
    /// [`WorkEstimate::TIMING_EVALUATIONS_PER_TORQUE_POINT`]).
    pub timing: u64,
    /// The scene: arms × candidates × branches × samples × (arm bodies + object) × scene
    /// bodies, at [`WorkEstimate::COLLISION_PAIRS_PER_EVALUATION`] body pairs an evaluation.
    pub collisions: u64,
    /// Two arms: candidates² pairs visited, at [`WorkEstimate::PAIR_VISITS_PER_EVALUATION`]
    /// an evaluation, and with `collision.between_arms` the two motions' bodies checked
    /// against each other at every sample of every pair.
    pub pairs: u64,
}

impl WorkEstimate {
    /// Body pairs whose distance costs about one kinematics evaluation.
    pub const COLLISION_PAIRS_PER_EVALUATION: u64 = 8;
    /// Pairs of the two-arm search visited in about one kinematics evaluation.
    pub const PAIR_VISITS_PER_EVALUATION: u64 = 1;
    /// Kinematics evaluations of the self-motion search per sample: the curve traced both
    /// ways in 4 steps of about 4 corrections each, and the chosen place traced to (and
    /// checked against the previous sample's) in up to 8 corrections each. Like the other
    /// parts, an upper bound on the measured time (BENCHMARKS.md, "Smooth self-motion": the
    /// search takes about 35 evaluations' time per sample on two cores), not on every
    /// iteration budget.
    pub const SELF_MOTION_EVALUATIONS_PER_SAMPLE: u64 = 2 * 4 * 4 + 2 * 8;
    /// Evaluations per timing grid point with torque limits: the inverse dynamics of the arm
    /// three times (gravity, `M q'`, `M q'' + C q'`) and the path's derivatives.
    pub const TIMING_EVALUATIONS_PER_TORQUE_POINT: u64 = 4;

    /// The whole estimate (saturating).
    pub fn total(&self) -> u64 {
        self.scoring
            .saturating_add(self.self_motion)
            .saturating_add(self.timing)
            .saturating_add(self.collisions)
            .saturating_add(self.pairs)
    }

    /// The parts, with what each counts, for a message.
    pub(super) fn explain(&self, task: &Task) -> String {
        let mut parts = vec![format!(
            "scoring {:.3e} ({} arm(s) × {} candidates × {} branches × ({} grasp iterations + {} \
             samples × {} per sample))",
            self.scoring as f64,
            task.arms.len(),
            task.candidate_count(),
            task.ik.branches,
            task.ik.ik.max_iterations,
            task.path.samples.len(),
            task.ik.per_sample_iterations,
        )];
        if self.self_motion > 0 {
            parts.push(format!(
                "self-motion search {:.3e} (ik.redundancy: optimize; first costs none)",
                self.self_motion as f64,
            ));
        }
        if self.timing > 0 {
            parts.push(format!(
                "timing {:.3e} (timing: false costs none)",
                self.timing as f64,
            ));
        }
        if self.collisions > 0 {
            parts.push(format!(
                "scene {:.3e} ({} scene bodies against the arm's bodies at every sample)",
                self.collisions as f64,
                task.collisions
                    .as_ref()
                    .map_or(0, |c| c.scene.bodies().len()),
            ));
        }
        if self.pairs > 0 {
            parts.push(format!(
                "pairs {:.3e} (up to {}² pairs of the two arms' candidates)",
                self.pairs as f64,
                task.candidate_count(),
            ));
        }
        parts.join(", ")
    }
}
