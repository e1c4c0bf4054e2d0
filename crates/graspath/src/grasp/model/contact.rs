//! Contact models: for each hand link near the object at the demonstrated grasp, the link pose
//! relative to every nearby surface feature, with the feature's curvature and a weight.

use super::ModelParams;
use crate::cloud::SurfaceFeature;
use crate::grasp::hand::Hand;
use crate::grasp::model::error::LinkClearance;
use nalgebra::{Isometry3, Point3, Vector3};

/// One sample `(u, r, w)` of a contact model.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct ContactSample {
    /// `u = v⁻¹ ∘ B`: the link pose in the surface-feature frame (m).
    pub feature_from_link: Isometry3<f64>,
    /// The feature's curvature `(pc1, pc2)`.
    pub curvature: [f64; 2],
    /// `w = exp(−λ d²)`, d the point's distance to the link (m).
    pub weight: f64,
    /// The feature position in the link frame (m).
    pub point: [f64; 3],
    /// The feature normal in the link frame (unit).
    pub normal: [f64; 3],
}

/// The contact model `M_i` of one link.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct ContactModel {
    /// The link's name.
    pub link: String,
    /// The link's index in the hand.
    pub link_index: usize,
    /// Curvature kernel widths `σr` per dimension (data-driven, Scott's rule × F).
    pub sigma_r: [f64; 2],
    /// Mean curvature of the samples.
    pub curvature_mean: [f64; 2],
    /// The weighted centroid of the sample points in the link frame (m): where the link
    /// touches.
    pub contact_centroid: [f64; 3],
    /// The samples.
    pub samples: Vec<ContactSample>,
}

/// Smallest curvature kernel width (pc units), so that perfectly flat training data still
/// gives a usable kernel.
pub(super) const MIN_SIGMA_R: f64 = 1e-4;

/// `σ_d = F · N^(−1/6) · std_d` (Scott's factor for two dimensions), floored at
/// [`MIN_SIGMA_R`]; and the mean. `values` are `(pc1, pc2)` pairs.
pub(super) fn curvature_bandwidth(
    values: impl Iterator<Item = [f64; 2]> + Clone,
    factor: f64,
) -> ([f64; 2], [f64; 2]) {
    let n = values.clone().count().max(1) as f64;
    let mut mean = [0.0; 2];
    for v in values.clone() {
        mean[0] += v[0] / n;
        mean[1] += v[1] / n;
    }
    let mut var = [0.0; 2];
    for v in values {
        var[0] += (v[0] - mean[0]).powi(2) / n;
        var[1] += (v[1] - mean[1]).powi(2) / n;
    }
    let scott = n.powf(-1.0 / 6.0);
    let sigma = var.map(|v| (factor * scott * v.sqrt()).max(MIN_SIGMA_R));
    (sigma, mean)
}

/// The contact models of every link with at least `params.min_points` accepted points, and
/// the clearance of every link with shapes (for error messages).
pub(super) fn train_contacts(
    hand: &Hand,
    features: &[SurfaceFeature],
    object_from_wrist: &Isometry3<f64>,
    hand_joints: &[f64],
    params: &ModelParams,
) -> (Vec<ContactModel>, Vec<LinkClearance>) {
    let wrist_from_link = hand.link_poses(hand_joints);
    let wrist_from_object = object_from_wrist.inverse();
    let cos_slope = params.normal_slope.cos();
    let mut models = Vec::new();
    let mut clearances = Vec::new();
    for (i, link) in hand.links.iter().enumerate() {
        if link.shapes.is_empty() {
            continue;
        }
        let lambda = if link.parent.is_none() {
            params.palm_lambda
        } else {
            params.finger_lambda
        };
        let object_from_link = object_from_wrist * wrist_from_link[i];
        let mut samples = Vec::new();
        let mut closest = f64::INFINITY;
        for f in features {
            let p = wrist_from_object * f.position;
            let Some(prox) = hand.link_proximity(i, &wrist_from_link[i], &p) else {
                continue;
            };
            let d = prox.signed_distance;
            closest = closest.min(d);
            if d >= params.contact_distance {
                continue;
            }
            if d > 0.0 {
                let n = wrist_from_object * f.normal;
                let to_link = prox.closest - p;
                if n.dot(&to_link) < cos_slope * to_link.norm() {
                    continue;
                }
            }
            let feature_from_link = f.pose().inverse() * object_from_link;
            let link_from_feature = feature_from_link.inverse();
            let point = link_from_feature.translation.vector;
            let normal = link_from_feature.rotation * Vector3::z();
            samples.push(ContactSample {
                feature_from_link,
                curvature: f.curvature,
                weight: (-lambda * d * d).exp(),
                point: [point.x, point.y, point.z],
                normal: [normal.x, normal.y, normal.z],
            });
        }
        clearances.push(LinkClearance {
            link: link.name.clone(),
            accepted: samples.len(),
            closest,
        });
        if samples.len() < params.min_points {
            continue;
        }
        let (sigma_r, curvature_mean) = curvature_bandwidth(
            samples.iter().map(|s| s.curvature),
            params.curvature_bandwidth_factor,
        );
        let total: f64 = samples.iter().map(|s| s.weight).sum();
        let centroid = samples.iter().fold(Point3::origin(), |acc, s| {
            acc + Vector3::from(s.point) * (s.weight / total)
        });
        models.push(ContactModel {
            link: link.name.clone(),
            link_index: i,
            sigma_r,
            curvature_mean,
            contact_centroid: [centroid.x, centroid.y, centroid.z],
            samples,
        });
    }
    (models, clearances)
}

#[cfg(test)]
mod tests {
    /// Every contact sample satisfies `feature ∘ u = link` at the demonstrated grasp, its point
    /// lies within δ of the link, and its weight is `exp(−λd²)`.
    #[test]
    fn contact_samples_encode_the_demonstrated_link_poses() {
        let model = crate::grasp::model::train_file(
            &std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("../../examples/grasp/demo_box.json"),
        )
        .expect("train");
        let wrist =
            crate::geometry::pose_from_rows(&model.demonstration.object_from_wrist).expect("pose");
        let poses = model.hand.link_poses(&model.demonstration.hand_joints);
        for contact in &model.contacts {
            let object_from_link = wrist * poses[contact.link_index];
            assert!(contact.samples.len() >= model.parameters.min_points);
            for s in &contact.samples {
                let object_from_feature = object_from_link * s.feature_from_link.inverse();
                let p = nalgebra::Point3::from(object_from_feature.translation.vector);
                // The feature position in the link frame is the stored point.
                let local = object_from_link.inverse_transform_point(&p);
                assert!((local.coords - nalgebra::Vector3::from(s.point)).norm() < 1e-12);
                let prox = model
                    .hand
                    .link_proximity(
                        contact.link_index,
                        &poses[contact.link_index],
                        &(wrist.inverse() * p),
                    )
                    .expect("shape");
                assert!(prox.signed_distance < model.parameters.contact_distance);
                let d = prox.signed_distance;
                assert!((s.weight - (-model.parameters.finger_lambda * d * d).exp()).abs() < 1e-12);
            }
        }
    }
}
