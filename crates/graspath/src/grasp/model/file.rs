//! The model file: a JSON document with a `format` and a `format_version`.
//!
//! ```text
//! {
//!   "format": "graspath-grasp-model",
//!   "format_version": 2,
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
//!
//! Hand shapes use the file spelling of [`crate::geometry::shape`] (`{box: {size}}`,
//! `{cylinder: {radius, length}}`, `{convex_mesh: {points}}`, ...). Version 1 files (written
//! before version 2 of this format) spelled them `{box: {half}}`, `{sphere: {radius}}`,
//! `{cylinder: {radius, half_length}}` and `{convex_mesh: {mesh: {vertices, triangles},
//! planes}}`; they are still read, converted exactly (sizes are doubled, which is exact; a
//! convex mesh becomes the hull of its vertices), and the model is then a version 2 model.

use super::configuration::ConfigurationSpec;
use super::contact::ContactModel;
use super::{ModelError, ModelParams};
use crate::cloud::FeatureParams;
use crate::grasp::hand::{Hand, HandJointKind};
use nalgebra::Isometry3;
use std::path::Path;

/// The `format` string of model files.
pub const MODEL_FORMAT: &str = "graspath-grasp-model";
/// The model file version this library writes. It also reads version 1 (the hand shapes'
/// earlier spelling; see the module documentation).
pub const MODEL_FORMAT_VERSION: u32 = 2;

/// The most hand-configuration kernels a model file may ask for (one million).
pub const MAX_CONFIGURATION_KERNELS: usize = 1_000_000;

/// Largest deviation of a stored rotation's quaternion norm from 1.
const UNIT_TOLERANCE: f64 = 1e-6;

/// An error unless every value is finite.
fn finite(source_name: &str, field: &str, values: &[f64]) -> Result<(), ModelError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(ModelError::field(
            source_name,
            format!("{field}[{i}]"),
            format!("must be a finite number, got {}", values[i]),
        )),
    }
}

/// An error unless the pose's translation is finite and its rotation a unit quaternion.
fn check_pose(source_name: &str, field: &str, pose: &Isometry3<f64>) -> Result<(), ModelError> {
    finite(
        source_name,
        &format!("{field}.translation"),
        pose.translation.vector.as_slice(),
    )?;
    let q = pose.rotation.coords;
    finite(source_name, &format!("{field}.rotation"), q.as_slice())?;
    let norm = q.norm();
    if (norm - 1.0).abs() > UNIT_TOLERANCE {
        return Err(ModelError::field(
            source_name,
            format!("{field}.rotation"),
            format!("must be a unit quaternion [x, y, z, w], its norm is {norm}"),
        ));
    }
    Ok(())
}

/// The hand's structure: parents before children, joint indices in range, finite numbers,
/// limits in order, positive widths, unit rotations, non-zero axes.
fn check_hand(hand: &Hand, source_name: &str) -> Result<(), ModelError> {
    let fail = |field: String, message: String| ModelError::field(source_name, field, message);
    if hand.links.is_empty() {
        return Err(fail("hand.links".into(), "the hand has no link".into()));
    }
    for (i, j) in hand.joints.iter().enumerate() {
        let at = format!("hand.joints[{i}]");
        finite(source_name, &at, &[j.lower, j.upper, j.sigma])?;
        if j.lower > j.upper {
            return Err(fail(
                at,
                format!("lower limit {} exceeds upper limit {}", j.lower, j.upper),
            ));
        }
        if j.sigma <= 0.0 {
            return Err(fail(
                format!("{at}.sigma"),
                format!("must be positive, got {}", j.sigma),
            ));
        }
    }
    for (i, link) in hand.links.iter().enumerate() {
        let at = |field: &str| format!("hand.links[{i}].{field}");
        match (i, link.parent) {
            (0, None) => {}
            (0, Some(_)) => return Err(fail(at("parent"), "link 0 is the root: no parent".into())),
            (_, Some(p)) if p < i => {}
            (_, Some(p)) => {
                return Err(fail(
                    at("parent"),
                    format!("link {p} does not come before link {i}: parents must come first"),
                ))
            }
            (_, None) => {
                return Err(fail(
                    at("parent"),
                    "only link 0 (the root) has no parent".into(),
                ))
            }
        }
        let joint = &link.joint;
        if joint.kind != HandJointKind::Fixed && joint.joint >= hand.joints.len() {
            return Err(fail(
                at("joint.joint"),
                format!(
                    "{} is not a hand joint ({} joints)",
                    joint.joint,
                    hand.joints.len()
                ),
            ));
        }
        finite(
            source_name,
            &at("joint.multiplier"),
            &[joint.multiplier, joint.offset],
        )?;
        finite(source_name, &at("joint.axis"), joint.axis.as_slice())?;
        if joint.kind != HandJointKind::Fixed && joint.axis.norm() < 1e-9 {
            return Err(fail(at("joint.axis"), "must not be zero".into()));
        }
        check_pose(
            source_name,
            &at("joint.parent_from_joint"),
            &joint.parent_from_joint,
        )?;
        for (k, shape) in link.shapes.iter().enumerate() {
            check_pose(
                source_name,
                &at(&format!("shapes[{k}].link_from_shape")),
                &shape.link_from_shape,
            )?;
            let r = shape.shape.bounding_radius();
            if !(r.is_finite() && r >= 0.0) {
                return Err(fail(
                    at(&format!("shapes[{k}].shape")),
                    "sizes must be finite and non-negative".into(),
                ));
            }
        }
    }
    Ok(())
}

/// A hand shape as version 1 model files spelled it.
#[derive(serde::Deserialize)]
#[serde(rename_all = "snake_case")]
enum ShapeVersion1 {
    Box {
        half: [f64; 3],
    },
    Sphere {
        radius: f64,
    },
    Cylinder {
        radius: f64,
        half_length: f64,
    },
    ConvexMesh {
        mesh: MeshVersion1,
        // The face planes were derived from the mesh; the hull is recomputed.
        #[allow(dead_code)]
        planes: serde::de::IgnoredAny,
    },
}

#[derive(serde::Deserialize)]
struct MeshVersion1 {
    vertices: Vec<[f64; 3]>,
    // The triangles of a convex mesh are its hull's: recomputed from the vertices.
    #[allow(dead_code)]
    triangles: serde::de::IgnoredAny,
}

/// Rewrites the hand shapes of a version 1 model (JSON) in the version 2 spelling and sets
/// `format_version` to 2. Sizes are doubled (exact in binary floating point).
fn upgrade_version_1(value: &mut serde_json::Value, source_name: &str) -> Result<(), ModelError> {
    use crate::geometry::shape::{ConvexMesh, Shape};
    let links = value
        .pointer_mut("/hand/links")
        .and_then(serde_json::Value::as_array_mut);
    for (i, link) in links.into_iter().flatten().enumerate() {
        let shapes = link
            .get_mut("shapes")
            .and_then(serde_json::Value::as_array_mut);
        for (k, entry) in shapes.into_iter().flatten().enumerate() {
            let field = format!("hand.links[{i}].shapes[{k}].shape");
            let Some(old) = entry.get_mut("shape") else {
                continue;
            };
            let fail = |message: String| ModelError::field(source_name, field.clone(), message);
            let parsed: ShapeVersion1 = serde_json::from_value(old.take())
                .map_err(|e| fail(format!("a version 1 hand shape: {e}")))?;
            let shape = match parsed {
                ShapeVersion1::Box { half } => Shape::cuboid(half.map(|h| 2.0 * h)),
                ShapeVersion1::Sphere { radius } => Shape::sphere(radius),
                ShapeVersion1::Cylinder {
                    radius,
                    half_length,
                } => Shape::cylinder(radius, 2.0 * half_length),
                ShapeVersion1::ConvexMesh { mesh, .. } => ConvexMesh::new(
                    mesh.vertices
                        .into_iter()
                        .map(nalgebra::Point3::from)
                        .collect(),
                )
                .map(Shape::ConvexMesh),
            }
            .map_err(|e| fail(e.to_string()))?;
            *old = serde_json::to_value(&shape).map_err(|e| fail(e.to_string()))?;
        }
    }
    value["format_version"] = serde_json::Value::from(MODEL_FORMAT_VERSION);
    Ok(())
}

/// One waypoint of the demonstrated approach, relative to the grasp.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct ApproachWaypoint {
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
    /// One contact model per involved link (internal; see [`GraspModel::contact_links`]).
    pub(crate) contacts: Vec<ContactModel>,
    /// The hand-configuration model (internal).
    pub(crate) configuration: ConfigurationSpec,
    /// The demonstrated approach, pre-grasp first, grasp (identity) last (internal).
    pub(crate) approach: Vec<ApproachWaypoint>,
    /// The demonstrated grasp (training cloud's object frame).
    pub demonstration: DemonstratedGrasp,
}

impl GraspModel {
    /// The hand links in contact in the demonstration, each with its number of contact
    /// points (the samples of its contact model), in the model's order.
    pub fn contact_links(&self) -> impl Iterator<Item = (&str, usize)> {
        self.contacts
            .iter()
            .map(|c| (c.link.as_str(), c.samples.len()))
    }

    /// The model as JSON bytes.
    pub fn to_json(&self) -> Result<Vec<u8>, ModelError> {
        let mut bytes = serde_json::to_vec(self).map_err(|source| ModelError::Encode {
            what: "<model>",
            source,
        })?;
        bytes.push(b'\n');
        Ok(bytes)
    }

    /// Parses a model from JSON text; checks the format and version first.
    pub fn from_json(text: &str, source_name: &str) -> Result<Self, ModelError> {
        let mut value: serde_json::Value = serde_json::from_str(text).map_err(|e| {
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
                        .map_or("nothing".to_string(), ToString::to_string)
                ),
            ));
        }
        match value
            .get("format_version")
            .and_then(serde_json::Value::as_u64)
        {
            Some(v) if v == u64::from(MODEL_FORMAT_VERSION) => {}
            Some(1) => upgrade_version_1(&mut value, source_name)?,
            other => {
                return Err(ModelError::Version {
                    source_name: source_name.to_string(),
                    found: other.map_or_else(
                        || {
                            value
                                .get("format_version")
                                .map_or("none".into(), ToString::to_string)
                        },
                        |v| v.to_string(),
                    ),
                    expected: MODEL_FORMAT_VERSION,
                })
            }
        }
        let model: GraspModel = serde_path_to_error::deserialize(value).map_err(|e| {
            let field = e.path().to_string();
            ModelError::field(
                source_name,
                field,
                crate::input::plain_serde_message(&e.into_inner().to_string()),
            )
        })?;
        model.check(source_name)?;
        Ok(model)
    }

    /// Consistency checks that serde cannot express: every number finite and in its range
    /// (kernel weights ≥ 0 with at least one positive per contact, widths > 0), rotations
    /// unit quaternions, indices in range, counts within [`MAX_CONFIGURATION_KERNELS`].
    pub fn check(&self, source_name: &str) -> Result<(), ModelError> {
        let fail = |field: String, message: String| ModelError::field(source_name, field, message);
        check_hand(&self.hand, source_name)?;
        let dof = self.hand.dof();
        for (field, v) in [
            ("features.normal_radius", self.features.normal_radius),
            ("features.curvature_radius", self.features.curvature_radius),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(fail(
                    field.into(),
                    format!("must be a positive length in metres, got {v}"),
                ));
            }
        }
        if let crate::cloud::NormalOrientation::Viewpoint(v) = self.features.orientation {
            finite(source_name, "features.orientation.viewpoint", &v)?;
        }
        if self.contacts.is_empty() {
            return Err(fail("contacts".into(), "no contact model".into()));
        }
        self.parameters.check(source_name)?;
        for (k, c) in self.contacts.iter().enumerate() {
            let at = |field: &str| format!("contacts[{k}].{field}");
            if c.sigma_r.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
                return Err(fail(at("sigma_r"), "must be positive".into()));
            }
            if c.link_index >= self.hand.links.len() {
                return Err(fail(
                    at("link_index"),
                    format!(
                        "{} is not a link of the hand ({} links)",
                        c.link_index,
                        self.hand.links.len()
                    ),
                ));
            }
            finite(source_name, &at("curvature_mean"), &c.curvature_mean)?;
            finite(source_name, &at("contact_centroid"), &c.contact_centroid)?;
            if c.samples.is_empty() {
                return Err(fail(at("samples"), "no samples".into()));
            }
            for (j, sample) in c.samples.iter().enumerate() {
                let at = |field: &str| format!("contacts[{k}].samples[{j}].{field}");
                if !(sample.weight.is_finite() && sample.weight >= 0.0) {
                    return Err(fail(
                        at("weight"),
                        format!(
                            "a kernel weight must be a non-negative number, got {}",
                            sample.weight
                        ),
                    ));
                }
                finite(source_name, &at("curvature"), &sample.curvature)?;
                finite(source_name, &at("point"), &sample.point)?;
                finite(source_name, &at("normal"), &sample.normal)?;
                check_pose(
                    source_name,
                    &at("feature_from_link"),
                    &sample.feature_from_link,
                )?;
            }
            if !c.samples.iter().any(|s| s.weight > 0.0) {
                return Err(fail(at("samples"), "every kernel weight is zero".into()));
            }
        }
        let config = &self.configuration;
        if config.sigma.len() != dof
            || config.path.is_empty()
            || config.path.iter().any(|h| h.len() != dof)
            || config.sigma.iter().any(|s| !(s.is_finite() && *s > 0.0))
        {
            return Err(fail(
                "configuration".into(),
                format!("path and sigma must have {dof} values per entry (the hand's joints) and positive widths"),
            ));
        }
        for (i, h) in config.path.iter().enumerate() {
            finite(source_name, &format!("configuration.path[{i}]"), h)?;
        }
        if !(config.beta.is_finite() && config.beta >= 0.0) {
            return Err(fail(
                "configuration.beta".into(),
                format!("must be non-negative, got {}", config.beta),
            ));
        }
        if !(config.cutoff.is_finite() && config.cutoff > 0.0) {
            return Err(fail(
                "configuration.cutoff".into(),
                format!("must be positive, got {}", config.cutoff),
            ));
        }
        if config.kernels == 0 || config.kernels > MAX_CONFIGURATION_KERNELS {
            return Err(fail(
                "configuration.kernels".into(),
                format!(
                    "must be between 1 and {MAX_CONFIGURATION_KERNELS}, got {}",
                    config.kernels
                ),
            ));
        }
        if self.approach.is_empty() || self.approach.iter().any(|w| w.hand_joints.len() != dof) {
            return Err(fail(
                "approach".into(),
                format!("needs waypoints with {dof} hand joints"),
            ));
        }
        for (i, w) in self.approach.iter().enumerate() {
            check_pose(
                source_name,
                &format!("approach[{i}].grasp_from_wrist"),
                &w.grasp_from_wrist,
            )?;
            finite(
                source_name,
                &format!("approach[{i}].hand_joints"),
                &w.hand_joints,
            )?;
        }
        crate::geometry::pose_from_rows(&self.demonstration.object_from_wrist)
            .map_err(|e| fail("demonstration.object_from_wrist".into(), e.to_string()))?;
        if self.demonstration.hand_joints.len() != dof {
            return Err(fail(
                "demonstration.hand_joints".into(),
                format!("needs {dof} values (the hand's joints)"),
            ));
        }
        finite(
            source_name,
            "demonstration.hand_joints",
            &self.demonstration.hand_joints,
        )
    }

    /// Reads a model file.
    pub fn read(path: &Path) -> Result<Self, ModelError> {
        Self::from_json(&ModelError::read_text(path)?, &path.display().to_string())
    }

    /// Writes the model file atomically (temporary file in the same directory, then rename).
    pub fn write(&self, path: &Path) -> Result<(), ModelError> {
        let bytes = self.to_json()?;
        crate::output_files::write_file(path, &bytes, crate::output_files::Existing::Replace)?;
        Ok(())
    }
}
