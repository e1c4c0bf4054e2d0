//! One module per subcommand.

pub mod ik;
pub mod kinematics;
