//! The options that choose a robot chain, shared by the kinematics subcommands.

use crate::bad_input;
use anyhow::Result;
use clap::builder::PossibleValuesParser;
use clap::ArgGroup;
use clap::Args;
use graspath::robot::builtin::BUILTIN_NAMES;
use graspath::robot::{Chain, RobotSource};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use std::path::PathBuf;

/// A URDF chain (`--urdf --base --tip`), an MJCF chain (`--mjcf --base --tip`), either
/// (`--robot-file --base --tip`) or a built-in robot (`--robot --arm`).
#[derive(Debug, Args)]
#[command(group(ArgGroup::new("urdf_options").args(["urdf", "robot_file"])))]
pub(crate) struct RobotArgs {
    /// A URDF file. A file named *.xacro is expanded by the `xacro` program (it runs code:
    /// only expand files you trust); markup in other files is refused.
    #[arg(long, value_name = "FILE", conflicts_with = "robot", requires_all = ["base", "tip"])]
    pub urdf: Option<PathBuf>,
    /// A folder where `package://PKG` mesh URIs and xacro's `$(find PKG)` look first
    /// (repeatable; then ROS_PACKAGE_PATH, AMENT_PREFIX_PATH, the file's folders).
    #[arg(long, value_name = "DIR", requires = "urdf_options")]
    pub search_path: Vec<PathBuf>,
    /// A xacro argument for a *.xacro --urdf or --robot-file file (repeatable), e.g.
    /// `--xacro-arg dof:=7`.
    #[arg(long, value_name = "NAME:=VALUE", requires = "urdf_options", value_parser = parse_xacro_arg)]
    pub xacro_arg: Vec<(String, String)>,
    /// A MuJoCo MJCF file; --base and --tip name its bodies.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["robot", "urdf"], requires_all = ["base", "tip"])]
    pub mjcf: Option<PathBuf>,
    /// A URDF, xacro or MJCF file, its format told by its name (*.urdf, *.xacro, *.mjcf) or,
    /// for *.xml and other names, by its root element (<robot> or <mujoco>).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["robot", "urdf", "mjcf"], requires_all = ["base", "tip"])]
    pub robot_file: Option<PathBuf>,
    /// The chain's base link (MJCF: body): poses and Jacobians are expressed in its frame.
    #[arg(long, value_name = "LINK")]
    pub base: Option<String>,
    /// The chain's tip link.
    #[arg(long, value_name = "LINK")]
    pub tip: Option<String>,
    /// A built-in robot.
    #[arg(long, value_name = "NAME", value_parser = PossibleValuesParser::new(BUILTIN_NAMES))]
    pub robot: Option<String>,
    /// The chain of a built-in robot: `left` or `right` for Baxter, `arm` for the others
    /// (default: the robot's first chain).
    #[arg(long, value_name = "ARM")]
    pub arm: Option<String>,
    /// A tool offset after the tip, `x,y,z` in metres in the tip frame.
    #[arg(long, value_name = "X,Y,Z", value_delimiter = ',')]
    pub tool_xyz: Option<Vec<f64>>,
    /// The tool offset's rotation, `roll,pitch,yaw` in radians (URDF convention).
    #[arg(long, value_name = "R,P,Y", value_delimiter = ',')]
    pub tool_rpy: Option<Vec<f64>>,
}

impl RobotArgs {
    fn tool(&self) -> Result<Option<Isometry3<f64>>> {
        if self.tool_xyz.is_none() && self.tool_rpy.is_none() {
            return Ok(None);
        }
        let xyz = self.tool_xyz.clone().unwrap_or_else(|| vec![0.0; 3]);
        let rpy = self.tool_rpy.clone().unwrap_or_else(|| vec![0.0; 3]);
        if xyz.len() != 3 || rpy.len() != 3 {
            return Err(bad_input!(
                "--tool-xyz / --tool-rpy: give three comma-separated numbers, e.g. 0,0,0.1"
            ));
        }
        if xyz.iter().chain(&rpy).any(|v| !v.is_finite()) {
            return Err(bad_input!(
                "--tool-xyz / --tool-rpy: values must be finite numbers"
            ));
        }
        Ok(Some(Isometry3::from_parts(
            Translation3::new(xyz[0], xyz[1], xyz[2]),
            UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
        )))
    }

    /// Loads the chain the options name, through the library's one robot resolver.
    pub(crate) fn load(&self) -> Result<Chain> {
        let tool = self.tool()?;
        if let Some(path) = &self.robot_file {
            let (Some(base), Some(tip)) = (&self.base, &self.tip) else {
                return Err(bad_input!("--robot-file needs --base LINK and --tip LINK"));
            };
            let source = RobotSource::from_path(path)?.with_urdf_options(
                self.search_path.clone(),
                self.xacro_arg.iter().cloned().collect(),
            )?;
            return Ok(source.load()?.chain(base, tip, tool)?);
        }
        if let Some(path) = &self.mjcf {
            let (Some(base), Some(tip)) = (&self.base, &self.tip) else {
                return Err(bad_input!("--mjcf needs --base BODY and --tip BODY"));
            };
            return Ok(RobotSource::mjcf(path).load()?.chain(base, tip, tool)?);
        }
        match (&self.urdf, &self.robot) {
            (Some(path), None) => {
                let (Some(base), Some(tip)) = (&self.base, &self.tip) else {
                    return Err(bad_input!("--urdf needs --base LINK and --tip LINK"));
                };
                let source = RobotSource::Urdf {
                    path: path.clone(),
                    search_paths: self.search_path.clone(),
                    xacro_args: self.xacro_arg.iter().cloned().collect(),
                };
                Ok(source.load()?.chain(base, tip, tool)?)
            }
            (None, Some(name)) => {
                let model = RobotSource::builtin(name.as_str())
                    .load()
                    .map_err(|e| bad_input!("--robot: {e}"))?;
                let arm = match &self.arm {
                    Some(arm) => arm.clone(),
                    None => model.chain_names().first().cloned().unwrap_or_default(),
                };
                Ok(model
                    .named_chain(&arm, tool)
                    .map_err(|e| bad_input!("--arm: {e}"))?)
            }
            _ => Err(bad_input!("choose a robot: --robot NAME (e.g. --robot baxter --arm left, --robot ur5e), --urdf FILE --base LINK --tip LINK, --mjcf FILE --base BODY --tip BODY, or --robot-file FILE --base LINK --tip LINK")),
        }
    }
}

/// `NAME:=VALUE` (xacro's own argument syntax) as a pair; the library checks the name.
fn parse_xacro_arg(text: &str) -> Result<(String, String), String> {
    text.split_once(":=")
        .map(|(name, value)| (name.to_string(), value.to_string()))
        .ok_or_else(|| format!("'{text}' is not NAME:=VALUE (e.g. dof:=7)"))
}
