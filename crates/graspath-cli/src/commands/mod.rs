//! One module per subcommand.

pub mod demo;
pub mod ik;
pub mod kinematics;
pub mod select;
