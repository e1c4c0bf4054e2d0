//! Grasping: hand models and the learned one-shot grasp model (Kopicki et al.).

pub mod hand;
pub mod model;
