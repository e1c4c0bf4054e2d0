//! Grasping: candidates (wrist poses in the object frame with likelihoods) from files or from
//! parametric families on primitive shapes, hand models, and the learned one-shot grasp model
//! (Kopicki et al.).

mod candidates;
mod families;
mod formats;
pub mod hand;
pub mod model;

pub use candidates::{read_candidates, Candidate, CandidateError};
pub use families::{
    edge_family, face_family, yaw_family, FaceLine, FamilyError, FamilyLayout, GRIPPER_MAX_OPENING,
};
pub use formats::{
    guess_format, read_grasp_file, FramePlacementError, GraspFileOptions, GraspFormat, GraspFrame,
    GripperConvention, FRANKA_TCP_DEPTH, MAX_ARRAY_BYTES,
};
