//! A chain described joint by joint, before flattening: what a URDF file or a built-in model
//! provides.

use nalgebra::{Isometry3, Matrix3, Vector3};

/// The motion a joint allows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation about the axis within `[lower, upper]` (rad).
    Revolute,
    /// Rotation about the axis without limits.
    Continuous,
    /// Translation along the axis within `[lower, upper]` (m).
    Prismatic,
    /// No motion: folded into a constant transform.
    Fixed,
}

/// A joint whose value follows another joint: `q = multiplier · q_leader + offset`.
#[derive(Debug, Clone, PartialEq)]
pub struct Mimic {
    /// The name of the joint that is followed.
    pub leader: String,
    /// Factor applied to the leader's value.
    pub multiplier: f64,
    /// Offset added (rad or m).
    pub offset: f64,
}

/// One joint of a chain, as in URDF: the child frame is
/// `parent_from_child = parent_from_joint · motion(axis, q)`.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpec {
    /// Joint name.
    pub name: String,
    /// The link the joint moves (URDF `<child>`): its frame is the joint frame after the
    /// motion. Empty when unknown; [`crate::robot::Chain::link_names`] then names it after the
    /// joint.
    pub child_link: String,
    /// The kind of motion.
    pub kind: JointKind,
    /// The joint frame in the parent link frame (URDF `<origin>`), metres.
    pub parent_from_joint: Isometry3<f64>,
    /// Unit axis in the joint frame (URDF `<axis>`; default `x`).
    pub axis: Vector3<f64>,
    /// Lower limit (rad or m); `-∞` for continuous joints.
    pub lower: f64,
    /// Upper limit (rad or m); `+∞` for continuous joints.
    pub upper: f64,
    /// Set when the joint mimics another joint.
    pub mimic: Option<Mimic>,
    /// Velocity, effort and acceleration limits (unknown ones `None`).
    pub limits: MotionLimits,
    /// The mass properties of the child link together with everything rigidly attached to it
    /// that is not on the chain (fixed children, and branches locked at zero), in the child
    /// link frame. `None` when the source gives no inertial data for any of them.
    pub child_inertial: Option<RigidBody>,
}

/// A joint's limits beyond its position range. `None` where the source does not say.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MotionLimits {
    /// Largest speed (rad/s or m/s).
    pub velocity: Option<f64>,
    /// Largest torque (N·m) or force (N).
    pub effort: Option<f64>,
    /// Largest acceleration (rad/s² or m/s²).
    pub acceleration: Option<f64>,
}

/// The mass properties of a rigid body in some frame `F` (the frame is named where the body
/// is used): its mass (kg), its centre of mass in `F` (m) and its rotational inertia about the
/// centre of mass along `F`'s axes (kg·m², symmetric).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidBody {
    /// Mass (kg), non-negative.
    pub mass: f64,
    /// Centre of mass in `F` (m).
    pub com: Vector3<f64>,
    /// Rotational inertia about the centre of mass, along `F`'s axes (kg·m²).
    pub inertia: Matrix3<f64>,
}

impl RigidBody {
    /// A body of mass `mass` (kg) at `com` (m) with the principal moments or full inertia
    /// `inertia` about its centre of mass (kg·m²).
    pub fn new(mass: f64, com: Vector3<f64>, inertia: Matrix3<f64>) -> Self {
        Self { mass, com, inertia }
    }

    /// A point mass (kg) at `com` (m).
    pub fn point(mass: f64, com: Vector3<f64>) -> Self {
        Self::new(mass, com, Matrix3::zeros())
    }

    /// The body described in frame `G`, given `g_from_f` (this body is in `F`).
    pub fn transformed(&self, g_from_f: &Isometry3<f64>) -> Self {
        let rotation = g_from_f.rotation.to_rotation_matrix().into_inner();
        Self {
            mass: self.mass,
            com: g_from_f.transform_point(&self.com.into()).coords,
            inertia: rotation * self.inertia * rotation.transpose(),
        }
    }

    /// The two bodies as one (both in the same frame). The centre of mass of two massless
    /// bodies is the origin.
    pub fn combined(&self, other: &Self) -> Self {
        let mass = self.mass + other.mass;
        let com = if mass > 0.0 {
            (self.com * self.mass + other.com * other.mass) / mass
        } else {
            Vector3::zeros()
        };
        let about = |b: &Self| {
            let d = b.com - com;
            b.inertia + b.mass * (Matrix3::identity() * d.norm_squared() - d * d.transpose())
        };
        Self {
            mass,
            com,
            inertia: about(self) + about(other),
        }
    }

    /// Whether every number is finite, the mass non-negative and the inertia symmetric
    /// (to 1e-9 relative) with non-negative diagonal, down to `INERTIA_ROUNDING` (1e-15 kg·m²) below zero
    /// (iCub's URDF writes a zero moment as −5.4e−20 kg·m², which Pinocchio and urdfdom
    /// accept). Physical consistency (the triangle inequality of the principal moments) is
    /// not required: published models break it.
    pub fn is_valid(&self) -> bool {
        let finite = self.mass.is_finite()
            && self.com.iter().all(|v| v.is_finite())
            && self.inertia.iter().all(|v| v.is_finite());
        let scale = self.inertia.amax().max(f64::MIN_POSITIVE);
        finite
            && self.mass >= 0.0
            && (self.inertia - self.inertia.transpose()).amax() <= 1e-9 * scale
            && (0..3).all(|i| self.inertia[(i, i)] >= -INERTIA_ROUNDING)
    }
}

/// How far below zero a moment of inertia may be and still be read as a rounded zero
/// (kg·m²): far below any physical link's (a 1 g, 1 mm part has about 1e−10).
pub(super) const INERTIA_ROUNDING: f64 = 1e-15;

/// A serial chain from a base link to a tip link, every joint in order from the base.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainSpec {
    /// Where it came from: a file path or `built-in <model>`; used in error messages.
    pub source_name: String,
    /// The base link: poses and Jacobians are expressed in its frame.
    pub base_link: String,
    /// The tip link.
    pub tip_link: String,
    /// The joints from base to tip, fixed ones included.
    pub joints: Vec<JointSpec>,
    /// An extra constant transform after the tip link (a tool centre point), `tip_from_tool`.
    pub tip_from_tool: Option<Isometry3<f64>>,
}
