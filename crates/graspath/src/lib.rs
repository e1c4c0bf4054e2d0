//! # graspath
//!
//! Task-relevant grasp selection: choose where a robot should grasp an object so that the arm
//! can then perform a given manipulation task well (Ghalamzan et al., "Task-relevant grasp
//! selection: a joint solution to planning grasps and manipulative motion trajectories",
//! IROS 2016).
//!
//! The modules follow the pipeline: [`geometry`] (poses), [`robot`] (chains, forward and
//! inverse kinematics), [`cloud`] (point clouds and their surface features), [`grasp`] (hand
//! models and the learned one-shot grasp model), [`manipulability`] (indices and their norms
//! along a path).
//!
//! Units are metres, radians and seconds. A transform is named `a_from_b`: it maps coordinates
//! in frame `b` to frame `a`.
#![warn(missing_docs)]

pub mod cloud;
pub mod failure;
pub mod fsutil;
pub mod geometry;
pub mod grasp;
pub mod manipulability;
pub mod robot;
pub mod select;
pub mod task;
