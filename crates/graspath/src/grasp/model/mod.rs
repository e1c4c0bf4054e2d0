//! The one-shot learned grasp model (Kopicki et al., IJRR 2016; spec in
//! `research/kopicki-grasp-model.md`): contact models per hand link and a hand-configuration
//! model learned from one demonstration, query densities on a new object cloud, and grasp
//! generation by seeds plus simulated annealing with staged selection.
//!
//! Frames: clouds, features and candidate poses are in the **object frame** (metres);
//! `object_from_wrist` is the wrist pose; link poses are `wrist_from_link` (see
//! [`crate::grasp::hand`]).

pub mod configuration;
pub mod kernel;
