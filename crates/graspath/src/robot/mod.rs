//! Robot kinematics: serial chains loaded from URDF (or xacro), MJCF or built in, forward kinematics, the
//! geometric Jacobian, inverse kinematics of single poses ([`solve_ik`]) and of whole
//! trajectories ([`solve_trajectory`]).
//!
//! Every pose and Jacobian is expressed in the **chain base frame** (the base link's frame).
//! The Jacobian has rows `[v; ω]`: `v` is the linear velocity (m/s) of the tip origin and `ω`
//! the angular velocity (rad/s) of the tip, both along base-frame axes (Siciliano's `J₀`,
//! Pinocchio's `LOCAL_WORLD_ALIGNED`). Column `j` belongs to the chain's `j`-th active joint.
//!
//! Rigid-body dynamics of a chain (gravity torques, inverse dynamics, the mass matrix, a
//! payload at the tool) is [`Dynamics`], built by [`Chain::dynamics`] from the links' mass
//! properties ([`RigidBody`]) and the joints' [`MotionLimits`]; see `docs/dynamics.md`.

pub mod builtin;
mod chain;
mod collision;
mod dynamics;
mod error;
mod ik;
mod mjcf;
mod source;
mod spec;
mod srdf;
mod trig;
mod urdf;
mod urdf_scan;
mod xacro;

pub use chain::{
    Chain, ChainLayout, FixedChain, JointAxes, JointAxis, LinkPlacement, MotionKind, SegmentLayout,
    SweepBound,
};
pub use collision::{CollisionGeometry, CollisionShape, LinkCollisions, MeshRef, MeshResolver};
pub use dynamics::{Dynamics, DynamicsData, STANDARD_GRAVITY};
pub use error::RobotError;
pub use ik::{
    null_space, optimize_self_motion, optimize_smooth_self_motion, solve_ik, solve_trajectories,
    solve_trajectory, IkFailure, IkOptions, IkSolution, JointPath, KeptRows, SampleValue,
    SelfMotionOptions, SelfMotionPath, SmoothSelfMotion, TrajectoryIkOptions, TrajectoryIkResult,
};
pub use mjcf::{MjcfRobot, SkippedGeom};
pub use source::{RobotModel, RobotSource};
pub use spec::{ChainSpec, JointKind, JointSpec, Mimic, MotionLimits, RigidBody};
pub use srdf::{DisabledPair, EndEffector, Srdf, SrdfGroup};
pub use urdf::{load_urdf_chain, parse_urdf_chain, UrdfRobot};
pub use xacro::{
    expand_xacro, expand_xacro_with, find_xacro_program, is_xacro_path, XacroOptions,
    PASSED_ENVIRONMENT,
};
