//! graspath's world written for a physics engine: the task's arms, gripper, object, table and
//! obstacles as one MJCF model that MuJoCo loads unchanged, so that a chosen grasp and its
//! task can be executed and measured (the Python package's `graspath.sim`). The core never
//! runs a simulator; this module only writes the model.
//!
//! **The model.** Every arm is a chain of bodies, one per moving segment of its [`Chain`]
//! ([`Chain::layout`]): a body's frame is the segment's aligned joint frame (its `z` is the
//! joint axis), placed exactly as graspath's kinematics places it, so MuJoCo's forward
//! kinematics equals graspath's to rounding; its `<inertial>` is the segment's mass, centre of
//! mass and full inertia, so MuJoCo's joint-space inertia equals graspath's dynamics. Joints
//! keep their limits; each joint has a torque motor (`<motor>`, control range the joint's
//! effort limit when known) for a computed-torque controller. No armature, damping or
//! friction is added to the arm joints. The links' collision shapes (the task's, when it
//! checks collisions) ride on their segments.
//!
//! At the tool frame (the chain's tool, `{arm}/tool` body and site) sits the gripper: the
//! task's, else a parallel gripper opening [`DEFAULT_OPENING`]. Each finger is a body on a
//! slide joint that moves it towards the tool's `z` axis (a parallel gripper's fingers close
//! along the tool's `y`), from open (0) to the middle (half the opening), driven by a
//! position actuator whose force is limited to [`WorldOptions::grip_force`] and damped to
//! close at most 10 cm/s; the palm and the hand's other shapes are fixed to the tool.
//!
//! The object is a free body (`object`) at the path's first pose, with the task's mass
//! properties (`object.mass`) or, without them, its shape's at
//! [`WorldOptions::object_density`]. The table is a plane (an infinite table) or a box, the
//! obstacles are their shapes (a cloud as spheres, a triangle mesh as MuJoCo takes every mesh:
//! its convex hull — said in [`MjcfWorld::notes`]).
//!
//! **Contacts.** The object touches everything; the arms and grippers touch the object, the
//! table and the obstacles, not themselves or each other (graspath's own checks cover those).
//! Finger and object geoms share the friction [`WorldOptions::friction`] with torsional
//! friction (`condim` 4), on elliptic cones with `impratio` 10 and the implicit integrator —
//! the settings under which a held object does not creep out of a grip.
//!
//! **Equality constraints**, off at the start, for the simulator to switch: `{arm}/grasp`
//! welds the object to an arm's tool (a welded grasp, which isolates the arm from slip).
//!
//! Names: arm `a`'s joint `j` is the joint and the motor `a/j`; its segment bodies are
//! `a/<first link of the segment>`; its fingers' joints and actuators `a/finger0`,
//! `a/finger1`, …; geoms `a/<link>/k`, `a/hand/k`, `object/k`, `table`, `obstacle <name>/k`.
//! [`MjcfWorld`] lists them.

mod mjcf;

use crate::collision::{ArmBodies, Body, BodyKind, Table};
use crate::geometry::shape::Shape;
use crate::robot::{Chain, JointKind, MotionKind, RigidBody};
use crate::task::{Gripper, Task};
use mjcf::{name, placement, pose_of, Value, Xml};
use nalgebra::{Isometry3, Vector3};

/// How the physics model is set up beyond what the task says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldOptions {
    /// The simulation time step (s).
    pub timestep: f64,
    /// The sliding friction coefficient of the fingers and the object.
    pub friction: f64,
    /// The largest force each finger presses with (N).
    pub grip_force: f64,
    /// The object's density when the task gives no mass (kg/m³).
    pub object_density: f64,
    /// Each finger's mass (kg).
    pub finger_mass: f64,
    /// Whether the arms' and hands' own weight is carried outside the motors (MuJoCo's
    /// `gravcomp` on their bodies): a gravity-assist spring or counterbalance, such as the one
    /// on Baxter's shoulder `s1` that its published 50 N·m limit leaves out. The motors then
    /// carry the motion and the object only.
    pub arm_gravity_compensation: bool,
}

/// The default sliding friction of fingers and object: rubber finger pads on wood or
/// cardboard.
pub const DEFAULT_FRICTION: f64 = 1.0;
/// The default grip force per finger (N): Baxter's electric gripper holds with about 35–45 N,
/// the Franka hand 70 N (continuous) between its two fingers.
pub const DEFAULT_GRIP_FORCE: f64 = 40.0;
/// The default object density without a task mass (kg/m³): light wood.
pub const DEFAULT_OBJECT_DENSITY: f64 = 500.0;
/// The opening of the gripper written when the task gives none (m).
pub const DEFAULT_OPENING: f64 = 0.10;
/// The most spheres a cloud obstacle may become in the model.
pub const MAX_SPHERES: usize = 20_000;

impl Default for WorldOptions {
    fn default() -> Self {
        Self {
            timestep: 0.002,
            friction: DEFAULT_FRICTION,
            grip_force: DEFAULT_GRIP_FORCE,
            object_density: DEFAULT_OBJECT_DENSITY,
            finger_mass: 0.05,
            arm_gravity_compensation: false,
        }
    }
}

/// Why a world cannot be written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    /// An option is out of its range.
    #[error("{field}: {message}")]
    BadOption {
        /// The option.
        field: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A segment of an arm has no mass properties.
    #[error(
        "chain {chain}: the segment moved by joint '{joint}' has no inertial data; a physics \
         model needs every moving link's mass"
    )]
    NoInertia {
        /// The chain.
        chain: String,
        /// The joint.
        joint: String,
    },
    /// An arm has a mimic joint (not written yet).
    #[error("chain {chain}: mimic joints are not written to physics models")]
    Mimic {
        /// The chain.
        chain: String,
    },
    /// The object has no mass in the task and its shape encloses no volume.
    #[error(
        "the object has no mass (object.mass) and its shape encloses no volume: a physics \
         model needs one"
    )]
    NoMass,
    /// The task has no object shape.
    #[error("the task's object has no shape (object.shape): a physics model needs one")]
    NoShape,
    /// A cloud has too many points.
    #[error("{body}: {points} points; a physics model takes at most {MAX_SPHERES} spheres")]
    TooManySpheres {
        /// The body.
        body: String,
        /// Its point count.
        points: usize,
    },
}

/// One arm's names in a written world.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmNames {
    /// The arm.
    pub arm: String,
    /// Its joints in the order of `q` (each also names its motor).
    pub joints: Vec<String>,
    /// Each joint's effort limit (N·m or N; infinite when unknown): its motor's range.
    pub effort: Vec<f64>,
    /// The tool body (and site): the chain's tool frame.
    pub tool: String,
    /// The finger joints (each also names its actuator): open at 0.
    pub fingers: Vec<String>,
    /// The finger joints' closed end (m): half the opening.
    pub finger_travel: f64,
    /// The weld of the object to the tool (inactive at the start).
    pub grasp_weld: String,
    /// Whether the gripper is the task's (`false`: [`DEFAULT_OPENING`] written in its place).
    pub task_gripper: bool,
}

/// A written world: the MJCF text and the names a simulator drives.
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfWorld {
    /// The MJCF document.
    pub xml: String,
    /// Each arm's names, in the task's arm order.
    pub arms: Vec<ArmNames>,
    /// The object's free body (and free joint).
    pub object: String,
    /// The object's mass (kg).
    pub object_mass: f64,
    /// Whether the world has a table.
    pub has_table: bool,
    /// What the model approximates, one line each (a mesh taken as its hull, a default
    /// gripper, a task without collision shapes).
    pub notes: Vec<String>,
}

/// The object's body name.
pub const OBJECT: &str = "object";

/// A geom's contact filter, `(contype, conaffinity)`.
type ContactBits = (&'static str, &'static str);

/// Contact filter bits: the object collides with everything, the arms with the object and
/// the static world only.
const STATIC: ContactBits = ("1", "1");
const OBJECT_BITS: ContactBits = ("1", "1");
const ARM_BITS: ContactBits = ("2", "1");

/// Writes `task`'s world ([module docs](self)).
pub fn world_mjcf(task: &Task, options: &WorldOptions) -> Result<MjcfWorld, PhysicsError> {
    check_options(options)?;
    let shape = task.shape.as_ref().ok_or(PhysicsError::NoShape)?;
    let mut notes = Vec::new();
    let mut writer = Writer::new(&task.source_name, options);
    let scene = task.collisions.as_ref().map(|c| &c.scene);
    let has_table = scene.and_then(|s| s.table()).is_some();
    match scene {
        Some(scene) => {
            if let Some(table) = scene.table() {
                writer.table(table);
            }
            for obstacle in scene.obstacles() {
                let label = obstacle.body.name().to_string();
                let mut attributes = vec![("name", name(&label))];
                attributes.extend(placement(&obstacle.world_from_body));
                writer.xml.open("body", &attributes);
                writer.body_geoms(
                    &label,
                    &obstacle.body,
                    &Isometry3::identity(),
                    STATIC,
                    None,
                    &mut notes,
                )?;
                writer.xml.close("body");
            }
        }
        None => notes.push(
            "the task has no scene: no table, no obstacles, and no collision shapes on the arms"
                .into(),
        ),
    }
    let mut arms = Vec::new();
    for arm in &task.arms {
        let gripper = task.gripper.clone().unwrap_or_else(|| {
            notes.push(format!(
                "arm {}: the task has no gripper; a parallel gripper opening {DEFAULT_OPENING} m \
                 is written",
                arm.name
            ));
            Gripper::parallel(DEFAULT_OPENING)
        });
        let input = ArmInput {
            arm: &arm.name,
            chain: &arm.chain,
            world_from_base: &arm.world_from_base,
            bodies: arm.bodies.as_deref(),
        };
        let mut names = writer.arm(&input, Some(&gripper), &mut notes)?;
        names.task_gripper = task.gripper.is_some();
        arms.push(names);
    }
    let object_mass = writer.object(task, shape, &mut notes)?;
    Ok(MjcfWorld {
        xml: writer.finish(&arms, true),
        arms,
        object: OBJECT.into(),
        object_mass,
        has_table,
        notes,
    })
}

/// Writes one arm alone (no gripper, no object, no scene), its base at the world origin: the
/// model whose kinematics and joint-space inertia are compared with graspath's. Its names
/// are those of [`world_mjcf`] for an arm named `arm`.
pub fn chain_mjcf(chain: &Chain, arm: &str) -> Result<(String, ArmNames), PhysicsError> {
    let options = WorldOptions::default();
    let mut writer = Writer::new(&chain.name(), &options);
    let input = ArmInput {
        arm,
        chain,
        world_from_base: &Isometry3::identity(),
        bodies: None,
    };
    let names = writer.arm(&input, None, &mut Vec::new())?;
    let xml = writer.finish(std::slice::from_ref(&names), false);
    Ok((xml, names))
}

fn check_options(options: &WorldOptions) -> Result<(), PhysicsError> {
    let checks: [(&'static str, f64, f64, f64); 5] = [
        ("timestep", options.timestep, 1e-5, 0.05),
        ("friction", options.friction, 0.0, 10.0),
        ("grip_force", options.grip_force, 0.0, 10_000.0),
        ("object_density", options.object_density, 1.0, 50_000.0),
        ("finger_mass", options.finger_mass, 1e-4, 10.0),
    ];
    for (field, value, lo, hi) in checks {
        if !(lo..=hi).contains(&value) {
            return Err(PhysicsError::BadOption {
                field,
                message: format!("{value} is not within {lo} to {hi}"),
            });
        }
    }
    Ok(())
}

/// An arm to write.
struct ArmInput<'a> {
    arm: &'a str,
    chain: &'a Chain,
    world_from_base: &'a Isometry3<f64>,
    /// Its collision bodies (links; the hand's are written from the gripper).
    bodies: Option<&'a ArmBodies>,
}

/// The model being written: the world body's contents, then the assets the geoms need.
struct Writer<'o> {
    xml: Xml,
    options: &'o WorldOptions,
    /// Meshes: name, vertices, triangles.
    meshes: Vec<(String, Vec<f64>, Vec<f64>)>,
    /// How many geoms each label has.
    geoms: std::collections::HashMap<String, usize>,
}

impl<'o> Writer<'o> {
    fn new(model: &str, options: &'o WorldOptions) -> Self {
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
    fn finish(mut self, arms: &[ArmNames], object: bool) -> String {
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

    fn table(&mut self, table: &Table) {
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
    fn body_geoms(
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
    fn arm(
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
    fn object(
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
