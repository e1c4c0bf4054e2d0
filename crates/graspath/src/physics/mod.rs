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
mod writer;

use crate::robot::Chain;
use crate::task::{Gripper, Task};
use mjcf::{name, placement};
use nalgebra::Isometry3;
use writer::{ArmInput, Writer, STATIC};

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

impl crate::fault::Classify for PhysicsError {
    /// A cloud over the sphere limit is [`ErrorKind`](crate::fault::ErrorKind)`::Limit`; everything
    /// else is `Content`.
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        Some(match self {
            Self::TooManySpheres { .. } => crate::fault::ErrorKind::Limit,
            _ => crate::fault::ErrorKind::Content,
        })
    }

    fn field(&self) -> Option<&str> {
        match self {
            Self::BadOption { field, .. } => Some(field),
            _ => None,
        }
    }
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
