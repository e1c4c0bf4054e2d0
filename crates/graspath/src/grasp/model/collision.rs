//! The collision term: penetration of cloud points into the hand's link shapes along the
//! approach and at the grasp (spec §4.5, with a grasp check added).
//!
//! Checks, as fractions `f` of the demonstrated approach (0 = grasp, 1 = pre-grasp), with the
//! shapes grown by `offset` and the term weighted by `weight`:
//! `(0.15, 0, 0.1)`, `(0.3, 0, 0.2)`, `(0.6, 5 mm, 0.5)`, `(1.0, 10 mm, 1.0)` — the spec's four
//! approach waypoints — and `(0, −grasp_clearance, 1.0)`: at the grasp, shapes shrunk by the
//! clearance, so touching is free and sinking in is not. The term is
//! `−Σ weight · Σ_points (exp(100·depth) − 1)`, depth in metres.
//!
//! Along the approach the wrist follows the demonstration rigidly attached to the new grasp
//! (`W_f = W ∘ interp(approach, f)`) and the hand joints are the demonstrated ones plus the
//! grasp's deviation from the demonstrated grasp, fading linearly to zero at the pre-grasp.

use super::file::ApproachWaypoint;
use crate::cloud::PointIndex;
use crate::geometry::interpolate_decoupled;
use crate::grasp::hand::Hand;
use nalgebra::{Isometry3, Point3};

/// `(fraction, offset, weight)` of each check; the grasp check's offset is replaced by
/// `−grasp_clearance`.
pub(super) const CHECKS: [(f64, f64, f64); 5] = [
    (0.0, 0.0, 1.0),
    (0.15, 0.0, 0.1),
    (0.3, 0.0, 0.2),
    (0.6, 0.005, 0.5),
    (1.0, 0.01, 1.0),
];

/// The cloud subset used by the collision term, indexed.
#[derive(Debug)]
pub(super) struct CollisionCloud {
    index: PointIndex,
}

impl CollisionCloud {
    /// Takes at most `max_points` points (every k-th, deterministic).
    pub(super) fn new(points: &[Point3<f64>], max_points: usize) -> Self {
        let stride = points.len().div_ceil(max_points.max(1)).max(1);
        let subset: Vec<Point3<f64>> = points.iter().step_by(stride).copied().collect();
        Self {
            index: PointIndex::new(&subset),
        }
    }

    /// `Σ_points (exp(100·depth) − 1)` for the hand at wrist pose `object_from_wrist` and
    /// joints `q`, shapes grown by `offset` (m).
    pub(super) fn penetration(
        &self,
        hand: &Hand,
        object_from_wrist: &Isometry3<f64>,
        q: &[f64],
        offset: f64,
        poses: &mut Vec<Isometry3<f64>>,
    ) -> f64 {
        hand.link_poses_into(q, poses);
        let mut total = 0.0;
        for (link, wrist_from_link) in hand.links.iter().zip(poses.iter()) {
            for s in &link.shapes {
                let object_from_shape = object_from_wrist * wrist_from_link * s.link_from_shape;
                let centre = Point3::from(object_from_shape.translation.vector);
                let radius = s.shape.bounding_radius() + offset.max(0.0);
                self.index.for_each_within(&centre, radius, |j, _| {
                    let local = object_from_shape.inverse_transform_point(&self.index.points()[j]);
                    // How deep the point lies inside the shape grown by `offset`.
                    let depth = (offset - s.shape.signed_distance(&local)).max(0.0);
                    if depth > 0.0 {
                        total += (100.0 * depth).exp() - 1.0;
                    }
                });
            }
        }
        total
    }
}

/// The wrist pose and hand joints at fraction `f` of the approach for a grasp
/// `(object_from_wrist, q)`; `demo_grasp` is the demonstrated grasp's joints.
pub(super) fn approach_state(
    approach: &[ApproachWaypoint],
    demo_grasp: &[f64],
    object_from_wrist: &Isometry3<f64>,
    q: &[f64],
    f: f64,
) -> (Isometry3<f64>, Vec<f64>) {
    // Waypoints from the grasp (index 0) back to the pre-grasp.
    let n = approach.len();
    let at = |k: usize| &approach[n - 1 - k];
    let (pose, joints) = if n < 2 {
        (at(0).grasp_from_wrist, at(0).hand_joints.clone())
    } else {
        let x = f.clamp(0.0, 1.0) * (n - 1) as f64;
        let k = (x.floor() as usize).min(n - 2);
        let s = x - k as f64;
        let (a, b) = (at(k), at(k + 1));
        let pose = interpolate_decoupled(&a.grasp_from_wrist, &b.grasp_from_wrist, s);
        let joints = a
            .hand_joints
            .iter()
            .zip(&b.hand_joints)
            .map(|(u, v)| u + (v - u) * s)
            .collect();
        (pose, joints)
    };
    let fade = 1.0 - f.clamp(0.0, 1.0);
    let joints = joints
        .iter()
        .zip(q.iter().zip(demo_grasp))
        .map(|(j, (c, g))| j + (c - g) * fade)
        .collect();
    (object_from_wrist * pose, joints)
}

/// The collision term (≤ 0) of a grasp.
pub(super) fn collision_term(
    cloud: &CollisionCloud,
    hand: &Hand,
    approach: &[ApproachWaypoint],
    demo_grasp: &[f64],
    grasp_clearance: f64,
    object_from_wrist: &Isometry3<f64>,
    q: &[f64],
) -> f64 {
    let mut poses = Vec::with_capacity(hand.links.len());
    let mut total = 0.0;
    for (k, (f, offset, weight)) in CHECKS.iter().enumerate() {
        let offset = if k == 0 { -grasp_clearance } else { *offset };
        let (wrist, mut joints) = approach_state(approach, demo_grasp, object_from_wrist, q, *f);
        hand.clamp(&mut joints);
        total += weight * cloud.penetration(hand, &wrist, &joints, offset, &mut poses);
    }
    -total
}
