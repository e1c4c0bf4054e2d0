//! One module per subcommand.

pub mod demo;
pub mod kinematics;
pub mod select;
