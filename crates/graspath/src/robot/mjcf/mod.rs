//! MuJoCo MJCF files (`<mujoco>` XML) as a robot source: bodies become links, `hinge` and
//! `slide` joints become revolute and prismatic joints, colliding geoms become the links'
//! collision shapes.
//!
//! **Frames and units.** A link is an MJCF body and has the body's name (the world body is
//! `world`; an unnamed body is `unnamed_body_K`, K its index in file order, the world being 0).
//! Its frame is the body frame: `pos` (m) and one of `quat` (`w x y z`), `euler` (in the
//! compiler's `eulerseq`, default `xyz` about the moving axes), `axisangle`, `xyaxes` or
//! `zaxis`, relative to the parent body. Angles (`euler`, `axisangle`, a hinge's `range` and
//! `ref`) are in **degrees unless `<compiler angle="radian">`** — MuJoCo's default. Lengths
//! are metres. A joint's `pos` is its anchor and `axis` its direction, both in the body frame:
//! a hinge turns the body about the line through `pos` along `axis`
//! (`parent_from_body(q) = parent_from_body · T(pos) · R(axis, q − ref) · T(−pos)`), a slide
//! moves it along `axis` by `q − ref`; several joints of one body act in order, each in the
//! frame left by the previous one (as MuJoCo composes them). The joint value `q` is MuJoCo's
//! `qpos`.
//!
//! **Chains** are named like URDF ones, by base and tip body ([`MjcfRobot::chain`]); the base
//! body's own joints are not part of its chain, so a floating base (`<freejoint/>`) is simply
//! left out by starting the chain at that body. A `ball` or `free` joint between base and tip,
//! or a `slide` joint without a range, is an error naming the file, the body and the joint. A
//! body with several joints gets one link per joint in the chain (`BODY@JOINT`) before its own.
//!
//! **Defaults**: `<default>` classes (nested ones inherit), chosen by an element's `class` or
//! the nearest enclosing `childclass`, supply `joint`, `geom`, `mesh` and actuator attributes.
//! An orientation is one setting, as in MuJoCo's compiler: a geom's own `quat`, `axisangle`,
//! `euler`, `xyaxes` or `zaxis` replaces the one its class gives, whatever the kinds (and a
//! nested class's replaces its parent's); two on one element are an error.
//!
//! **Names**: as MuJoCo's compiler, a body, joint (`freejoint` included), geom, mesh or
//! default class name used twice is an error naming the line of both uses.
//! `limited="auto"` (the default) with `<compiler autolimits="true">` (the default) limits a
//! joint that has a `range`; `limited="true"` without a range is an error.
//!
//! **Collision shapes** ([`MjcfRobot::collisions`]): `box` (`size` = half-sizes), `sphere`,
//! `capsule` and `cylinder` (`size` = radius, half-length; or radius and `fromto`, two points
//! the geom's `z` axis joins), and `mesh` geoms (`<asset><mesh file scale>`; the file is looked
//! up relative to `<compiler meshdir>` (else `assetdir`), itself relative to the model file's
//! folder; OBJ and STL files can be read). Geoms with `contype="0" conaffinity="0"` never
//! collide in MuJoCo (visual geoms) and are left out. `plane`, `hfield`, `ellipsoid` and `sdf`
//! geoms, meshes given by inline vertices and primitives fitted to a mesh are skipped and listed
//! by [`MjcfRobot::skipped_geoms`] with the reason.
//!
//! **Mass properties and limits** (for the dynamics): a body's `<inertial>` (in its body
//! frame), with the bodies hanging from a chain body off the chain folded in at their written
//! pose (MuJoCo's `qpos0`); a joint's effort limit from its `actuatorfrcrange` or its
//! actuators' `forcerange` times `gear` (the smallest wins); MJCF has no velocity limits.
//! Where a body has no `<inertial>`, MuJoCo's compiler would infer one from its geoms
//! (`inertiafromgeom="auto"`); this reader does not: the body has no inertial data, and
//! asking a chain through it for dynamics is an error ([`RobotError::NoInertia`]) that says
//! so, never a silent zero mass. With `<compiler inertiafromgeom="true">` every `<inertial>`
//! is ignored, as MuJoCo ignores them, and the same error follows.
//!
//! Not supported (an error names the element): `<include>`, `<replicate>`, `<attach>`,
//! `<composite>`, `<flexcomp>`, joints inside `<frame>`. Sites, cameras and lights are
//! ignored.
//!
//! Files: `dom.rs` (the element tree, via quick-xml), `parse.rs` (compiler, defaults, bodies,
//! joints), `defaults.rs` (default classes' storage), `values.rs` (numbers, angles, orientations), `geom.rs` (collision shapes),
//! `inertia.rs` (inertials, actuator force ranges), this file
//! (the model's chains and collisions).

mod defaults;
mod dom;
mod geom;
mod inertia;
mod parse;
mod values;

use super::chain::Chain;
use super::collision::{CollisionGeometry, CollisionShape, LinkCollisions, MeshRef, MeshResolver};
use super::error::closest_names;
use super::error::RobotError;
use super::spec::{ChainSpec, JointKind, JointSpec, MotionLimits, RigidBody};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use parse::{GeomKind, JointType, Model};
use std::path::{Path, PathBuf};

/// Where a chain joint comes from: the index of the body it carries, and the index of its
/// `<joint>` in that body (`None` for the fixed joint that places the body).
type JointOrigin = (usize, Option<usize>);

/// A geom that did not become a collision shape, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SkippedGeom {
    /// The body that carries it.
    pub body: String,
    /// The geom's name, if any.
    pub geom: Option<String>,
    /// 1-based line of the `<geom>` element.
    pub line: usize,
    /// Why it was skipped.
    pub reason: String,
}

/// A parsed MJCF model from which chains are extracted (see the module documentation for
/// frames, units and what is supported).
#[derive(Debug, Clone)]
pub struct MjcfRobot {
    source_name: String,
    model: Model,
    /// The folder mesh files are relative to (`meshdir` joined to the file's folder).
    mesh_dir: PathBuf,
}

/// Whether `text` looks like MJCF: its first element is `<mujoco`.
pub(crate) fn is_mjcf(text: &str) -> bool {
    let mut rest = text.trim_start_matches('\u{feff}').trim_start();
    // Skip the XML declaration, comments and processing instructions before the root.
    loop {
        if let Some(after) = rest.strip_prefix("<?") {
            rest = after.split_once("?>").map_or("", |(_, r)| r).trim_start();
        } else if let Some(after) = rest.strip_prefix("<!--") {
            rest = after.split_once("-->").map_or("", |(_, r)| r).trim_start();
        } else {
            break;
        }
    }
    rest.strip_prefix("<mujoco")
        .is_some_and(|r| r.starts_with(|c: char| c.is_whitespace() || c == '>' || c == '/'))
}

impl MjcfRobot {
    /// Reads and parses an MJCF file; mesh files are looked up relative to its folder (and its
    /// `<compiler meshdir>`).
    pub fn from_file(path: &Path) -> Result<Self, RobotError> {
        let source_name = path.display().to_string();
        let text = crate::input::read_to_string(path, crate::input::MAX_ROBOT_FILE_BYTES).map_err(
            |source| RobotError::Io {
                source_name: source_name.clone(),
                source,
            },
        )?;
        let folder = path.parent().unwrap_or(Path::new("."));
        Self::from_xml_in(&text, &source_name, folder)
    }

    /// Parses MJCF text; `source_name` names it in errors, `folder` is where relative mesh
    /// paths start (the file's folder).
    pub fn from_xml_in(text: &str, source_name: &str, folder: &Path) -> Result<Self, RobotError> {
        let root = dom::parse(text, source_name)?;
        let model = parse::read(&root, source_name)?;
        let mesh_dir = match &model.compiler.mesh_dir {
            Some(dir) => folder.join(dir),
            None => folder.to_path_buf(),
        };
        Ok(Self {
            source_name: source_name.to_string(),
            model,
            mesh_dir,
        })
    }

    /// The `<mujoco model="...">` name (MuJoCo's default `MuJoCo Model` when absent).
    pub fn name(&self) -> &str {
        &self.model.name
    }

    /// The file the model was read from, for messages.
    pub fn source_name(&self) -> &str {
        &self.source_name
    }

    /// Every body name, `world` first, then in file order.
    pub fn body_names(&self) -> Vec<&str> {
        self.model.bodies.iter().map(|b| b.name.as_str()).collect()
    }

    /// The folder mesh files are looked up in.
    pub fn mesh_dir(&self) -> &Path {
        &self.mesh_dir
    }

    /// The colliding geoms that are not collision shapes (see the module documentation).
    pub fn skipped_geoms(&self) -> Vec<SkippedGeom> {
        let mut out = Vec::new();
        for body in &self.model.bodies {
            for geom in &body.geoms {
                if let GeomKind::Skipped(reason) = &geom.kind {
                    out.push(SkippedGeom {
                        body: body.name.clone(),
                        geom: geom.name.clone(),
                        line: geom.line,
                        reason: reason.clone(),
                    });
                }
            }
        }
        out
    }

    /// The collision shapes of every body that has any, in file order, each in its body frame;
    /// mesh files are resolved through `meshes` (relative to [`MjcfRobot::mesh_dir`]) but not
    /// read.
    pub fn collisions(&self, meshes: &MeshResolver) -> Result<Vec<LinkCollisions>, RobotError> {
        let mut out = Vec::new();
        for body in &self.model.bodies {
            let mut shapes = Vec::new();
            for geom in &body.geoms {
                let geometry = match &geom.kind {
                    GeomKind::Shape(shape) => CollisionGeometry::Shape(shape.clone()),
                    GeomKind::Mesh { file, scale } => CollisionGeometry::Mesh(MeshRef {
                        source_name: self.source_name.clone(),
                        link: body.name.clone(),
                        uri: file.clone(),
                        path: meshes.resolve(file, &self.source_name, &body.name)?,
                        scale: *scale,
                    }),
                    GeomKind::Skipped(_) => continue,
                };
                shapes.push(CollisionShape {
                    name: geom.name.clone(),
                    link_from_collision: geom.body_from_geom,
                    geometry,
                });
            }
            if !shapes.is_empty() {
                out.push(LinkCollisions {
                    link: body.name.clone(),
                    shapes,
                });
            }
        }
        Ok(out)
    }

    /// A mesh resolver for this model: plain paths relative to [`MjcfRobot::mesh_dir`].
    pub fn mesh_resolver(&self) -> MeshResolver {
        MeshResolver {
            base_dir: self.mesh_dir.clone(),
            ..MeshResolver::default()
        }
    }

    fn body_index(&self, name: &str, role: &'static str) -> Result<usize, RobotError> {
        self.model
            .body_index
            .get(name)
            .copied()
            .ok_or_else(|| RobotError::UnknownLink {
                source_name: self.source_name.clone(),
                element: "body",
                link: name.to_string(),
                role,
                suggestions: closest_names(name, self.body_names()),
            })
    }

    /// The chain from body `base` down to body `tip`, with an optional tool offset
    /// `tip_from_tool` (see the module documentation for how joints become chain joints).
    pub fn chain_spec(
        &self,
        base: &str,
        tip: &str,
        tip_from_tool: Option<Isometry3<f64>>,
    ) -> Result<ChainSpec, RobotError> {
        Ok(self.chain_spec_and_origins(base, tip, tip_from_tool)?.0)
    }

    /// [`MjcfRobot::chain_spec`], with the MJCF origin of each chain joint: the body it
    /// carries and the index of its `<joint>` in that body (`None` for a fixed joint).
    fn chain_spec_and_origins(
        &self,
        base: &str,
        tip: &str,
        tip_from_tool: Option<Isometry3<f64>>,
    ) -> Result<(ChainSpec, Vec<JointOrigin>), RobotError> {
        let base_index = self.body_index(base, "base")?;
        let tip_index = self.body_index(tip, "tip")?;
        let mut path = Vec::new();
        let mut at = tip_index;
        while at != base_index {
            path.push(at);
            match self.model.bodies[at].parent {
                Some(parent) => at = parent,
                None => {
                    return Err(RobotError::TipNotBelowBase {
                        source_name: self.source_name.clone(),
                        element: "body",
                        base: base.to_string(),
                        tip: tip.to_string(),
                        root: self.model.bodies[at].name.clone(),
                    })
                }
            }
        }
        path.reverse();
        let mut on_path = vec![false; self.model.bodies.len()];
        on_path[base_index] = true;
        for &index in &path {
            on_path[index] = true;
        }
        let mut joints = Vec::new();
        let mut origins = Vec::new();
        for &index in &path {
            let before = joints.len();
            self.body_joints(index, &mut joints)?;
            let body = &self.model.bodies[index];
            for k in 0..joints.len() - before {
                origins.push((index, (k < body.joints.len()).then_some(k)));
            }
            if let Some(last) = joints.last_mut() {
                // The last joint of a body carries the body frame (see `body_joints`).
                last.child_inertial = self.attached_body(index, &on_path);
            }
        }
        let spec = ChainSpec {
            source_name: self.source_name.clone(),
            base_link: base.to_string(),
            tip_link: tip.to_string(),
            joints,
            tip_from_tool,
        };
        Ok((spec, origins))
    }

    /// The flattened chain from body `base` to body `tip` (see [`MjcfRobot::chain_spec`]).
    pub fn chain(
        &self,
        base: &str,
        tip: &str,
        tip_from_tool: Option<Isometry3<f64>>,
    ) -> Result<Chain, RobotError> {
        let (spec, origins) = self.chain_spec_and_origins(base, tip, tip_from_tool)?;
        Chain::from_spec(&spec).map_err(|e| self.in_mjcf_terms(e, &spec, &origins))
    }

    /// A chain joint's error (worded for URDF: `origin/@xyz`, `limit`) restated for the MJCF
    /// element it comes from: the body's or joint's `pos`, the joint's `range`.
    fn in_mjcf_terms(
        &self,
        error: RobotError,
        spec: &ChainSpec,
        origins: &[JointOrigin],
    ) -> RobotError {
        let RobotError::BadJoint {
            joint: name,
            field,
            message,
            ..
        } = &error
        else {
            return error;
        };
        let Some(at) = spec.joints.iter().position(|j| j.name == *name) else {
            return error;
        };
        let (body_index, joint_index) = origins[at];
        let body = &self.model.bodies[body_index];
        let joint = joint_index.map(|k| &body.joints[k]);
        let body_element = if body.name.starts_with("unnamed_body_") {
            format!("<body> ({})", body.name)
        } else {
            format!("<body name=\"{}\">", body.name)
        };
        let (line, element, attribute, message) = match (*field, joint) {
            ("limit", Some(joint)) => {
                let js = &spec.joints[at];
                (
                    joint.line,
                    if joint.name.starts_with('#') {
                        format!("<joint> {} in body '{}'", joint.name, body.name)
                    } else {
                        format!("<joint name=\"{}\">", joint.name)
                    },
                    "range",
                    format!(
                        "[{}, {}] (rad or m) is beyond ±{} (a joint without limits takes no range, or limited=\"false\")",
                        js.lower,
                        js.upper,
                        crate::robot::chain::MAX_JOINT_LIMIT
                    ),
                )
            }
            ("origin" | "origin/@xyz", _) => (
                body.line,
                body_element,
                "pos",
                format!("the body frame, with its joints' pos, in its parent's frame: {message}"),
            ),
            _ => (body.line, body_element, "-", message.clone()),
        };
        RobotError::Mjcf {
            source_name: self.source_name.clone(),
            line,
            element,
            attribute: attribute.to_string(),
            message,
        }
    }

    /// The mass properties of body `index` and of every body below it that is not in
    /// `on_path` (their joints held at `qpos0`, the written pose), in `index`'s frame; `None`
    /// when none of them has an `<inertial>` or when `<compiler inertiafromgeom="true">` tells
    /// MuJoCo to ignore them all.
    fn attached_body(&self, index: usize, on_path: &[bool]) -> Option<RigidBody> {
        if self.model.compiler.inertia_from_geom_only {
            return None;
        }
        let mut total: Option<RigidBody> = None;
        let mut stack = vec![(index, Isometry3::<f64>::identity())];
        while let Some((at, top_from_body)) = stack.pop() {
            if let Some(body) = &self.model.bodies[at].inertial {
                let body = body.transformed(&top_from_body);
                total = Some(total.map_or(body, |t| t.combined(&body)));
            }
            for &child in &self.model.children[at] {
                if !on_path[child] {
                    let b = &self.model.bodies[child];
                    stack.push((child, top_from_body * b.parent_from_body));
                }
            }
        }
        total
    }

    /// The chain joints that carry body `index` from its parent's frame to its own.
    fn body_joints(&self, index: usize, out: &mut Vec<JointSpec>) -> Result<(), RobotError> {
        let body = &self.model.bodies[index];
        // The transform from the last joint's child frame (or the parent body) still to apply.
        let mut pending = body.parent_from_body;
        for (k, joint) in body.joints.iter().enumerate() {
            let refuse = |message: String| RobotError::MjcfJointInChain {
                source_name: self.source_name.clone(),
                body: body.name.clone(),
                joint: joint.name.clone(),
                message,
            };
            let anchor = Translation3::from(joint.pos);
            let (kind, lower, upper, parent_from_joint) = match joint.kind {
                JointType::Ball | JointType::Free => {
                    return Err(refuse(format!(
                        "a {} joint cannot be part of a serial chain (only hinge and slide joints); start the chain at '{}' or below{}",
                        joint.kind.word(),
                        body.name,
                        if joint.kind == JointType::Free { " to leave a floating base out" } else { "" },
                    )))
                }
                JointType::Hinge => {
                    // R(axis, q − ref) = R(axis, −ref) · R(axis, q).
                    let turn = UnitQuaternion::from_axis_angle(&joint.axis, -joint.reference);
                    let at = pending * anchor * turn;
                    match joint.range {
                        Some((lo, hi)) => (JointKind::Revolute, lo, hi, at),
                        None => (JointKind::Continuous, f64::NEG_INFINITY, f64::INFINITY, at),
                    }
                }
                JointType::Slide => {
                    let Some((lo, hi)) = joint.range else {
                        return Err(refuse(
                            "an unlimited slide joint cannot be part of a chain: give it a range".into(),
                        ));
                    };
                    let shift = Translation3::from(-joint.reference * joint.axis.into_inner());
                    (JointKind::Prismatic, lo, hi, pending * anchor * shift)
                }
            };
            let last = k + 1 == body.joints.len();
            let child_link = if last && joint.pos == Vector3::zeros() {
                body.name.clone()
            } else {
                format!("{}@{}", body.name, joint.name)
            };
            out.push(JointSpec {
                name: self.joint_name(&body.name, &joint.name),
                child_link,
                kind,
                parent_from_joint,
                axis: joint.axis.into_inner(),
                lower,
                upper,
                mimic: None,
                limits: MotionLimits {
                    effort: joint.effort,
                    ..MotionLimits::default()
                },
                // A link between two joints of one body is a frame, not a body: massless.
                child_inertial: (!last).then(|| RigidBody::point(0.0, Vector3::zeros())),
            });
            pending = anchor.inverse().into();
        }
        let needs_fixed = match body.joints.last() {
            None => true,
            Some(joint) => joint.pos != Vector3::zeros(),
        };
        if needs_fixed {
            out.push(JointSpec {
                name: format!("{}_fixed", body.name),
                child_link: body.name.clone(),
                kind: JointKind::Fixed,
                parent_from_joint: pending,
                axis: Vector3::z(),
                lower: 0.0,
                upper: 0.0,
                mimic: None,
                limits: Default::default(),
                child_inertial: None,
            });
        }
        Ok(())
    }

    /// A joint's chain name: its MJCF name, or `BODY#K` when unnamed.
    fn joint_name(&self, body: &str, joint: &str) -> String {
        if joint.starts_with('#') {
            format!("{body}{joint}")
        } else {
            joint.to_string()
        }
    }
}
