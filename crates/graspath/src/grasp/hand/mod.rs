//! Hand models: a tree of links below the **wrist frame**, each with collision shapes of the
//! one shape vocabulary ([`crate::geometry::shape::Shape`]), moved by a few independent hand joints (mimic joints follow them).
//!
//! Frames: every link pose is `wrist_from_link` (metres). The wrist frame is the frame whose
//! pose the grasp model generates (`object_from_wrist`); for the built-in Baxter gripper it is
//! the tip frame `{arm}_gripper` of the built-in Baxter chain (see [`baxter_electric_gripper`]).

mod baxter;
mod stock;
mod urdf;

pub use baxter::{baxter_electric_gripper, BAXTER_GRIPPER_NAME};
pub use stock::StockGripper;
pub use urdf::{hand_from_robot, hand_from_robot_with_wrist, hand_from_urdf, HandError};

use crate::geometry::shape::{Proximity, Shape};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

/// How a link moves relative to its parent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HandJointKind {
    /// No motion.
    Fixed,
    /// Rotation about the axis (rad).
    Revolute,
    /// Translation along the axis (m).
    Prismatic,
}

/// An independent hand joint: one entry of the hand configuration vector.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HandJoint {
    /// Joint name.
    pub name: String,
    /// Lower limit (rad or m).
    pub lower: f64,
    /// Upper limit (rad or m).
    pub upper: f64,
    /// Kernel width of the hand-configuration model and of annealing steps (rad or m).
    pub sigma: f64,
}

/// The joint that places a link on its parent: `parent_from_link = parent_from_joint ·
/// motion(axis, multiplier · q[joint] + offset)`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LinkJoint {
    /// Fixed, revolute or prismatic.
    pub kind: HandJointKind,
    /// The joint frame in the parent link frame (m).
    pub parent_from_joint: Isometry3<f64>,
    /// Unit axis in the joint frame.
    pub axis: Vector3<f64>,
    /// Index of the driving entry of the hand configuration (ignored for fixed joints).
    pub joint: usize,
    /// Factor applied to the driving value.
    pub multiplier: f64,
    /// Offset added (rad or m).
    pub offset: f64,
}

/// A collision shape placed in its link frame.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LinkShape {
    /// The shape's frame in the link frame (m).
    pub link_from_shape: Isometry3<f64>,
    /// The solid, in its own frame (file spelling of [`crate::geometry::shape`]).
    pub shape: Shape,
}

/// One link of a hand.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HandLink {
    /// Link name.
    pub name: String,
    /// The parent link's index (`None` for the root, placed in the wrist frame by its joint).
    pub parent: Option<usize>,
    /// How the link hangs on its parent (the root's is fixed: the identity, or `wrist_from_root`
    /// when the wrist frame is a link fixed below the root, [`hand_from_robot_with_wrist`]).
    pub joint: LinkJoint,
    /// Collision shapes (may be empty: such a link never gets a contact model).
    pub shapes: Vec<LinkShape>,
}

/// A hand: links in parent-before-child order (link 0 is the root, at the wrist frame or fixed
/// in it) and the
/// independent joints that move them.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Hand {
    /// A name for messages and files.
    pub name: String,
    /// The independent joints, in the order of a hand configuration vector.
    pub joints: Vec<HandJoint>,
    /// The links, parents first.
    pub links: Vec<HandLink>,
}

impl LinkJoint {
    /// The fixed identity joint of a root link.
    pub fn root() -> Self {
        Self::fixed(Isometry3::identity())
    }

    /// A fixed joint at `parent_from_joint`.
    pub fn fixed(parent_from_joint: Isometry3<f64>) -> Self {
        Self {
            kind: HandJointKind::Fixed,
            parent_from_joint,
            axis: Vector3::x(),
            joint: 0,
            multiplier: 0.0,
            offset: 0.0,
        }
    }

    /// `parent_from_link` at hand configuration `q`.
    #[inline]
    pub fn parent_from_link(&self, q: &[f64]) -> Isometry3<f64> {
        let value = || self.multiplier * q.get(self.joint).copied().unwrap_or(0.0) + self.offset;
        match self.kind {
            HandJointKind::Fixed => self.parent_from_joint,
            HandJointKind::Revolute => {
                self.parent_from_joint
                    * Isometry3::from_parts(
                        Translation3::identity(),
                        UnitQuaternion::from_scaled_axis(self.axis * value()),
                    )
            }
            HandJointKind::Prismatic => {
                self.parent_from_joint * Translation3::from(self.axis * value())
            }
        }
    }
}

impl Hand {
    /// The number of hand joints (the length of a configuration).
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// The index of the link named `name`.
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }

    /// Writes `wrist_from_link` of every link at configuration `q` into `out` (resized to the
    /// link count; no allocation once it has that size).
    pub fn link_poses_into(&self, q: &[f64], out: &mut Vec<Isometry3<f64>>) {
        out.resize(self.links.len(), Isometry3::identity());
        for (i, link) in self.links.iter().enumerate() {
            let local = link.joint.parent_from_link(q);
            out[i] = match link.parent {
                Some(parent) => out[parent] * local,
                None => local,
            };
        }
    }

    /// `wrist_from_link` of every link at `q`.
    pub fn link_poses(&self, q: &[f64]) -> Vec<Isometry3<f64>> {
        let mut out = Vec::new();
        self.link_poses_into(q, &mut out);
        out
    }

    /// `q` clamped to the joint limits.
    pub fn clamp(&self, q: &mut [f64]) {
        for (v, j) in q.iter_mut().zip(&self.joints) {
            *v = v.clamp(j.lower, j.upper);
        }
    }

    /// The signed distance (m) from `p` (wrist frame) to link `link` (minimum over its shapes)
    /// and the closest surface point (wrist frame), given the link poses; `None` for a link
    /// without shapes.
    pub fn link_proximity(
        &self,
        link: usize,
        wrist_from_link: &Isometry3<f64>,
        p: &Point3<f64>,
    ) -> Option<Proximity> {
        let mut best: Option<Proximity> = None;
        for s in &self.links[link].shapes {
            let wrist_from_shape = wrist_from_link * s.link_from_shape;
            let local = wrist_from_shape.inverse_transform_point(p);
            let prox = s.shape.proximity(&local);
            if best.is_none_or(|b| prox.signed_distance < b.signed_distance) {
                best = Some(Proximity {
                    signed_distance: prox.signed_distance,
                    closest: wrist_from_shape * prox.closest,
                });
            }
        }
        best
    }
}

/// A parallel-jaw hand: the root link `palm` with the shapes `palm` (wrist frame), and the
/// fingers `l_finger` (on `+y`) and `r_finger` (on `−y`), each a box `[width, thickness,
/// length]` whose joint frame sits at `z = finger_z` and slides along `±y` by half the one
/// hand joint `opening` (m, in `[lower, upper]`, σ = 1 mm), so that the fingers' inner faces
/// lie at `y = ±opening/2`.
fn parallel_jaw_hand(
    name: &str,
    palm: Vec<LinkShape>,
    finger_z: f64,
    [width, thickness, length]: [f64; 3],
    (lower, upper): (f64, f64),
) -> Hand {
    let finger = |name: &str, side: f64| HandLink {
        name: name.to_string(),
        parent: Some(0),
        joint: LinkJoint {
            kind: HandJointKind::Prismatic,
            parent_from_joint: Isometry3::translation(0.0, 0.0, finger_z),
            axis: Vector3::new(0.0, side, 0.0),
            joint: 0,
            multiplier: 0.5,
            offset: 0.0,
        },
        shapes: vec![LinkShape {
            link_from_shape: Isometry3::translation(0.0, side * thickness / 2.0, 0.0),
            shape: Shape::cuboid([width, thickness, length]).expect("built-in sizes are positive"),
        }],
    };
    Hand {
        name: name.to_string(),
        joints: vec![HandJoint {
            name: "opening".into(),
            lower,
            upper,
            sigma: 0.001,
        }],
        links: vec![
            HandLink {
                name: "palm".into(),
                parent: None,
                joint: LinkJoint::root(),
                shapes: palm,
            },
            finger("l_finger", 1.0),
            finger("r_finger", -1.0),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn revolute_and_prismatic_links_move_as_urdf_says() {
        let hand = Hand {
            name: "test".into(),
            joints: vec![HandJoint {
                name: "j".into(),
                lower: -1.0,
                upper: 1.0,
                sigma: 0.01,
            }],
            links: vec![
                HandLink {
                    name: "root".into(),
                    parent: None,
                    joint: LinkJoint::root(),
                    shapes: vec![],
                },
                HandLink {
                    name: "a".into(),
                    parent: Some(0),
                    joint: LinkJoint {
                        kind: HandJointKind::Revolute,
                        parent_from_joint: Isometry3::translation(0.1, 0.0, 0.0),
                        axis: Vector3::z(),
                        joint: 0,
                        multiplier: 1.0,
                        offset: 0.0,
                    },
                    shapes: vec![],
                },
                HandLink {
                    name: "b".into(),
                    parent: Some(1),
                    joint: LinkJoint {
                        kind: HandJointKind::Prismatic,
                        parent_from_joint: Isometry3::translation(0.1, 0.0, 0.0),
                        axis: Vector3::x(),
                        joint: 0,
                        multiplier: 0.5,
                        offset: 0.0,
                    },
                    shapes: vec![],
                },
            ],
        };
        let q = std::f64::consts::FRAC_PI_2;
        let poses = hand.link_poses(&[q]);
        // a at (0.1, 0, 0) turned 90° about z; b 0.1 + q/2 further along a's x (= wrist y).
        let b = poses[2].translation.vector;
        assert!(
            (b - Vector3::new(0.1, 0.1 + q / 2.0, 0.0)).norm() < 1e-12,
            "{b}"
        );
    }
}
