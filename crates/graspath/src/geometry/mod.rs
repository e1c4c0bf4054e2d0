//! Rigid-body geometry: poses, SE(3) exponential and logarithm, pose interpolation,
//! quaternion helpers and the one shape vocabulary ([`shape`]).
//!
//! Conventions (used throughout the crate): metres and radians; a transform is named
//! `a_from_b` and maps coordinates in frame `b` to frame `a`; transforms compose right to left
//! (`world_from_wrist = world_from_object * object_from_wrist`). A twist is a 6-vector
//! `[v; ω]` (linear part first).

mod interpolate;
mod matrix;
mod pose_spec;
mod quaternion;
mod se3;
pub mod shape;

pub use interpolate::{interpolate_decoupled, interpolate_screw};
pub use matrix::{pose_from_rows, pose_to_rows, PoseError, ROTATION_TOLERANCE};
pub use pose_spec::{
    unit_quaternion_xyzw, PoseSpec, PoseSpecError, QuaternionError, QUATERNION_NORM_TOLERANCE,
};
pub use quaternion::{quaternion_angle_between, quaternion_in_hemisphere_of, quaternion_xyzw};
pub use se3::{se3_exp, se3_log, so3_log, Twist};
