//! Grasping: candidates (wrist poses in the object frame with likelihoods) from files or from
//! parametric families on primitive shapes, hand models, and the learned one-shot grasp model
//! (Kopicki et al.).

mod candidates;
mod families;
mod formats;
pub mod hand;
pub mod model;
mod source;

pub use candidates::{read_candidates, Candidate, CandidateError, CandidateFile, INDEX_STRIDE};
pub use families::{
    edge_family, face_family, yaw_family, FaceLine, FamilyError, FamilyLayout, GRIPPER_MAX_OPENING,
};
pub use formats::{
    guess_format, open_grasp_file, read_grasp_file, FramePlacementError, GraspCandidates,
    GraspFileOptions, GraspFormat, GraspFrame, GripperConvention, FRANKA_TCP_DEPTH,
    GRASPGEN_FRANKA_TCP_DEPTH, MAX_ARRAY_BYTES,
};
pub use source::CandidateSource;
