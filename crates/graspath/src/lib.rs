//! # graspath
//!
//! Task-relevant grasp selection: choose where a robot should grasp an object so that the arm
//! can then perform a given manipulation task well (Ghalamzan et al., "Task-relevant grasp
//! selection: a joint solution to planning grasps and manipulative motion trajectories",
//! IROS 2016).
//!
//! ## The pipeline
//!
//! The modules follow the data, and each imports only the modules before it in this list
//! (those on one line import each other in neither direction):
//!
//! 1. the ground, which imports nothing of the pipeline: [`defaults`] — every default of a
//!    task, in one place; [`spelling`] — every setting chosen by name and its spellings;
//!    [`failure`] — why something failed, one spelling everywhere; [`input`] — opening input
//!    files (regular files only, under a size cap); [`random`] — the one seed mixer;
//! 2. [`geometry`] — poses (`a_from_b` transforms, the one pose syntax of every input file
//!    [`geometry::PoseSpec`]), SE(3) logarithm and exponential, interpolation, shapes; and
//!    [`output_files`] — writing output files and folders atomically, never clobbering;
//! 3. [`robot`] — serial chains (built-in arms, URDF, xacro or MJCF, SRDF beside them) with
//!    every link frame and each link's collision shapes and inertia, forward kinematics, the
//!    geometric Jacobian and rigid-body dynamics, inverse kinematics of one pose and of a
//!    whole trajectory;
//! 4. [`collision`] — the scene (a table and obstacles), the bodies of an arm and its hand,
//!    and the checks of a whole motion at every sample and, with a proven bound, between
//!    samples; [`cloud`] — point clouds (PLY, PCD, meshes, sampled shapes) and their surface
//!    features; [`manipulability`] — the classical indices, the task-relevant index
//!    `M_T = uᵀ J Jᵀ u`, the dynamic one and their norms along the path, with the settings
//!    that choose among them; [`timing`] — how long a motion takes: a branch's joint samples
//!    as a cubic spline, its time-optimal parameterisation under joint velocity, acceleration
//!    and torque limits (TOPP-RA), and the timed trajectory a controller executes;
//! 5. [`grasp`] — grasp candidates (wrist poses in the object frame with likelihoods) from
//!    files, parametric families or the learned one-shot grasp model;
//! 6. [`task`] — [`task::Task`]: the arms, the candidates, the object's path after the grasp
//!    and every setting, built and checked by [`task::TaskBuilder`] or read from a task file;
//! 7. [`select`] — every candidate scored along its whole motion for each arm (approach, the
//!    object's path, retreat: trajectory IK, collisions in a scene, torques, timing, the
//!    index per path sample, norms), ranked, and paired for two arms (best first, refusing
//!    pairs whose arms touch). Each result carries its candidate; and [`physics`] — the
//!    task's world written for a physics engine (MuJoCo MJCF);
//! 8. [`placement`] — placement maps: the selection run with the object started at every
//!    placement of a grid (x, y, optionally z and yaw), in parallel, one record per placement.
//!
//! Every module has its own error type naming the file and field at fault, with the error that
//! caused it kept as its [`source`](std::error::Error::source); [`Error`] gathers them for
//! applications that handle errors once. Each says what kind of failure it is ([`Classify`],
//! [`ErrorKind`]: an unusable file, bad content, a resource limit, or internal): the `graspath`
//! binary's exit codes and the Python exceptions are derived from it.
//!
//! Reports (JSON, figures, the HTML 3D view) are in the `graspath-report` crate; the `graspath`
//! binary and the Python bindings are thin layers over these two.
//!
//! ## Example
//!
//! ```
//! use graspath::grasp::edge_family;
//! use graspath::robot::builtin::{baxter, Arm};
//! use graspath::select::select;
//! use graspath::geometry::shape::Shape;
//! use graspath::task::{Sampling, Step, Task, TimedStep};
//! use nalgebra::{Isometry3, Vector3};
//!
//! let shape = Shape::cuboid([0.06, 0.40, 0.10]).unwrap();
//! let lift = TimedStep::new("lift", Step::translation(Vector3::new(0.0, 0.0, 0.2)));
//! let task = Task::builder("lift a box")
//!     .arm("left", baxter(Arm::Left), Isometry3::identity())
//!     .shape(shape.clone())
//!     .candidates(edge_family(&shape, 5, 0.02, 0.02).unwrap())
//!     .object_motion(Isometry3::translation(0.75, 0.0, -0.1), vec![lift], Sampling::PerStep(5))
//!     .build()
//!     .unwrap();
//! let selection = select(&task, &|| {}).unwrap();
//! let best = selection.arms[0].best().expect("a feasible grasp");
//! println!("grasp {}", selection.arms[0].scores[best].candidate.label);
//! ```
//!
//! Units are metres, radians and seconds. A transform is named `a_from_b`: it maps coordinates
//! in frame `b` to frame `a`.
#![warn(missing_docs, unreachable_pub)]

pub mod cloud;
pub mod collision;
mod cpu;
pub mod defaults;
mod error;
pub mod failure;
mod fault;
pub mod geometry;
pub mod grasp;
pub mod input;
pub mod manipulability;
pub mod output_files;
pub mod physics;
pub mod placement;
pub mod random;
pub mod robot;
pub mod select;
pub mod spelling;
pub mod task;
pub mod timing;

pub use error::{fault_of, Error, Result};
pub use fault::{Chain, Classify, ErrorKind, Fault};
