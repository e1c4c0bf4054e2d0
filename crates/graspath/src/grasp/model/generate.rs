//! Grasp generation (spec §4): initial grasps (the spec's "seeds") drawn from the query
//! densities and the hand-configuration model, then simulated annealing with staged selection:
//!
//! 1. evaluate every initial grasp (best of `tries` draws) and keep the best `keep_fraction`;
//! 2. anneal them for steps `[0, first_stage_steps)`, add the collision term, re-rank and keep
//!    the best `keep_fraction` again;
//! 3. anneal those for steps `[first_stage_steps, steps)`, add the collision term and sort.
//!
//! The objective is `ℓ = Σ_i ln(Q_i(FK_i)·e^{−pen_i}/Z) + ln C(c)` with `ln 0` replaced by
//! `ln(f64::MIN_POSITIVE)` ≈ −708.4; a candidate's `log_likelihood` is `ℓ` plus its collision
//! term. Every random draw comes from a generator derived from the random seed
//! ([`GenerateOptions::seed`]) and the item's index, so results are identical at any thread
//! count.

use super::collision::{collision_term, CollisionCloud};
use super::configuration::ConfigurationModel;
use super::kernel::{item_rng, sample_vmf_rotation, unit_vector};
use super::query::{object_curvature_stats, QueryDensity};
use super::{GraspModel, ModelError};
use crate::cloud::{compute_features, PointCloud, PointIndex};
use nalgebra::{Isometry3, Point3, Translation3, Vector3};
use rand::{rngs::StdRng, RngExt};
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;

/// The generation budget and random seed.
#[derive(Debug, Clone, PartialEq)]
pub struct GenerateOptions {
    /// Number of initial grasps drawn before annealing (the spec's "seeds"; 50 000 by
    /// default).
    pub initial_grasps: usize,
    /// Total annealing steps S (500).
    pub steps: usize,
    /// Steps of the first stage (50).
    pub first_stage_steps: usize,
    /// Query kernels per involved link (5 000).
    pub query_kernels: usize,
    /// Draws per initial grasp, the best kept (2).
    pub tries: usize,
    /// Fraction kept after the initial grasps and after the first stage (0.1).
    pub keep_fraction: f64,
    /// Random seed of every random choice: the same inputs and seed give the same candidates.
    pub seed: u64,
}

/// The largest number of initial grasps `generate` accepts (200 × the default).
pub const MAX_INITIAL_GRASPS: usize = 10_000_000;
/// The largest number of annealing steps (200 × the default).
pub const MAX_GENERATE_STEPS: usize = 100_000;
/// The largest number of query kernels per link (200 × the default).
pub const MAX_QUERY_KERNELS: usize = 1_000_000;
/// The largest number of draws per initial grasp.
pub const MAX_GENERATE_TRIES: usize = 1_000;

impl Default for GenerateOptions {
    fn default() -> Self {
        Self {
            initial_grasps: 50_000,
            steps: 500,
            first_stage_steps: 50,
            query_kernels: 5000,
            tries: 2,
            keep_fraction: 0.1,
            seed: 0,
        }
    }
}

/// A generated grasp candidate.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// The wrist pose in the object frame (m).
    pub object_from_wrist: Isometry3<f64>,
    /// Hand joints (rad or m).
    pub hand_joints: Vec<f64>,
    /// `ℓ` plus the collision term.
    pub log_likelihood: f64,
    /// The collision term alone (≤ 0).
    pub collision: f64,
    /// Where the hand touches: the mean over involved links of the link's weighted contact
    /// centroid, in the object frame (m).
    pub contact: Option<Point3<f64>>,
}

/// A stage of generation, for progress reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Progress {
    /// Computing features and query densities.
    Preparing,
    /// Initial grasps evaluated so far of the total.
    InitialGrasps(usize, usize),
    /// First annealing stage: solutions done of the total.
    FirstStage(usize, usize),
    /// Second annealing stage: solutions done of the total.
    SecondStage(usize, usize),
}

/// `ln(1e−10)`: an initial grasp whose every factor exceeds 1e−10 needs no further draw.
const EARLY_STOP: f64 = -23.025850929940457;

struct State {
    wrist: Isometry3<f64>,
    joints: Vec<f64>,
    value: f64,
    index: usize,
}

/// Everything the objective needs, built once per cloud.
pub(super) struct Evaluator<'a> {
    model: &'a GraspModel,
    densities: Vec<QueryDensity>,
    log_z: f64,
    configuration: ConfigurationModel,
}

impl<'a> Evaluator<'a> {
    /// Builds the query densities of every involved link on the cloud's features.
    pub(super) fn new(
        model: &'a GraspModel,
        cloud: &PointCloud,
        query_kernels: usize,
        random_seed: u64,
        source_name: &str,
    ) -> Result<Self, ModelError> {
        let features = compute_features(cloud, &model.features, source_name)?;
        let index = PointIndex::new(&cloud.points);
        let stats = object_curvature_stats(&features, model.parameters.curvature_bandwidth_factor);
        let mut densities = Vec::new();
        for contact in &model.contacts {
            let density = QueryDensity::build(
                contact,
                &features,
                &index,
                stats,
                &model.parameters,
                query_kernels,
                random_seed,
            );
            if density.is_empty() {
                return Err(ModelError::field(
                    source_name,
                    "points",
                    format!(
                        "no surface of the cloud matches the contact of link '{}'",
                        contact.link
                    ),
                ));
            }
            densities.push(density);
        }
        let log_z = densities
            .iter()
            .map(|d| d.total_weight().ln() + d.log_factor)
            .fold(f64::NEG_INFINITY, f64::max);
        Ok(Self {
            model,
            densities,
            log_z,
            configuration: ConfigurationModel::new(model.configuration.clone()),
        })
    }

    /// `ℓ(W, c)` without the collision term; `poses` is scratch space.
    pub(super) fn log_likelihood(
        &self,
        wrist: &Isometry3<f64>,
        joints: &[f64],
        poses: &mut Vec<Isometry3<f64>>,
    ) -> f64 {
        self.terms(wrist, joints, poses).0
    }

    /// `ℓ` and the smallest of its log factors.
    fn terms(
        &self,
        wrist: &Isometry3<f64>,
        joints: &[f64],
        poses: &mut Vec<Isometry3<f64>>,
    ) -> (f64, f64) {
        self.terms_above(wrist, joints, poses, f64::NEG_INFINITY)
            .unwrap_or((f64::NEG_INFINITY, f64::NEG_INFINITY))
    }

    /// Like [`Evaluator::terms`], but gives up (`None`) as soon as the partial sum falls below
    /// `threshold`: every factor is at most 1 (`Q_i·e^{−pen_i} ≤ Z`, `C ≤ 1`), so the
    /// remaining terms cannot lift it back.
    fn terms_above(
        &self,
        wrist: &Isometry3<f64>,
        joints: &[f64],
        poses: &mut Vec<Isometry3<f64>>,
        threshold: f64,
    ) -> Option<(f64, f64)> {
        let floor = f64::MIN_POSITIVE.ln();
        let c = self.configuration.density(joints);
        let mut total = if c > 0.0 {
            c.ln().max(floor).min(0.0)
        } else {
            floor
        };
        let mut smallest = total;
        if total < threshold {
            return None;
        }
        self.model.hand.link_poses_into(joints, poses);
        for d in &self.densities {
            let q = d.evaluate(&(wrist * poses[d.link_index]));
            let term = if q > 0.0 {
                (q.ln() + d.log_factor - self.log_z).clamp(floor, 0.0)
            } else {
                floor
            };
            smallest = smallest.min(term);
            total += term;
            if total < threshold {
                return None;
            }
        }
        Some((total, smallest))
    }

    fn initial_state(
        &self,
        rng: &mut StdRng,
        poses: &mut Vec<Isometry3<f64>>,
    ) -> Option<(Isometry3<f64>, Vec<f64>)> {
        let d = &self.densities[rng.random_range(0..self.densities.len())];
        let link_pose = d.sample(rng)?;
        let mut joints = self.configuration.sample(rng);
        self.model.hand.clamp(&mut joints);
        self.model.hand.link_poses_into(&joints, poses);
        Some((link_pose * poses[d.link_index].inverse(), joints))
    }

    fn anneal(
        &self,
        state: &mut State,
        steps: std::ops::Range<usize>,
        total_steps: usize,
        rng: &mut StdRng,
        poses: &mut Vec<Isometry3<f64>>,
    ) {
        let p = &self.model.parameters;
        let mut joints = state.joints.clone();
        for i in steps {
            let s = (total_steps as f64 - i as f64 - 1.0) / total_steps as f64;
            let t = s + (1.0 - s) * p.anneal_min_temperature;
            let e: f64 = StandardNormal.sample(rng);
            let shift = unit_vector(rng) * (e * t * p.anneal_sigma_position).abs();
            let turn = sample_vmf_rotation(p.anneal_kappa / (t * t), rng);
            let proposal = state.wrist * Isometry3::from_parts(Translation3::from(shift), turn);
            for ((v, c), j) in joints
                .iter_mut()
                .zip(&state.joints)
                .zip(&self.model.hand.joints)
            {
                let e: f64 = StandardNormal.sample(rng);
                *v = c + e * t * j.sigma;
            }
            self.model.hand.clamp(&mut joints);
            // Accept when ℓ' > ℓ or exp((ℓ' − ℓ)/(E·T)) > u, i.e. when ℓ' > ℓ + E·T·ln u.
            let u: f64 = rng.random();
            let threshold = state.value + p.anneal_energy * t * u.max(f64::MIN_POSITIVE).ln();
            if let Some((value, _)) = self.terms_above(&proposal, &joints, poses, threshold) {
                state.wrist = proposal;
                state.value = value;
                state.joints.copy_from_slice(&joints);
            }
        }
    }

    fn contact_point(&self, wrist: &Isometry3<f64>, joints: &[f64]) -> Option<Point3<f64>> {
        let poses = self.model.hand.link_poses(joints);
        let sum: Vector3<f64> = self
            .model
            .contacts
            .iter()
            .map(|c| (wrist * poses[c.link_index] * Point3::from(c.contact_centroid)).coords)
            .sum();
        (!self.model.contacts.is_empty())
            .then(|| Point3::from(sum / self.model.contacts.len() as f64))
    }
}

fn rank(states: &mut [State]) {
    states.sort_by(|a, b| b.value.total_cmp(&a.value).then(a.index.cmp(&b.index)));
}

fn keep(n: usize, fraction: f64) -> usize {
    ((n as f64 * fraction).ceil() as usize).clamp(1.min(n), n)
}

/// Runs `f` over `items` in parallel in chunks, reporting progress after each chunk.
fn chunked<T: Send, U: Send>(
    items: Vec<T>,
    f: impl Fn(T) -> U + Sync,
    report: impl Fn(usize),
) -> Vec<U> {
    const CHUNK: usize = 1024;
    let mut out = Vec::with_capacity(items.len());
    let mut items = items.into_iter().peekable();
    while items.peek().is_some() {
        let chunk: Vec<T> = items.by_ref().take(CHUNK).collect();
        out.extend(chunk.into_par_iter().map(&f).collect::<Vec<U>>());
        report(out.len());
    }
    out
}

/// Generates candidates for `cloud` (object frame) from a trained model, best first.
/// `source_name` names the cloud in errors; `progress` is called between chunks of work.
pub fn generate(
    model: &GraspModel,
    cloud: &PointCloud,
    options: &GenerateOptions,
    source_name: &str,
    progress: &dyn Fn(Progress),
) -> Result<Vec<Candidate>, ModelError> {
    if options.initial_grasps == 0 || options.tries == 0 || options.query_kernels == 0 {
        return Err(ModelError::field(
            "options",
            "initial_grasps/tries/query_kernels",
            "must be at least 1",
        ));
    }
    if !(options.keep_fraction > 0.0 && options.keep_fraction <= 1.0) {
        return Err(ModelError::field(
            "options",
            "keep_fraction",
            "must be in (0, 1]",
        ));
    }
    for (name, value, limit) in [
        ("initial_grasps", options.initial_grasps, MAX_INITIAL_GRASPS),
        ("steps", options.steps, MAX_GENERATE_STEPS),
        ("query_kernels", options.query_kernels, MAX_QUERY_KERNELS),
        ("tries", options.tries, MAX_GENERATE_TRIES),
    ] {
        if value > limit {
            return Err(ModelError::field(
                "options",
                name,
                format!("{value} is more than the limit {limit} (each costs memory and time)"),
            ));
        }
    }
    progress(Progress::Preparing);
    let evaluator = Evaluator::new(
        model,
        cloud,
        options.query_kernels,
        options.seed,
        source_name,
    )?;
    let collision_cloud = CollisionCloud::new(&cloud.points, model.parameters.collision_points);
    let seed = options.seed;
    let n_initial = options.initial_grasps;
    let initial: Vec<State> = chunked(
        (0..n_initial).collect(),
        |k| {
            let mut rng = item_rng(seed, 1, k as u64);
            let mut poses = Vec::new();
            let mut best: Option<State> = None;
            for _ in 0..options.tries {
                if let Some((wrist, joints)) = evaluator.initial_state(&mut rng, &mut poses) {
                    let (value, smallest) = evaluator.terms(&wrist, &joints, &mut poses);
                    if best.as_ref().is_none_or(|b| value > b.value) {
                        best = Some(State {
                            wrist,
                            joints,
                            value,
                            index: k,
                        });
                    }
                    // Every factor above 1e−10: good enough, no further draw (spec §4.2).
                    if smallest > EARLY_STOP {
                        break;
                    }
                }
            }
            best
        },
        |done| progress(Progress::InitialGrasps(done, n_initial)),
    )
    .into_iter()
    .flatten()
    .collect();
    let mut states = initial;
    rank(&mut states);
    states.truncate(keep(states.len(), options.keep_fraction));
    let steps = options.steps;
    let first = options.first_stage_steps.min(steps);
    let hand = &model.hand;
    let demo_grasp = &model.demonstration.hand_joints;
    let clearance = model.parameters.grasp_clearance;
    let stage = |states: Vec<State>,
                 range: std::ops::Range<usize>,
                 stream: u64,
                 report: &dyn Fn(usize)|
     -> Vec<(State, f64)> {
        chunked(
            states,
            |mut s| {
                let mut rng = item_rng(seed, stream, s.index as u64);
                let mut poses = Vec::new();
                evaluator.anneal(&mut s, range.clone(), steps, &mut rng, &mut poses);
                let collision = collision_term(
                    &collision_cloud,
                    hand,
                    &model.approach,
                    demo_grasp,
                    clearance,
                    &s.wrist,
                    &s.joints,
                );
                (s, collision)
            },
            report,
        )
    };
    let n1 = states.len();
    let after_first = stage(states, 0..first, 2, &|done| {
        progress(Progress::FirstStage(done, n1));
    });
    let mut states: Vec<State> = after_first
        .into_iter()
        .map(|(mut s, collision)| {
            s.value += collision;
            s
        })
        .collect();
    rank(&mut states);
    states.truncate(keep(states.len(), options.keep_fraction));
    // The second stage anneals ℓ without the collision term again.
    let mut poses = Vec::new();
    for s in &mut states {
        s.value = evaluator.log_likelihood(&s.wrist, &s.joints, &mut poses);
    }
    let n2 = states.len();
    let after_second = stage(states, first..steps, 3, &|done| {
        progress(Progress::SecondStage(done, n2));
    });
    let mut candidates: Vec<(usize, Candidate)> = after_second
        .into_iter()
        .map(|(s, collision)| {
            let contact = evaluator.contact_point(&s.wrist, &s.joints);
            (
                s.index,
                Candidate {
                    object_from_wrist: s.wrist,
                    hand_joints: s.joints,
                    log_likelihood: s.value + collision,
                    collision,
                    contact,
                },
            )
        })
        .collect();
    candidates.sort_by(|a, b| {
        b.1.log_likelihood
            .total_cmp(&a.1.log_likelihood)
            .then(a.0.cmp(&b.0))
    });
    Ok(candidates.into_iter().map(|(_, c)| c).collect())
}
