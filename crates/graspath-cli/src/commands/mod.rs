//! One module per subcommand.

pub mod demo;
pub mod generate;
pub mod ik;
pub mod kinematics;
pub mod map;
pub mod select;
pub mod train;
