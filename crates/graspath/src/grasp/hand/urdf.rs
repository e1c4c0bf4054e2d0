//! Hands from URDF: every link below a chosen root link (the wrist frame), with its collision
//! boxes, spheres, cylinders, capsules or meshes (OBJ / STL; a link's solid is the convex hull
//! of the mesh's vertices), and the joints that move them.

use super::{Hand, HandJoint, HandJointKind, HandLink, LinkJoint, LinkShape};
use crate::cloud::read_mesh;
use crate::geometry::shape::{ConvexMesh, Shape, ShapeError};
use crate::robot::{MeshResolver, RobotError, RobotModel, UrdfRobot};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use std::collections::HashMap;

/// Default kernel width of a revolute hand joint (rad; ≈ 0.9°).
pub(super) const REVOLUTE_SIGMA: f64 = 0.0157;
/// Default kernel width of a prismatic hand joint (m).
pub(super) const PRISMATIC_SIGMA: f64 = 0.001;

/// An error from building a hand out of a URDF file.
#[derive(Debug, thiserror::Error)]
pub enum HandError {
    /// The URDF could not be loaded.
    #[error(transparent)]
    Robot(#[from] RobotError),
    /// The root link does not exist.
    #[error("{source_name}: no link named '{link}' to use as the hand root (links: {links})")]
    UnknownRoot {
        /// The file.
        source_name: String,
        /// The requested root.
        link: String,
        /// The links present.
        links: String,
    },
    /// A link's collision geometry cannot be used.
    #[error("{source_name}: link '{link}', collision geometry: {message}")]
    BadGeometry {
        /// The file.
        source_name: String,
        /// The link.
        link: String,
        /// What is wrong.
        message: String,
    },
    /// A link's collision shape has sizes or a mesh that cannot be used; the shape's error is
    /// the source.
    #[error("{source_name}: link '{link}', collision geometry")]
    BadShape {
        /// The file.
        source_name: String,
        /// The link.
        link: String,
        /// What is wrong with the shape.
        source: ShapeError,
    },
    /// A link's collision mesh cannot be read; the mesh file's error is the source.
    #[error("{source_name}: link '{link}', collision geometry")]
    Mesh {
        /// The file.
        source_name: String,
        /// The link.
        link: String,
        /// Why the mesh cannot be read: the [`CloudError`](crate::cloud::CloudError) that names the mesh file (boxed, so
        /// that the error stays small).
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// The wrist link is not below the root through fixed joints only.
    #[error("{source_name}: wrist link '{link}': {message}")]
    BadWrist {
        /// The file.
        source_name: String,
        /// The requested wrist link.
        link: String,
        /// What is wrong.
        message: String,
    },
    /// A joint below the root cannot be used.
    #[error("{source_name}: joint '{joint}', field '{field}': {message}")]
    BadJoint {
        /// The file.
        source_name: String,
        /// The joint.
        joint: String,
        /// The URDF field.
        field: &'static str,
        /// What is wrong.
        message: String,
    },
}

impl crate::fault::Classify for HandError {
    /// A robot, shape or mesh error's own kind (a missing mesh file is
    /// [`ErrorKind`](crate::fault::ErrorKind)`::File`); everything else is
    /// [`ErrorKind`](crate::fault::ErrorKind)`::Content`.
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        match self {
            Self::Robot(e) => e.kind(),
            Self::BadShape { .. } | Self::Mesh { .. } => None,
            _ => Some(crate::fault::ErrorKind::Content),
        }
    }

    fn file(&self) -> Option<&str> {
        match self {
            Self::Robot(e) => e.file(),
            Self::UnknownRoot { source_name, .. }
            | Self::BadGeometry { source_name, .. }
            | Self::BadShape { source_name, .. }
            | Self::Mesh { source_name, .. }
            | Self::BadWrist { source_name, .. }
            | Self::BadJoint { source_name, .. } => Some(source_name),
        }
    }

    fn field(&self) -> Option<&str> {
        match self {
            Self::Robot(e) => e.field(),
            Self::BadJoint { field, .. } => Some(field),
            _ => None,
        }
    }
}

fn pose(xyz: [f64; 3], rpy: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

/// Builds a hand from a loaded robot model (see [`crate::robot::RobotSource`]): its URDF, with
/// mesh URIs resolved by the model's search paths. A built-in robot has no hand links: use
/// the built-in gripper ([`super::baxter_electric_gripper`]) instead.
pub fn hand_from_robot(model: &RobotModel, root_link: &str) -> Result<Hand, HandError> {
    match (model.urdf(), model.mesh_resolver()) {
        (Some(robot), Some(meshes)) => hand_from_urdf(robot, root_link, meshes),
        _ => Err(HandError::UnknownRoot {
            source_name: model.source_name().to_string(),
            link: root_link.to_string(),
            links: "none: a built-in robot model has no hand links; give a URDF hand".into(),
        }),
    }
}

/// Builds a hand from a loaded robot model like [`hand_from_robot`], with the links below
/// `root_link` but every pose in the frame of `wrist_link`: a link fixed below the root (the
/// Panda's `panda_hand_tcp` below `panda_hand`), so that a model trained with this hand
/// generates `object_from_wrist` in the frame a robot chain ends at (its tool frame). The root's
/// joint becomes the fixed `wrist_from_root`; the wrist link must hang on the root through
/// fixed joints only.
pub fn hand_from_robot_with_wrist(
    model: &RobotModel,
    root_link: &str,
    wrist_link: &str,
) -> Result<Hand, HandError> {
    let mut hand = hand_from_robot(model, root_link)?;
    let fail = |message: String| HandError::BadWrist {
        source_name: model.source_name().to_string(),
        link: wrist_link.to_string(),
        message,
    };
    let Some(wrist) = hand.link_index(wrist_link) else {
        return Err(fail(format!(
            "not a link below the root '{root_link}' (links: {})",
            hand.links
                .iter()
                .map(|l| l.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    };
    let mut k = wrist;
    while let Some(parent) = hand.links[k].parent {
        if hand.links[k].joint.kind != HandJointKind::Fixed {
            return Err(fail(format!(
                "link '{}' between it and the root '{root_link}' moves with a hand joint: the \
                 wrist frame must be fixed to the root",
                hand.links[k].name
            )));
        }
        k = parent;
    }
    // With the root at the identity, link poses are root_from_link; fixed joints ignore q.
    let root_from_wrist = hand.link_poses(&vec![0.0; hand.dof()])[wrist];
    hand.links[0].joint = LinkJoint::fixed(root_from_wrist.inverse());
    Ok(hand)
}

/// Builds a hand from a parsed URDF: `root_link`'s frame becomes the wrist frame and every link
/// below it a hand link. Non-fixed joints without `<mimic>` become hand joints (continuous
/// joints get limits ±π); mimic joints follow their leader. Mesh URIs (`package://`,
/// `model://`, paths relative to the URDF) are resolved through `meshes`, as for robot links.
pub fn hand_from_urdf(
    robot: &UrdfRobot,
    root_link: &str,
    meshes: &MeshResolver,
) -> Result<Hand, HandError> {
    let doc = robot.document();
    let source_name = robot.source_name().to_string();
    if !doc.links.iter().any(|l| l.name == root_link) {
        return Err(HandError::UnknownRoot {
            source_name,
            link: root_link.to_string(),
            links: robot.link_names().join(", "),
        });
    }
    // Breadth-first from the root: parents before children.
    let mut order: Vec<(String, Option<(usize, &urdf_rs::Joint)>)> =
        vec![(root_link.to_string(), None)];
    let mut k = 0;
    while k < order.len() {
        let name = order[k].0.clone();
        for joint in doc.joints.iter().filter(|j| j.parent.link == name) {
            if order.iter().any(|(n, _)| *n == joint.child.link) {
                return Err(HandError::BadJoint {
                    source_name,
                    joint: joint.name.clone(),
                    field: "child",
                    message: "the links below the root form a loop".into(),
                });
            }
            order.push((joint.child.link.clone(), Some((k, joint))));
        }
        k += 1;
    }
    let bad = |joint: &urdf_rs::Joint, field: &'static str, message: String| HandError::BadJoint {
        source_name: source_name.clone(),
        joint: joint.name.clone(),
        field,
        message,
    };
    let mut joints = Vec::new();
    let mut joint_index = HashMap::new();
    for (_, parent) in &order {
        let Some((_, joint)) = parent else { continue };
        let (lower, upper, sigma) = match joint.joint_type {
            urdf_rs::JointType::Revolute => (joint.limit.lower, joint.limit.upper, REVOLUTE_SIGMA),
            urdf_rs::JointType::Continuous => {
                (-std::f64::consts::PI, std::f64::consts::PI, REVOLUTE_SIGMA)
            }
            urdf_rs::JointType::Prismatic => {
                (joint.limit.lower, joint.limit.upper, PRISMATIC_SIGMA)
            }
            urdf_rs::JointType::Fixed => continue,
            ref other => {
                return Err(bad(
                    joint,
                    "@type",
                    format!("{other:?} joints are not supported in a hand"),
                ))
            }
        };
        if joint.mimic.is_some() {
            continue;
        }
        if !(lower.is_finite() && upper.is_finite() && lower <= upper) {
            return Err(bad(
                joint,
                "limit",
                format!("lower {lower} and upper {upper} are not an interval"),
            ));
        }
        joint_index.insert(joint.name.clone(), joints.len());
        joints.push(HandJoint {
            name: joint.name.clone(),
            lower,
            upper,
            sigma,
        });
    }
    let mut links = Vec::with_capacity(order.len());
    for (name, parent) in &order {
        let link_joint = match parent {
            None => LinkJoint::root(),
            Some((_, joint)) => {
                let origin = pose(joint.origin.xyz.0, joint.origin.rpy.0);
                if origin.translation.vector.iter().any(|v| !v.is_finite()) {
                    return Err(bad(joint, "origin", "not finite".into()));
                }
                let kind = match joint.joint_type {
                    urdf_rs::JointType::Fixed => HandJointKind::Fixed,
                    urdf_rs::JointType::Prismatic => HandJointKind::Prismatic,
                    _ => HandJointKind::Revolute,
                };
                let (driver, multiplier, offset) = match &joint.mimic {
                    Some(m) => (
                        m.joint.clone(),
                        m.multiplier.unwrap_or(1.0),
                        m.offset.unwrap_or(0.0),
                    ),
                    None => (joint.name.clone(), 1.0, 0.0),
                };
                let index = if kind == HandJointKind::Fixed {
                    0
                } else {
                    *joint_index.get(&driver).ok_or_else(|| {
                        bad(joint, "mimic/@joint", format!("mimics '{driver}', which is not an independent joint below the root"))
                    })?
                };
                let axis = Vector3::from(joint.axis.xyz.0);
                let axis = if kind == HandJointKind::Fixed {
                    Vector3::x()
                } else if axis.norm() > 1e-9 && axis.iter().all(|v| v.is_finite()) {
                    axis.normalize()
                } else {
                    return Err(bad(
                        joint,
                        "axis/@xyz",
                        "must be a non-zero finite vector".into(),
                    ));
                };
                LinkJoint {
                    kind,
                    parent_from_joint: origin,
                    axis,
                    joint: index,
                    multiplier,
                    offset,
                }
            }
        };
        let link =
            doc.links
                .iter()
                .find(|l| l.name == *name)
                .ok_or_else(|| HandError::BadGeometry {
                    source_name: source_name.clone(),
                    link: name.clone(),
                    message: "the link is named by a joint but not defined".into(),
                })?;
        let mut shapes = Vec::new();
        for collision in &link.collision {
            let checked = |r: Result<Shape, ShapeError>| {
                r.map_err(|source| HandError::BadShape {
                    source_name: source_name.clone(),
                    link: name.clone(),
                    source,
                })
            };
            let shape = match &collision.geometry {
                urdf_rs::Geometry::Box { size } => checked(Shape::cuboid(size.0))?,
                urdf_rs::Geometry::Sphere { radius } => checked(Shape::sphere(*radius))?,
                urdf_rs::Geometry::Cylinder { radius, length } => {
                    checked(Shape::cylinder(*radius, *length))?
                }
                urdf_rs::Geometry::Capsule { radius, length } => {
                    checked(Shape::capsule(*radius, *length))?
                }
                urdf_rs::Geometry::Mesh { filename, scale } => {
                    let path = meshes.resolve(filename, robot.source_name(), name)?;
                    let mesh = read_mesh(&path).map_err(|e| HandError::Mesh {
                        source_name: source_name.clone(),
                        link: name.clone(),
                        source: Box::new(e),
                    })?;
                    let s = scale.as_ref().map(|v| v.0).unwrap_or([1.0; 3]);
                    let points = mesh
                        .vertices
                        .iter()
                        .map(|v| Point3::new(v.x * s[0], v.y * s[1], v.z * s[2]))
                        .collect();
                    // The link's solid is the hull of the mesh's vertices.
                    checked(ConvexMesh::new(points).map(Shape::ConvexMesh))?
                }
            };
            shapes.push(LinkShape {
                link_from_shape: pose(collision.origin.xyz.0, collision.origin.rpy.0),
                shape,
            });
        }
        links.push(HandLink {
            name: name.clone(),
            parent: parent.map(|(p, _)| p),
            joint: link_joint,
            shapes,
        });
    }
    Ok(Hand {
        name: robot.name().to_string(),
        joints,
        links,
    })
}
