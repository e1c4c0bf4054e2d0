//! Grasp candidates: wrist poses in the object frame with likelihoods, from files or from
//! parametric families on primitive shapes.

mod candidates;
mod families;

pub use candidates::{read_candidates, Candidate, CandidateError};
pub use families::{edge_family, face_family, yaw_family, GRIPPER_MAX_OPENING};
