//! The MJCF writer behind [`super::world_mjcf`]: bodies, joints and inertials of the arms, the
//! geoms of every shape, the gripper's sliding fingers, the object, the table, and the assets,
//! welds and actuators after the world body.

use super::mjcf::{name, placement, pose_of, Value, Xml};
use super::{ArmNames, PhysicsError, WorldOptions, MAX_SPHERES, OBJECT};
use crate::collision::{ArmBodies, Body, BodyKind, Table};
use crate::geometry::shape::Shape;
use crate::robot::{Chain, JointKind, MotionKind, RigidBody};
use crate::task::{Gripper, Task};
use nalgebra::{Isometry3, Vector3};

/// A geom's contact filter, `(contype, conaffinity)`.
pub(super) type ContactBits = (&'static str, &'static str);

/// Contact filter bits: the object collides with everything, the arms with the object and
/// the static world only.
pub(super) const STATIC: ContactBits = ("1", "1");
const OBJECT_BITS: ContactBits = ("1", "1");
const ARM_BITS: ContactBits = ("2", "1");

/// An arm to write.
pub(super) struct ArmInput<'a> {
    pub arm: &'a str,
    pub chain: &'a Chain,
    pub world_from_base: &'a Isometry3<f64>,
    /// Its collision bodies (links; the hand's are written from the gripper).
    pub bodies: Option<&'a ArmBodies>,
}

/// The model being written: the world body's contents, then the assets the geoms need.
pub(super) struct Writer<'o> {
    pub xml: Xml,
    options: &'o WorldOptions,
    /// Meshes: name, vertices, triangles.
    meshes: Vec<(String, Vec<f64>, Vec<f64>)>,
    /// How many geoms each label has.
    geoms: std::collections::HashMap<String, usize>,
}

impl<'o> Writer<'o> {
    pub(super) fn new(model: &str, options: &'o WorldOptions) -> Self {
        let mut xml = Xml::new();
        xml.open("mujoco", &[("model", name(model))]);
        xml.comment("written by graspath: see docs/simulation.md");
        xml.leaf(
            "compiler",
            &[
                ("angle", "radian".into()),
                ("autolimits", "true".into()),
                ("inertiafromgeom", "false".into()),
            ],
        );
        xml.leaf(
            "option",
            &[
                ("timestep", options.timestep.into()),
                (
                    "gravity",
                    vec![0.0, 0.0, -crate::robot::STANDARD_GRAVITY].into(),
                ),
                ("integrator", "implicitfast".into()),
                ("cone", "elliptic".into()),
                ("impratio", 10.0.into()),
            ],
        );
        xml.open("worldbody", &[]);
        Self {
            xml,
            options,
            meshes: Vec::new(),
            geoms: std::collections::HashMap::new(),
        }
    }

    /// The next geom name of `label`: `label/0`, `label/1`, ...
    fn geom_name(&mut self, label: &str) -> String {
        let count = self.geoms.entry(label.to_string()).or_insert(0);
        *count += 1;
        format!("{label}/{}", *count - 1)
    }

    /// Closes the world body and writes the assets, the welds (with an object) and the
    /// actuators.
    pub(super) fn finish(mut self, arms: &[ArmNames], object: bool) -> String {
        self.xml.close("worldbody");
        if !self.meshes.is_empty() {
            self.xml.open("asset", &[]);
            for (mesh, vertices, faces) in std::mem::take(&mut self.meshes) {
                self.xml.leaf(
                    "mesh",
                    &[
                        ("name", name(&mesh)),
                        ("vertex", vertices.into()),
                        ("face", faces.into()),
                    ],
                );
            }
            self.xml.close("asset");
        }
        if object {
            self.xml.open("equality", &[]);
            for arm in arms {
                self.xml.leaf(
                    "weld",
                    &[
                        ("name", name(&arm.grasp_weld)),
                        ("body1", name(&arm.tool)),
                        ("body2", name(OBJECT)),
                        ("active", "false".into()),
                    ],
                );
            }
            self.xml.close("equality");
        }
        self.xml.open("actuator", &[]);
        for arm in arms {
            for (joint, effort) in arm.joints.iter().zip(&arm.effort) {
                let mut attributes = vec![("name", name(joint)), ("joint", name(joint))];
                if effort.is_finite() {
                    attributes.push(("ctrlrange", vec![-effort, *effort].into()));
                }
                self.xml.leaf("motor", &attributes);
            }
            let force = self.options.grip_force;
            for finger in &arm.fingers {
                self.xml.leaf(
                    "position",
                    &[
                        ("name", name(finger)),
                        ("joint", name(finger)),
                        ("kp", (force / FINGER_SATURATION).into()),
                        ("ctrlrange", vec![0.0, arm.finger_travel].into()),
                        ("forcerange", vec![-force, force].into()),
                    ],
                );
            }
        }
        self.xml.close("actuator");
        self.xml.close("mujoco");
        self.xml.finish()
    }

    pub(super) fn table(&mut self, table: &Table) {
        let friction = Value::from(vec![self.options.friction, 0.005, 0.0001]);
        match table.footprint {
            None => self.xml.leaf(
                "geom",
                &[
                    ("name", "table".into()),
                    ("type", "plane".into()),
                    ("pos", vec![0.0, 0.0, table.height].into()),
                    ("size", vec![0.0, 0.0, 1.0].into()),
                    ("contype", STATIC.0.into()),
                    ("conaffinity", STATIC.1.into()),
                    ("friction", friction),
                ],
            ),
            Some(([x, y], [cx, cy])) => self.xml.leaf(
                "geom",
                &[
                    ("name", "table".into()),
                    ("type", "box".into()),
                    (
                        "pos",
                        vec![cx, cy, table.height - table.thickness / 2.0].into(),
                    ),
                    ("size", vec![x / 2.0, y / 2.0, table.thickness / 2.0].into()),
                    ("contype", STATIC.0.into()),
                    ("conaffinity", STATIC.1.into()),
                    ("friction", friction),
                ],
            ),
        }
    }

    /// The geoms of a collision body placed at `pose` in the current body's frame, named
    /// `label/k`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn body_geoms(
        &mut self,
        label: &str,
        body: &Body,
        pose: &Isometry3<f64>,
        bits: ContactBits,
        friction: Option<f64>,
        notes: &mut Vec<String>,
    ) -> Result<(), PhysicsError> {
        match body.kind() {
            BodyKind::Solid(shape) => self.shape(label, shape, pose, bits, friction),
            BodyKind::Surface(shape) => {
                notes.push(format!(
                    "{label}: a triangle mesh collides as its convex hull in MuJoCo"
                ));
                self.shape(label, shape, pose, bits, friction);
            }
            BodyKind::HalfSpace { height } => {
                let plane = pose * Isometry3::translation(0.0, 0.0, *height);
                let geom = self.geom_name(label);
                let mut attributes = vec![
                    ("name", name(&geom)),
                    ("type", "plane".into()),
                    ("size", vec![0.0, 0.0, 1.0].into()),
                ];
                attributes.extend(placement(&plane));
                attributes.push(("contype", bits.0.into()));
                attributes.push(("conaffinity", bits.1.into()));
                self.xml.leaf("geom", &attributes);
            }
            BodyKind::Points { points, radius } => {
                if points.len() > MAX_SPHERES {
                    return Err(PhysicsError::TooManySpheres {
                        body: label.into(),
                        points: points.len(),
                    });
                }
                for p in points.iter() {
                    let geom = self.geom_name(label);
                    let centre = pose * p;
                    self.xml.leaf(
                        "geom",
                        &[
                            ("name", name(&geom)),
                            ("type", "sphere".into()),
                            ("size", (*radius).into()),
                            ("pos", vec![centre.x, centre.y, centre.z].into()),
                            ("contype", bits.0.into()),
                            ("conaffinity", bits.1.into()),
                        ],
                    );
                }
            }
        }
        Ok(())
    }

    /// The geoms of one shape at `pose`, named `label/k` (a T-shape is two geoms).
    fn shape(
        &mut self,
        label: &str,
        shape: &Shape,
        pose: &Isometry3<f64>,
        bits: ContactBits,
        friction: Option<f64>,
    ) {
        let parts: Vec<GeomPart> = match shape {
            Shape::Box(b) => vec![GeomPart::sized(
                *pose,
                "box",
                b.half_extents().as_slice().to_vec(),
            )],
            Shape::Cylinder(c) => {
                vec![GeomPart::sized(
                    *pose,
                    "cylinder",
                    vec![c.radius(), c.length() / 2.0],
                )]
            }
            Shape::Sphere(s) => vec![GeomPart::sized(*pose, "sphere", vec![s.radius()])],
            // A capsule without a segment is a sphere (MuJoCo needs a positive half-length).
            Shape::Capsule(c) if c.length() == 0.0 => {
                vec![GeomPart::sized(*pose, "sphere", vec![c.radius()])]
            }
            Shape::Capsule(c) => vec![GeomPart::sized(
                *pose,
                "capsule",
                vec![c.radius(), c.length() / 2.0],
            )],
            Shape::TShape(t) => {
                let stem = pose * Isometry3::translation(0.0, 0.0, t.stem_centre());
                let stem_part = match t.stem() {
                    crate::geometry::shape::Stem::Cylinder(c) => {
                        GeomPart::sized(stem, "cylinder", vec![c.radius(), c.length() / 2.0])
                    }
                    crate::geometry::shape::Stem::Box(b) => {
                        GeomPart::sized(stem, "box", b.half_extents().as_slice().to_vec())
                    }
                };
                vec![
                    GeomPart::sized(*pose, "box", t.bar().half_extents().as_slice().to_vec()),
                    stem_part,
                ]
            }
            Shape::ConvexMesh(m) => {
                let mesh = format!("mesh{}", self.meshes.len());
                let vertices = m
                    .hull_vertices()
                    .iter()
                    .flat_map(|p| [p.x, p.y, p.z])
                    .collect();
                self.meshes.push((mesh.clone(), vertices, Vec::new()));
                vec![GeomPart::mesh(*pose, mesh)]
            }
            Shape::TriangleMesh(m) => {
                let mesh = format!("mesh{}", self.meshes.len());
                let vertices = m.vertices().iter().flat_map(|p| [p.x, p.y, p.z]).collect();
                let faces = m
                    .triangles()
                    .iter()
                    .flat_map(|t| t.map(f64::from))
                    .collect();
                self.meshes.push((mesh.clone(), vertices, faces));
                vec![GeomPart::mesh(*pose, mesh)]
            }
        };
        for part in parts {
            let geom = self.geom_name(label);
            let mut attributes = vec![("name", name(&geom)), ("type", Value::Text(part.kind))];
            match &part.size {
                GeomSize::Mesh(mesh) => attributes.push(("mesh", name(mesh))),
                GeomSize::Size(size) => attributes.push(("size", size.clone().into())),
            }
            attributes.extend(placement(&part.pose));
            attributes.push(("contype", bits.0.into()));
            attributes.push(("conaffinity", bits.1.into()));
            if let Some(friction) = friction {
                attributes.push(("friction", vec![friction, 0.005, 0.0001].into()));
                attributes.push(("condim", "4".into()));
            }
            self.xml.leaf("geom", &attributes);
        }
    }

    /// One arm: its base, segments, link shapes, tool and (given) gripper.
    pub(super) fn arm(
        &mut self,
        input: &ArmInput<'_>,
        gripper: Option<&Gripper>,
        notes: &mut Vec<String>,
    ) -> Result<ArmNames, PhysicsError> {
        let (arm, chain) = (input.arm, input.chain);
        let layout = chain.layout();
        if layout.has_mimic {
            return Err(PhysicsError::Mimic {
                chain: chain.name(),
            });
        }
        // The link shapes, by the segment they ride on (index 0: the base).
        let mut shapes: Vec<Vec<(String, Isometry3<f64>, &Body)>> =
            vec![Vec::new(); layout.segments.len() + 1];
        if let Some(bodies) = input.bodies {
            for link_body in bodies.bodies.iter().filter(|b| !b.hand) {
                let link = &layout.links[link_body.link];
                let link_from_body: Isometry3<f64> = nalgebra::convert(link_body.link_from_body);
                let pose = pose_of(&link.rotation, &link.translation) * link_from_body;
                let label = format!("{arm}/{}", link.name);
                shapes[link.segment.map_or(0, |s| s + 1)].push((label, pose, &link_body.body));
            }
        }
        let base = format!("{arm}/base");
        let mut attributes = vec![("name", name(&base))];
        attributes.extend(placement(input.world_from_base));
        self.xml.open("body", &attributes);
        let mut joints = Vec::new();
        let mut effort = Vec::new();
        for (k, segment_shapes) in shapes.iter().enumerate() {
            if let Some(i) = k.checked_sub(1) {
                let segment = &layout.segments[i];
                let joint = &chain.joint_names()[i];
                let body = segment.body.filter(|b| b.mass > 0.0).ok_or_else(|| {
                    PhysicsError::NoInertia {
                        chain: chain.name(),
                        joint: joint.clone(),
                    }
                })?;
                let label = format!(
                    "{arm}/{}",
                    segment.links.first().map_or(joint.as_str(), String::as_str)
                );
                let mut attributes = vec![("name", name(&label))];
                attributes.extend(placement(&pose_of(&segment.rotation, &segment.translation)));
                attributes.extend(self.gravity_compensation());
                self.xml.open("body", &attributes);
                self.inertial(&body);
                let joint_name = format!("{arm}/{joint}");
                let mut attributes = vec![
                    ("name", name(&joint_name)),
                    (
                        "type",
                        match segment.kind {
                            MotionKind::Revolute => "hinge".into(),
                            MotionKind::Prismatic => "slide".into(),
                        },
                    ),
                    ("axis", vec![0.0, 0.0, 1.0].into()),
                ];
                if chain.joint_kinds()[i] != JointKind::Continuous {
                    attributes.push(("range", vec![chain.lower()[i], chain.upper()[i]].into()));
                }
                self.xml.leaf("joint", &attributes);
                joints.push(joint_name);
                effort.push(chain.motion_limits()[i].effort.unwrap_or(f64::INFINITY));
            }
            for (label, pose, body) in segment_shapes {
                self.body_geoms(label, body, pose, ARM_BITS, None, notes)?;
            }
        }
        let tool = format!("{arm}/tool");
        let mut attributes = vec![("name", name(&tool))];
        attributes.extend(placement(&pose_of(
            &layout.tail_rotation,
            &layout.tail_translation,
        )));
        self.xml.open("body", &attributes);
        self.xml
            .leaf("site", &[("name", name(&tool)), ("size", 0.005.into())]);
        let (fingers, finger_travel) = match gripper {
            Some(gripper) => self.gripper(arm, gripper),
            None => (Vec::new(), 0.0),
        };
        self.xml.close("body");
        for _ in 0..layout.segments.len() + 1 {
            self.xml.close("body");
        }
        Ok(ArmNames {
            arm: arm.into(),
            joints,
            effort,
            tool,
            fingers,
            finger_travel,
            grasp_weld: format!("{arm}/grasp"),
            task_gripper: false,
        })
    }

    /// `gravcomp="1"` on an arm's moving body when its weight is carried outside the motors.
    fn gravity_compensation(&self) -> Option<(&'static str, Value<'static>)> {
        self.options
            .arm_gravity_compensation
            .then_some(("gravcomp", 1.0.into()))
    }

    /// A body's `<inertial>`: its mass at its centre of mass with its full inertia.
    fn inertial(&mut self, body: &RigidBody) {
        let i = &body.inertia;
        self.xml.leaf(
            "inertial",
            &[
                ("pos", body.com.as_slice().to_vec().into()),
                ("mass", body.mass.into()),
                (
                    "fullinertia",
                    vec![
                        i[(0, 0)],
                        i[(1, 1)],
                        i[(2, 2)],
                        i[(0, 1)],
                        i[(0, 2)],
                        i[(1, 2)],
                    ]
                    .into(),
                ),
            ],
        );
    }

    /// The gripper on the tool body: fixed hand shapes, then one body per finger on a slide
    /// joint towards the tool's `z` axis. Returns the finger joints and their travel (m).
    fn gripper(&mut self, arm: &str, gripper: &Gripper) -> (Vec<String>, f64) {
        let fingers = gripper.finger_shapes();
        let hand_label = format!("{arm}/hand");
        for (shape_name, tool_from_shape, shape) in gripper.hand_shapes() {
            if !fingers.iter().any(|(f, _, _)| *f == shape_name) {
                self.shape(&hand_label, &shape, &tool_from_shape, ARM_BITS, None);
            }
        }
        // Fingers grouped by name (a URDF hand's finger link may have several shapes).
        let mut groups: Vec<(String, FingerShapes)> = Vec::new();
        for (finger, pose, shape) in fingers {
            match groups.iter_mut().find(|(g, _)| *g == finger) {
                Some((_, parts)) => parts.push((pose, shape)),
                None => groups.push((finger, vec![(pose, shape)])),
            }
        }
        let travel = gripper.opening / 2.0;
        let mut joints = Vec::new();
        for (k, (_, parts)) in groups.iter().enumerate() {
            let centre: Vector3<f64> = parts
                .iter()
                .map(|(p, _)| p.translation.vector)
                .sum::<Vector3<f64>>()
                / parts.len() as f64;
            let inward = Vector3::new(-centre.x, -centre.y, 0.0);
            let body_name = format!("{arm}/finger{k}");
            let mut attributes = vec![("name", name(&body_name))];
            attributes.extend(self.gravity_compensation());
            self.xml.open("body", &attributes);
            self.xml.leaf(
                "inertial",
                &[
                    ("pos", vec![centre.x, centre.y, centre.z].into()),
                    ("mass", self.options.finger_mass.into()),
                    ("diaginertia", vec![1e-5, 1e-5, 1e-5].into()),
                ],
            );
            if let Some(axis) = inward.try_normalize(1e-9) {
                self.xml.leaf(
                    "joint",
                    &[
                        ("name", name(&body_name)),
                        ("type", "slide".into()),
                        ("axis", axis.as_slice().to_vec().into()),
                        ("range", vec![0.0, travel].into()),
                        (
                            "damping",
                            (self.options.grip_force.max(1.0) / FINGER_SPEED).into(),
                        ),
                        ("armature", FINGER_ARMATURE.into()),
                    ],
                );
                joints.push(body_name.clone());
            }
            for (pose, shape) in parts {
                self.shape(
                    &body_name,
                    shape,
                    pose,
                    ARM_BITS,
                    Some(self.options.friction),
                );
            }
            self.xml.close("body");
        }
        (joints, travel)
    }

    /// The object: a free body at the path's first pose with the task's mass properties (or
    /// its shape's at the option's density). Returns its mass (kg).
    pub(super) fn object(
        &mut self,
        task: &Task,
        shape: &Shape,
        notes: &mut Vec<String>,
    ) -> Result<f64, PhysicsError> {
        let start = task
            .path
            .samples
            .first()
            .map_or_else(Isometry3::identity, |s| s.world_from_object);
        let mut attributes = vec![("name", name(OBJECT))];
        attributes.extend(placement(&start));
        self.xml.open("body", &attributes);
        self.xml.leaf("freejoint", &[("name", name(OBJECT))]);
        let friction = Some(self.options.friction);
        let body = match &task.payload {
            Some(payload) => *payload,
            None => {
                let density = self.options.object_density;
                let solid = shape.solid_mass().map_err(|_| PhysicsError::NoMass)?;
                let body = RigidBody::new(
                    density * solid.volume,
                    solid.centroid,
                    solid.inertia * density,
                );
                notes.push(format!(
                    "the task gives the object no mass: {density} kg/m³ is assumed ({:.3} kg)",
                    body.mass
                ));
                body
            }
        };
        self.inertial(&body);
        self.shape(OBJECT, shape, &Isometry3::identity(), OBJECT_BITS, friction);
        let mass = body.mass;
        self.xml.close("body");
        Ok(mass)
    }
}

/// One finger's shapes, tool frame.
type FingerShapes = Vec<(Isometry3<f64>, Shape)>;

/// A geom's size: numbers, or the name of a mesh asset.
enum GeomSize {
    Size(Vec<f64>),
    Mesh(String),
}

/// One geom of a shape: its pose in the body frame, MuJoCo type and size.
struct GeomPart {
    pose: Isometry3<f64>,
    kind: &'static str,
    size: GeomSize,
}

impl GeomPart {
    fn sized(pose: Isometry3<f64>, kind: &'static str, size: Vec<f64>) -> Self {
        Self {
            pose,
            kind,
            size: GeomSize::Size(size),
        }
    }

    fn mesh(pose: Isometry3<f64>, mesh: String) -> Self {
        Self {
            pose,
            kind: "mesh",
            size: GeomSize::Mesh(mesh),
        }
    }
}

/// The finger position error (m) at which the grip force saturates: the actuators' gain is the
/// grip force over it.
const FINGER_SATURATION: f64 = 0.01;
/// The fingers' closing speed (m/s) under the full grip force, set by their joints' damping:
/// about the speed of the Franka hand and Baxter's electric gripper. A finger that closes
/// faster strikes a light object hard enough to squeeze it out at millisecond steps.
const FINGER_SPEED: f64 = 0.1;
/// Finger joint armature (kg): keeps the stiff finger drive stable at millisecond steps.
const FINGER_ARMATURE: f64 = 0.01;
