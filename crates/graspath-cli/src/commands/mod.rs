//! One module per subcommand.

pub mod generate;
pub mod kinematics;
pub mod train;
