//! The model file: a JSON document with a `format` and a `format_version`.
//!
//! ```text
//! {
//!   "format": "graspath-grasp-model",
//!   "format_version": 1,
//!   "label": "pinch",                     grasp type, copied to every candidate
//!   "hand": { name, joints, links },      the hand, self-contained (shapes included)
//!   "features": { normal_radius, curvature_radius, orientation, recompute_normals },
//!   "parameters": { ... },                training and generation constants (ModelParams)
//!   "contacts": [ { link, link_index, sigma_r, curvature_mean, contact_centroid,
//!                   samples: [ { feature_from_link, curvature, weight, point, normal } ] } ],
//!   "configuration": { path, sigma, beta, kernels, cutoff },
//!   "approach": [ { grasp_from_wrist, hand_joints } ],   pre-grasp first, grasp last
//!   "demonstration": { object_from_wrist, hand_joints }   the demonstrated grasp
//! }
//! ```
//!
//! Poses (`feature_from_link`, `grasp_from_wrist`) use nalgebra's serde form
//! `{"rotation": [x, y, z, w], "translation": [x, y, z]}` (metres); `object_from_wrist` is a
//! 4×4 row-major matrix. Distances are in metres, angles in radians.

use super::configuration::ConfigurationSpec;
use super::contact::ContactModel;
use super::{ModelError, ModelParams};
use crate::cloud::FeatureParams;
use crate::grasp::hand::Hand;
use nalgebra::Isometry3;
use std::path::Path;

/// The `format` string of model files.
pub const MODEL_FORMAT: &str = "graspath-grasp-model";
/// The model file version this library reads and writes.
pub const MODEL_FORMAT_VERSION: u32 = 1;

/// One waypoint of the demonstrated approach, relative to the grasp.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ApproachWaypoint {
    /// `W_g⁻¹ ∘ W_k`: the wrist at this waypoint in the grasp wrist frame (m).
    pub grasp_from_wrist: Isometry3<f64>,
    /// Hand joints at this waypoint.
    pub hand_joints: Vec<f64>,
}

/// The demonstrated grasp, in the training cloud's object frame.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DemonstratedGrasp {
    /// The wrist pose, 4×4 row-major (m).
    pub object_from_wrist: [[f64; 4]; 4],
    /// The hand joints.
    pub hand_joints: Vec<f64>,
}

/// A trained one-shot grasp model.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GraspModel {
    /// Always [`MODEL_FORMAT`].
    pub format: String,
    /// Always [`MODEL_FORMAT_VERSION`].
    pub format_version: u32,
    /// The grasp type's name, copied to the candidates' `label`.
    pub label: String,
    /// The hand.
    pub hand: Hand,
    /// How surface features are computed (the same on new clouds).
    pub features: FeatureParams,
    /// Training and generation constants.
    pub parameters: ModelParams,
    /// One contact model per involved link.
    pub contacts: Vec<ContactModel>,
    /// The hand-configuration model.
    pub configuration: ConfigurationSpec,
    /// The demonstrated approach, pre-grasp first, grasp (identity) last.
    pub approach: Vec<ApproachWaypoint>,
    /// The demonstrated grasp.
    pub demonstration: DemonstratedGrasp,
}

impl GraspModel {
    /// The model as JSON bytes.
    pub fn to_json(&self) -> Result<Vec<u8>, ModelError> {
        let mut bytes = serde_json::to_vec(self).map_err(|e| ModelError::io("<model>", e))?;
        bytes.push(b'\n');
        Ok(bytes)
    }

    /// Parses a model from JSON text; checks the format and version first.
    pub fn from_json(text: &str, source_name: &str) -> Result<Self, ModelError> {
        let value: serde_json::Value = serde_json::from_str(text).map_err(|e| {
            ModelError::field(source_name, format!("line {}", e.line()), e.to_string())
        })?;
        let format = value.get("format").and_then(|v| v.as_str());
        if format != Some(MODEL_FORMAT) {
            return Err(ModelError::field(
                source_name,
                "format",
                format!(
                    "expected \"{MODEL_FORMAT}\", found {}",
                    value
                        .get("format")
                        .map_or("nothing".to_string(), |v| v.to_string())
                ),
            ));
        }
        match value.get("format_version").and_then(|v| v.as_u64()) {
            Some(v) if v == u64::from(MODEL_FORMAT_VERSION) => {}
            other => {
                return Err(ModelError::Version {
                    source_name: source_name.to_string(),
                    found: other.map_or_else(
                        || {
                            value
                                .get("format_version")
                                .map_or("none".into(), |v| v.to_string())
                        },
                        |v| v.to_string(),
                    ),
                    expected: MODEL_FORMAT_VERSION,
                })
            }
        }
        let model: GraspModel = serde_json::from_value(value)
            .map_err(|e| ModelError::field(source_name, "model", e.to_string()))?;
        model.check(source_name)?;
        Ok(model)
    }

    /// Consistency checks that serde cannot express.
    pub fn check(&self, source_name: &str) -> Result<(), ModelError> {
        let dof = self.hand.dof();
        if self.contacts.is_empty() {
            return Err(ModelError::field(
                source_name,
                "contacts",
                "no contact model",
            ));
        }
        self.parameters.check(source_name)?;
        for (k, c) in self.contacts.iter().enumerate() {
            if c.sigma_r.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
                return Err(ModelError::field(
                    source_name,
                    format!("contacts[{k}].sigma_r"),
                    "must be positive",
                ));
            }
            if c.link_index >= self.hand.links.len() || c.samples.is_empty() {
                return Err(ModelError::field(
                    source_name,
                    format!("contacts[{k}]"),
                    "bad link index or no samples",
                ));
            }
        }
        if self.configuration.sigma.len() != dof
            || self.configuration.path.is_empty()
            || self.configuration.path.iter().any(|h| h.len() != dof)
            || self
                .configuration
                .sigma
                .iter()
                .any(|s| !(s.is_finite() && *s > 0.0))
        {
            return Err(ModelError::field(
                source_name,
                "configuration",
                format!("path and sigma must have {dof} values per entry (the hand's joints) and positive widths"),
            ));
        }
        if self.approach.is_empty() || self.approach.iter().any(|w| w.hand_joints.len() != dof) {
            return Err(ModelError::field(
                source_name,
                "approach",
                format!("needs waypoints with {dof} hand joints"),
            ));
        }
        Ok(())
    }

    /// Reads a model file.
    pub fn read(path: &Path) -> Result<Self, ModelError> {
        Self::from_json(&ModelError::read_text(path)?, &path.display().to_string())
    }

    /// Writes the model file atomically (temporary file in the same directory, then rename).
    pub fn write(&self, path: &Path) -> Result<(), ModelError> {
        let bytes = self.to_json()?;
        crate::fsutil::write_atomic(path, &bytes)
            .map_err(|e| ModelError::io(path.display().to_string(), e))
    }
}
