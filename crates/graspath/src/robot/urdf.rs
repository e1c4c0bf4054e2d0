//! Loading chains from URDF files (through `urdf-rs`).
//!
//! Loading checks the file strictly: malformed XML is reported with its line and column, a
//! revolute or prismatic joint needs its `<limit>` (the URDF specification requires it), and
//! a link may be the child of one joint only. Collision geometry is read on request
//! ([`UrdfRobot::collisions`]), so `package://` mesh paths never slow down or stop chain
//! building. A file named `*.xacro` is expanded by the `xacro` program when it is installed, else
//! refused with the way to install it; xacro markup in a file with any other name is refused
//! (xacro runs code: see [`super::xacro`]).

use super::chain::{unit_axis, Chain};
use super::collision::{CollisionGeometry, CollisionShape, LinkCollisions, MeshRef, MeshResolver};
use super::error::{closest_names, RobotError};
use super::spec::{ChainSpec, JointKind, JointSpec, Mimic, MotionLimits, RigidBody};
use super::xacro::XacroOptions;
use crate::geometry::shape::Shape;
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use std::collections::{HashMap, HashSet};
use std::path::Path;

/// A parsed URDF robot from which chains are extracted.
#[derive(Debug, Clone)]
pub struct UrdfRobot {
    source_name: String,
    robot: urdf_rs::Robot,
    /// The links with an `<inertial>` element.
    inertial_links: HashSet<String>,
}

impl UrdfRobot {
    /// Reads and parses a URDF file. A file named `*.xacro` ([`super::xacro::is_xacro_path`])
    /// is first expanded by the `xacro` program with no arguments
    /// ([`super::xacro::expand_xacro`]; [`UrdfRobot::from_xacro`] passes arguments); xacro
    /// markup in a file with any other name is refused.
    pub fn from_file(path: &Path) -> Result<Self, RobotError> {
        if super::xacro::is_xacro_path(path) {
            return Self::from_xacro(path, &XacroOptions::default());
        }
        let source_name = path.display().to_string();
        let text = crate::input::read_to_string(path, crate::input::MAX_ROBOT_FILE_BYTES).map_err(
            |source| RobotError::Io {
                source_name: source_name.clone(),
                source,
            },
        )?;
        Self::from_xml(&text, &source_name)
    }

    /// Expands the xacro file `path` with `options` and parses the URDF it gives. The file is
    /// expanded whatever its name: call this only for files the user named as xacro files
    /// (xacro runs code).
    pub fn from_xacro(path: &Path, options: &XacroOptions) -> Result<Self, RobotError> {
        let source_name = path.display().to_string();
        // A missing file, or one that is not a regular file (a FIFO would block xacro), is
        // named as such, not as a xacro failure.
        let io = |source: std::io::Error| RobotError::Io {
            source_name: source_name.clone(),
            source,
        };
        let metadata = std::fs::metadata(path).map_err(io)?;
        if !metadata.is_file() {
            return Err(io(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not a regular file",
            )));
        }
        let expanded = super::xacro::expand_xacro(path, options)?;
        Self::from_xml(&expanded, &source_name)
    }

    /// Parses URDF text; `source_name` names it in errors. Text with xacro markup outside
    /// comments is refused ([`RobotError::XacroMarkup`]): it can only be expanded from a file
    /// named `*.xacro`.
    pub fn from_xml(text: &str, source_name: &str) -> Result<Self, RobotError> {
        if super::mjcf::is_mjcf(text) {
            return Err(RobotError::MjcfNotUrdf {
                source_name: source_name.to_string(),
            });
        }
        let scan = super::urdf_scan::scan(text, source_name)?;
        if let Some((line, markup)) = scan.xacro_markup {
            return Err(RobotError::XacroMarkup {
                source_name: source_name.to_string(),
                line,
                markup,
            });
        }
        if let Some(message) = scan.duplicate_name.clone() {
            return Err(RobotError::Parse {
                source_name: source_name.to_string(),
                message,
            });
        }
        let robot = urdf_rs::read_from_string(&scan.without_blank_textures(text)).map_err(|e| {
            // urdf-rs prefixes serde's messages with `custom: `, which says nothing to a reader.
            let message = e.to_string();
            RobotError::Parse {
                source_name: source_name.to_string(),
                message: message
                    .strip_prefix("custom: ")
                    .unwrap_or(&message)
                    .to_string(),
            }
        })?;
        if robot.links.is_empty() {
            return Err(RobotError::Parse {
                source_name: source_name.to_string(),
                message: "the robot has no <link> element (a URDF describes at least one link)"
                    .into(),
            });
        }
        let mut parent_of: HashMap<&str, &str> = HashMap::new();
        for joint in &robot.joints {
            if let Some(first) = parent_of.insert(&joint.child.link, &joint.name) {
                return Err(RobotError::TwoParents {
                    source_name: source_name.to_string(),
                    link: joint.child.link.clone(),
                    first: first.to_string(),
                    second: joint.name.clone(),
                });
            }
            let kind = match joint.joint_type {
                urdf_rs::JointType::Revolute => "revolute",
                urdf_rs::JointType::Prismatic => "prismatic",
                _ => continue,
            };
            if let Some(&(line, false)) = scan.joints.get(&joint.name) {
                return Err(RobotError::BadJoint {
                    source_name: source_name.to_string(),
                    joint: joint.name.clone(),
                    field: "limit",
                    message: format!(
                        "a {kind} joint needs a <limit lower=.. upper=.. effort=.. velocity=../> element (line {line}; the URDF specification requires it)"
                    ),
                });
            }
        }
        Ok(Self {
            source_name: source_name.to_string(),
            robot,
            inertial_links: scan.inertial_links,
        })
    }

    /// The robot's name attribute.
    pub fn name(&self) -> &str {
        &self.robot.name
    }

    /// The names of all links, in file order.
    pub fn link_names(&self) -> Vec<&str> {
        self.robot.links.iter().map(|l| l.name.as_str()).collect()
    }

    /// The file (or name) the robot was read from, for messages.
    pub fn source_name(&self) -> &str {
        &self.source_name
    }

    /// The collision elements of every link that has any, in file order. Primitives are
    /// checked (positive sizes, finite origins); meshes are resolved to files through
    /// `meshes` (an error names the link and every path tried) but not read.
    pub fn collisions(&self, meshes: &MeshResolver) -> Result<Vec<LinkCollisions>, RobotError> {
        let mut out = Vec::new();
        for link in &self.robot.links {
            if !link.collision.is_empty() {
                out.push(self.link_collisions(&link.name, meshes)?);
            }
        }
        Ok(out)
    }

    /// The collision elements of link `link` (see [`UrdfRobot::collisions`]).
    pub fn link_collisions(
        &self,
        link: &str,
        meshes: &MeshResolver,
    ) -> Result<LinkCollisions, RobotError> {
        self.require_link(link, "collision")?;
        let urdf_link = self
            .robot
            .links
            .iter()
            .find(|l| l.name == link)
            .ok_or_else(|| RobotError::UnknownLink {
                source_name: self.source_name.clone(),
                element: "link",
                link: link.to_string(),
                role: "collision",
                suggestions: Vec::new(),
            })?;
        let mut shapes = Vec::with_capacity(urdf_link.collision.len());
        for (index, collision) in urdf_link.collision.iter().enumerate() {
            let bad = |message: String| RobotError::BadCollision {
                source_name: self.source_name.clone(),
                link: link.to_string(),
                index,
                message,
            };
            let (xyz, rpy) = (collision.origin.xyz.0, collision.origin.rpy.0);
            if xyz.iter().chain(&rpy).any(|v| !v.is_finite()) {
                return Err(bad(format!(
                    "origin is not finite: xyz {xyz:?}, rpy {rpy:?}"
                )));
            }
            let shape = |r: Result<Shape, crate::geometry::shape::ShapeError>| {
                r.map(CollisionGeometry::Shape)
                    .map_err(|e| bad(e.to_string()))
            };
            let geometry = match &collision.geometry {
                urdf_rs::Geometry::Box { size } => shape(Shape::cuboid(size.0))?,
                urdf_rs::Geometry::Cylinder { radius, length } => {
                    shape(Shape::cylinder(*radius, *length))?
                }
                urdf_rs::Geometry::Capsule { radius, length } => {
                    shape(Shape::capsule(*radius, *length))?
                }
                urdf_rs::Geometry::Sphere { radius } => shape(Shape::sphere(*radius))?,
                urdf_rs::Geometry::Mesh { filename, scale } => {
                    let scale = scale.map(|v| v.0).unwrap_or([1.0; 3]);
                    if scale.iter().any(|v| !v.is_finite() || *v == 0.0) {
                        return Err(bad(format!(
                            "mesh scale must be finite and non-zero, got {scale:?}"
                        )));
                    }
                    CollisionGeometry::Mesh(MeshRef {
                        source_name: self.source_name.clone(),
                        link: link.to_string(),
                        uri: filename.clone(),
                        path: meshes.resolve(filename, &self.source_name, link)?,
                        scale,
                    })
                }
            };
            shapes.push(CollisionShape {
                name: collision.name.clone(),
                link_from_collision: Isometry3::from_parts(
                    Translation3::new(xyz[0], xyz[1], xyz[2]),
                    UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
                ),
                geometry,
            });
        }
        Ok(LinkCollisions {
            link: link.to_string(),
            shapes,
        })
    }

    /// The underlying parsed document (links with their geometry, joints, materials).
    pub fn document(&self) -> &urdf_rs::Robot {
        &self.robot
    }

    /// The chain from `base_link` down to `tip_link`, with an optional tool offset
    /// `tip_from_tool` appended.
    ///
    /// Each joint carries its `<limit effort velocity>` (and the ROS 2 `acceleration`
    /// extension) as [`MotionLimits`]; a value that is absent, zero or not finite is unknown.
    /// Each joint's `child_inertial` is the `<inertial>` of its child link together with every
    /// link hanging from that link off the chain (a camera, a hand's fingers: their joints
    /// locked at zero, as Pinocchio's reduced models lock them), in the child link frame.
    pub fn chain_spec(
        &self,
        base_link: &str,
        tip_link: &str,
        tip_from_tool: Option<Isometry3<f64>>,
    ) -> Result<ChainSpec, RobotError> {
        self.require_link(base_link, "base")?;
        self.require_link(tip_link, "tip")?;
        let parent_joint: HashMap<&str, &urdf_rs::Joint> = self
            .robot
            .joints
            .iter()
            .map(|j| (j.child.link.as_str(), j))
            .collect();
        let mut path = Vec::new();
        let mut link = tip_link;
        while link != base_link {
            match parent_joint.get(link) {
                Some(joint) => {
                    path.push(*joint);
                    link = joint.parent.link.as_str();
                    if path.len() > self.robot.joints.len() {
                        return Err(RobotError::Parse {
                            source_name: self.source_name.clone(),
                            message: format!("the joints above link '{tip_link}' form a loop"),
                        });
                    }
                }
                None => {
                    return Err(RobotError::TipNotBelowBase {
                        source_name: self.source_name.clone(),
                        element: "link",
                        base: base_link.to_string(),
                        tip: tip_link.to_string(),
                        root: link.to_string(),
                    })
                }
            }
        }
        path.reverse();
        let on_path: HashSet<&str> = std::iter::once(base_link)
            .chain(path.iter().map(|j| j.child.link.as_str()))
            .collect();
        let mut joints = Vec::with_capacity(path.len());
        for joint in path {
            let mut spec = self.joint_spec(joint)?;
            spec.child_inertial = self.attached_body(&joint.child.link, &on_path)?;
            joints.push(spec);
        }
        Ok(ChainSpec {
            source_name: self.source_name.clone(),
            base_link: base_link.to_string(),
            tip_link: tip_link.to_string(),
            joints,
            tip_from_tool,
        })
    }

    /// The flattened chain from `base_link` to `tip_link` (see [`UrdfRobot::chain_spec`]).
    pub fn chain(
        &self,
        base_link: &str,
        tip_link: &str,
        tip_from_tool: Option<Isometry3<f64>>,
    ) -> Result<Chain, RobotError> {
        Chain::from_spec(&self.chain_spec(base_link, tip_link, tip_from_tool)?)
    }

    /// The `<inertial>` of link `name` in its link frame, `None` when it has none.
    fn link_body(&self, link: &urdf_rs::Link) -> Result<Option<RigidBody>, RobotError> {
        if !self.inertial_links.contains(&link.name) {
            return Ok(None);
        }
        let inertial = &link.inertial;
        let (xyz, rpy) = (inertial.origin.xyz.0, inertial.origin.rpy.0);
        let i = &inertial.inertia;
        let body = RigidBody::new(
            inertial.mass.value,
            Vector3::zeros(),
            Matrix3::new(
                i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz,
            ),
        );
        let bad = || {
            RobotError::BadInertia {
            what: format!("{}: link '{}', <inertial>", self.source_name, link.name),
            message: format!(
                "mass {}, origin xyz {xyz:?} rpy {rpy:?}, inertia {:?}: the mass must be finite and non-negative, the rest finite, the diagonal non-negative",
                inertial.mass.value,
                [i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz]
            ),
        }
        };
        if xyz.iter().chain(&rpy).any(|v| !v.is_finite()) || !body.is_valid() {
            return Err(bad());
        }
        let link_from_inertial = Isometry3::from_parts(
            Translation3::new(xyz[0], xyz[1], xyz[2]),
            UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
        );
        Ok(Some(body.transformed(&link_from_inertial)))
    }

    /// The mass properties of link `link` and of every link below it that is not in
    /// `on_path` (joints locked at zero), in `link`'s frame; `None` when none of them has an
    /// `<inertial>`.
    fn attached_body(
        &self,
        link: &str,
        on_path: &HashSet<&str>,
    ) -> Result<Option<RigidBody>, RobotError> {
        let mut total: Option<RigidBody> = None;
        // (link, link_from_it), depth first; a link has one parent, so each is met once.
        let mut stack = vec![(link, Isometry3::<f64>::identity())];
        let mut visited = 0;
        while let Some((name, top_from_link)) = stack.pop() {
            visited += 1;
            if visited > self.robot.links.len() {
                break;
            }
            if let Some(urdf_link) = self.robot.links.iter().find(|l| l.name == name) {
                if let Some(body) = self.link_body(urdf_link)? {
                    let body = body.transformed(&top_from_link);
                    total = Some(total.map_or(body, |t| t.combined(&body)));
                }
            }
            for joint in self.robot.joints.iter().filter(|j| j.parent.link == name) {
                let child = joint.child.link.as_str();
                if on_path.contains(child) {
                    continue;
                }
                let (xyz, rpy) = (joint.origin.xyz.0, joint.origin.rpy.0);
                if xyz.iter().chain(&rpy).any(|v| !v.is_finite()) {
                    return Err(RobotError::BadJoint {
                        source_name: self.source_name.clone(),
                        joint: joint.name.clone(),
                        field: "origin",
                        message: format!("not finite: xyz {xyz:?}, rpy {rpy:?}"),
                    });
                }
                let parent_from_child = Isometry3::from_parts(
                    Translation3::new(xyz[0], xyz[1], xyz[2]),
                    UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
                );
                stack.push((child, top_from_link * parent_from_child));
            }
        }
        Ok(total)
    }

    fn require_link(&self, name: &str, role: &'static str) -> Result<(), RobotError> {
        if self.robot.links.iter().any(|l| l.name == name) {
            return Ok(());
        }
        Err(RobotError::UnknownLink {
            source_name: self.source_name.clone(),
            element: "link",
            link: name.to_string(),
            role,
            suggestions: closest_names(name, self.link_names()),
        })
    }

    fn joint_spec(&self, joint: &urdf_rs::Joint) -> Result<JointSpec, RobotError> {
        let bad = |field: &'static str, message: String| RobotError::BadJoint {
            source_name: self.source_name.clone(),
            joint: joint.name.clone(),
            field,
            message,
        };
        let xyz = joint.origin.xyz.0;
        let rpy = joint.origin.rpy.0;
        if xyz.iter().any(|v| !v.is_finite()) {
            return Err(bad("origin/@xyz", format!("not finite: {xyz:?}")));
        }
        if rpy.iter().any(|v| !v.is_finite()) {
            return Err(bad("origin/@rpy", format!("not finite: {rpy:?}")));
        }
        let parent_from_joint = Isometry3::from_parts(
            Translation3::new(xyz[0], xyz[1], xyz[2]),
            UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
        );
        let kind = match joint.joint_type {
            urdf_rs::JointType::Revolute => JointKind::Revolute,
            urdf_rs::JointType::Continuous => JointKind::Continuous,
            urdf_rs::JointType::Prismatic => JointKind::Prismatic,
            urdf_rs::JointType::Fixed => JointKind::Fixed,
            ref other => {
                return Err(bad(
                    "@type",
                    format!("{other:?} joints are not supported in a serial chain"),
                ))
            }
        };
        let raw_axis = Vector3::from(joint.axis.xyz.0);
        let axis = if kind == JointKind::Fixed {
            unit_axis(&raw_axis).unwrap_or_else(Vector3::x)
        } else {
            unit_axis(&raw_axis).ok_or_else(|| {
                bad(
                    "axis/@xyz",
                    format!(
                        "must be a non-zero finite vector, got {:?}",
                        raw_axis.as_slice()
                    ),
                )
            })?
        };
        let (lower, upper) = match kind {
            JointKind::Continuous => (f64::NEG_INFINITY, f64::INFINITY),
            JointKind::Fixed => (0.0, 0.0),
            _ => {
                let (lo, hi) = (joint.limit.lower, joint.limit.upper);
                if lo.is_nan() || hi.is_nan() || lo > hi {
                    return Err(bad(
                        "limit",
                        format!("lower {lo} and upper {hi} are not an interval"),
                    ));
                }
                (lo, hi)
            }
        };
        let mimic = joint
            .mimic
            .as_ref()
            .map(|m| {
                let multiplier = m.multiplier.unwrap_or(1.0);
                let offset = m.offset.unwrap_or(0.0);
                if !multiplier.is_finite() || !offset.is_finite() {
                    return Err(bad("mimic", "multiplier and offset must be finite".into()));
                }
                Ok(Mimic {
                    leader: m.joint.clone(),
                    multiplier,
                    offset,
                })
            })
            .transpose()?;
        // A limit of 0 (or `inf`) is none given; a negative or NaN one is a mistake, never
        // read as "unlimited".
        let known = |what: &'static str, v: f64| {
            if v < 0.0 || v.is_nan() {
                Err(bad(
                    "limit",
                    format!("<limit {what}> is {v}: a limit is a magnitude, 0 or more"),
                ))
            } else {
                Ok((v.is_finite() && v > 0.0).then_some(v))
            }
        };
        let limits = if kind == JointKind::Fixed {
            MotionLimits::default()
        } else {
            MotionLimits {
                velocity: known("velocity", joint.limit.velocity)?,
                effort: known("effort", joint.limit.effort)?,
                acceleration: known("acceleration", joint.limit.acceleration)?,
            }
        };
        Ok(JointSpec {
            name: joint.name.clone(),
            child_link: joint.child.link.clone(),
            kind,
            parent_from_joint,
            axis,
            lower,
            upper,
            mimic,
            limits,
            child_inertial: None,
        })
    }
}

/// Loads the chain `base_link → tip_link` from a URDF file.
pub fn load_urdf_chain(
    path: &Path,
    base_link: &str,
    tip_link: &str,
    tip_from_tool: Option<Isometry3<f64>>,
) -> Result<Chain, RobotError> {
    UrdfRobot::from_file(path)?.chain(base_link, tip_link, tip_from_tool)
}

/// Parses URDF text and extracts one chain; `source_name` names the text in errors.
pub fn parse_urdf_chain(
    text: &str,
    source_name: &str,
    base_link: &str,
    tip_link: &str,
) -> Result<Chain, RobotError> {
    UrdfRobot::from_xml(text, source_name)?.chain(base_link, tip_link, None)
}
