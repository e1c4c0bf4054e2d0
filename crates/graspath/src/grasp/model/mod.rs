//! The one-shot learned grasp model (Kopicki et al., "One-shot learning and generation of
//! dexterous grasps for novel objects", IJRR 2016; `docs/demonstrations.md`): contact models per hand link and a hand-configuration
//! model learned from one demonstration, query densities on a new object cloud, and grasp
//! generation from initial grasps plus simulated annealing with staged selection.
//!
//! Frames: clouds, features and candidate poses are in the **object frame** (metres);
//! `object_from_wrist` is the wrist pose; link poses are `wrist_from_link` (see
//! [`crate::grasp::hand`]).
//!
//! The public surface is what this module re-exports: the model ([`GraspModel`], its
//! [`ModelParams`] and file format), training ([`train`], [`train_file`], [`Demonstration`]),
//! generation ([`generate`], [`GenerateOptions`], [`Candidate`], [`Progress`]), the candidate
//! writer and [`ModelError`]. The contact, hand-configuration and query-density models, the
//! kernels and the collision term behind them are internal (`pub(crate)` at most).

mod collision;
mod configuration;
mod contact;
mod error;
mod file;
mod generate;
mod kernel;
mod lanes;
mod output;
mod query;
mod train;

pub use error::{LinkClearance, ModelError};
/// Re-exported because it is the type of the public field [`GraspModel::demonstration`]: the
/// demonstrated grasp is what generated candidates are compared with (does generation find the
/// demonstration again on the training cloud?).
pub use file::DemonstratedGrasp;
pub use file::{GraspModel, MAX_CONFIGURATION_KERNELS, MODEL_FORMAT, MODEL_FORMAT_VERSION};
pub use generate::{
    generate, Candidate, GenerateOptions, Progress, MAX_GENERATE_STEPS, MAX_GENERATE_TRIES,
    MAX_INITIAL_GRASPS, MAX_QUERY_KERNELS,
};
pub use output::{candidates_json, write_candidates, CANDIDATES_FORMAT};
pub use train::{train, train_file, DemoWaypoint, Demonstration, HandSource, DEMONSTRATION_FORMAT};

use crate::grasp::hand::{Hand, HandJointKind};

/// Training and generation constants stored with a model (defaults: the values of the
/// paper's reference implementation, Golem). Lengths in metres, angles in radians.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct ModelParams {
    /// δ: a cloud point within this distance of a link is a contact (m).
    pub contact_distance: f64,
    /// Largest angle between a point's normal and the direction to the link (rad).
    pub normal_slope: f64,
    /// λ of the contact weight `exp(−λd²)` for links below the root (m⁻²).
    pub finger_lambda: f64,
    /// λ for the root link (the palm) (m⁻²).
    pub palm_lambda: f64,
    /// A link is involved when it has at least this many contact points.
    pub min_points: usize,
    /// F in the curvature bandwidth `σr = F·N^(−1/6)·std(r)`.
    pub curvature_bandwidth_factor: f64,
    /// β: the γ interval of the hand-configuration model is `[−β, β]`.
    pub configuration_beta: f64,
    /// Number of hand-configuration kernels.
    pub configuration_kernels: usize,
    /// Cut-off of hand-configuration kernels, in kernel widths.
    pub configuration_cutoff: f64,
    /// σp of query-density kernels (m).
    pub query_sigma_position: f64,
    /// κ of query-density kernels.
    pub query_kappa: f64,
    /// ρ of the sensor model's spin about the normal.
    pub sensor_rho: f64,
    /// Weight query kernels by the density distance (does the demonstrated contact patch
    /// exist around the kernel?).
    pub density_distance: bool,
    /// Number of contact samples per link used by the density distance.
    pub density_points: usize,
    /// σW of annealing steps (m).
    pub anneal_sigma_position: f64,
    /// κW of annealing steps.
    pub anneal_kappa: f64,
    /// E: the acceptance energy scale.
    pub anneal_energy: f64,
    /// T_min: the final temperature.
    pub anneal_min_temperature: f64,
    /// At most this many cloud points enter the collision term.
    pub collision_points: usize,
    /// At the grasp itself the link shapes are shrunk by this much (m) before counting
    /// penetration: touching is allowed, sinking in is not.
    pub grasp_clearance: f64,
}

impl Default for ModelParams {
    fn default() -> Self {
        Self {
            contact_distance: 0.01,
            normal_slope: std::f64::consts::FRAC_PI_2,
            finger_lambda: 50.0,
            palm_lambda: 20.0,
            min_points: 50,
            curvature_bandwidth_factor: 50.0,
            configuration_beta: 0.5,
            configuration_kernels: 1000,
            configuration_cutoff: 5.0,
            query_sigma_position: 0.005,
            query_kappa: 200.0,
            sensor_rho: 100.0,
            density_distance: true,
            density_points: 50,
            anneal_sigma_position: 0.002,
            anneal_kappa: 1000.0,
            anneal_energy: 0.05,
            anneal_min_temperature: 0.1,
            collision_points: 2000,
            grasp_clearance: 0.003,
        }
    }
}

impl ModelParams {
    /// The defaults for a hand: a hand whose moving joints are all prismatic (a parallel
    /// gripper) gets the gripper annealing constants (σW = 1 mm, κW = 10 000, E = 0.1).
    pub fn for_hand(hand: &Hand) -> Self {
        let gripper = hand
            .links
            .iter()
            .filter(|l| l.joint.kind != HandJointKind::Fixed)
            .all(|l| l.joint.kind == HandJointKind::Prismatic);
        let mut params = Self::default();
        if gripper {
            params.anneal_sigma_position = 0.001;
            params.anneal_kappa = 10000.0;
            params.anneal_energy = 0.1;
        }
        params
    }

    /// Checks that every constant is in its range.
    pub fn check(&self, source_name: &str) -> Result<(), ModelError> {
        let positive = [
            ("contact_distance", self.contact_distance),
            ("finger_lambda", self.finger_lambda),
            ("palm_lambda", self.palm_lambda),
            (
                "curvature_bandwidth_factor",
                self.curvature_bandwidth_factor,
            ),
            ("configuration_cutoff", self.configuration_cutoff),
            ("query_sigma_position", self.query_sigma_position),
            ("query_kappa", self.query_kappa),
            ("anneal_sigma_position", self.anneal_sigma_position),
            ("anneal_kappa", self.anneal_kappa),
            ("anneal_energy", self.anneal_energy),
            ("anneal_min_temperature", self.anneal_min_temperature),
        ];
        for (field, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(ModelError::field(
                    source_name,
                    format!("parameters.{field}"),
                    format!("must be positive, got {v}"),
                ));
            }
        }
        for (field, v) in [
            ("normal_slope", self.normal_slope),
            ("configuration_beta", self.configuration_beta),
            ("sensor_rho", self.sensor_rho),
            ("grasp_clearance", self.grasp_clearance),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(ModelError::field(
                    source_name,
                    format!("parameters.{field}"),
                    format!("must be non-negative, got {v}"),
                ));
            }
        }
        if self.configuration_kernels == 0 {
            return Err(ModelError::field(
                source_name,
                "parameters.configuration_kernels",
                "must be at least 1",
            ));
        }
        Ok(())
    }
}
