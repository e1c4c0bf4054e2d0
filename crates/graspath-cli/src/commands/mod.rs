//! One module per subcommand.

pub mod demo;
pub mod generate;
pub mod ik;
pub mod kinematics;
pub mod select;
pub mod train;
