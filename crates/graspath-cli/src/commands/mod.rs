//! One module per subcommand.

pub mod kinematics;
