//! Loading chains from URDF files (through `urdf-rs`).
//!
//! Only kinematics is read: link geometry is ignored, so `package://` mesh paths never stop a
//! robot from loading. A `.xacro` file is refused with the command that expands it.

use super::chain::{unit_axis, Chain};
use super::error::RobotError;
use super::spec::{ChainSpec, JointKind, JointSpec, Mimic};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::collections::HashMap;
use std::path::Path;

/// A parsed URDF robot from which chains are extracted.
#[derive(Debug, Clone)]
pub struct UrdfRobot {
    source_name: String,
    robot: urdf_rs::Robot,
}

impl UrdfRobot {
    /// Reads and parses a URDF file.
    pub fn from_file(path: &Path) -> Result<Self, RobotError> {
        let source_name = path.display().to_string();
        if path.extension().is_some_and(|e| e == "xacro") {
            return Err(RobotError::Xacro { source_name });
        }
        let text = std::fs::read_to_string(path).map_err(|e| RobotError::Io {
            source_name: source_name.clone(),
            message: e.to_string(),
        })?;
        Self::from_xml(&text, &source_name)
    }

    /// Parses URDF text; `source_name` names it in errors.
    pub fn from_xml(text: &str, source_name: &str) -> Result<Self, RobotError> {
        if text.contains("<xacro:") {
            return Err(RobotError::Xacro {
                source_name: source_name.to_string(),
            });
        }
        let robot = urdf_rs::read_from_string(text).map_err(|e| RobotError::Parse {
            source_name: source_name.to_string(),
            message: e.to_string(),
        })?;
        Ok(Self {
            source_name: source_name.to_string(),
            robot,
        })
    }

    /// The robot's name attribute.
    pub fn name(&self) -> &str {
        &self.robot.name
    }

    /// The names of all links, in file order.
    pub fn link_names(&self) -> Vec<&str> {
        self.robot.links.iter().map(|l| l.name.as_str()).collect()
    }

    /// The underlying parsed document (links with their geometry, joints, materials).
    pub fn document(&self) -> &urdf_rs::Robot {
        &self.robot
    }

    /// The chain from `base_link` down to `tip_link`, with an optional tool offset
    /// `tip_from_tool` appended.
    pub fn chain_spec(
        &self,
        base_link: &str,
        tip_link: &str,
        tip_from_tool: Option<Isometry3<f64>>,
    ) -> Result<ChainSpec, RobotError> {
        self.require_link(base_link, "base")?;
        self.require_link(tip_link, "tip")?;
        let parent_joint: HashMap<&str, &urdf_rs::Joint> = self
            .robot
            .joints
            .iter()
            .map(|j| (j.child.link.as_str(), j))
            .collect();
        let mut path = Vec::new();
        let mut link = tip_link;
        while link != base_link {
            match parent_joint.get(link) {
                Some(joint) => {
                    path.push(*joint);
                    link = joint.parent.link.as_str();
                    if path.len() > self.robot.joints.len() {
                        return Err(RobotError::Parse {
                            source_name: self.source_name.clone(),
                            message: format!("the joints above link '{tip_link}' form a loop"),
                        });
                    }
                }
                None => {
                    return Err(RobotError::TipNotBelowBase {
                        source_name: self.source_name.clone(),
                        base: base_link.to_string(),
                        tip: tip_link.to_string(),
                        root: link.to_string(),
                    })
                }
            }
        }
        path.reverse();
        let joints = path
            .into_iter()
            .map(|j| self.joint_spec(j))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(ChainSpec {
            source_name: self.source_name.clone(),
            base_link: base_link.to_string(),
            tip_link: tip_link.to_string(),
            joints,
            tip_from_tool,
        })
    }

    /// The flattened chain from `base_link` to `tip_link` (see [`UrdfRobot::chain_spec`]).
    pub fn chain(
        &self,
        base_link: &str,
        tip_link: &str,
        tip_from_tool: Option<Isometry3<f64>>,
    ) -> Result<Chain, RobotError> {
        Chain::from_spec(&self.chain_spec(base_link, tip_link, tip_from_tool)?)
    }

    fn require_link(&self, name: &str, role: &'static str) -> Result<(), RobotError> {
        if self.robot.links.iter().any(|l| l.name == name) {
            return Ok(());
        }
        Err(RobotError::UnknownLink {
            source_name: self.source_name.clone(),
            link: name.to_string(),
            role,
            suggestions: closest_names(name, self.link_names()),
        })
    }

    fn joint_spec(&self, joint: &urdf_rs::Joint) -> Result<JointSpec, RobotError> {
        let bad = |field: &'static str, message: String| RobotError::BadJoint {
            source_name: self.source_name.clone(),
            joint: joint.name.clone(),
            field,
            message,
        };
        let xyz = joint.origin.xyz.0;
        let rpy = joint.origin.rpy.0;
        if xyz.iter().any(|v| !v.is_finite()) {
            return Err(bad("origin/@xyz", format!("not finite: {xyz:?}")));
        }
        if rpy.iter().any(|v| !v.is_finite()) {
            return Err(bad("origin/@rpy", format!("not finite: {rpy:?}")));
        }
        let parent_from_joint = Isometry3::from_parts(
            Translation3::new(xyz[0], xyz[1], xyz[2]),
            UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
        );
        let kind = match joint.joint_type {
            urdf_rs::JointType::Revolute => JointKind::Revolute,
            urdf_rs::JointType::Continuous => JointKind::Continuous,
            urdf_rs::JointType::Prismatic => JointKind::Prismatic,
            urdf_rs::JointType::Fixed => JointKind::Fixed,
            ref other => {
                return Err(bad(
                    "@type",
                    format!("{other:?} joints are not supported in a serial chain"),
                ))
            }
        };
        let raw_axis = Vector3::from(joint.axis.xyz.0);
        let axis = if kind == JointKind::Fixed {
            unit_axis(&raw_axis).unwrap_or_else(Vector3::x)
        } else {
            unit_axis(&raw_axis).ok_or_else(|| {
                bad(
                    "axis/@xyz",
                    format!(
                        "must be a non-zero finite vector, got {:?}",
                        raw_axis.as_slice()
                    ),
                )
            })?
        };
        let (lower, upper) = match kind {
            JointKind::Continuous => (f64::NEG_INFINITY, f64::INFINITY),
            JointKind::Fixed => (0.0, 0.0),
            _ => {
                let (lo, hi) = (joint.limit.lower, joint.limit.upper);
                if lo.is_nan() || hi.is_nan() || lo > hi {
                    return Err(bad(
                        "limit",
                        format!("lower {lo} and upper {hi} are not an interval"),
                    ));
                }
                (lo, hi)
            }
        };
        let mimic = joint
            .mimic
            .as_ref()
            .map(|m| {
                let multiplier = m.multiplier.unwrap_or(1.0);
                let offset = m.offset.unwrap_or(0.0);
                if !multiplier.is_finite() || !offset.is_finite() {
                    return Err(bad("mimic", "multiplier and offset must be finite".into()));
                }
                Ok(Mimic {
                    leader: m.joint.clone(),
                    multiplier,
                    offset,
                })
            })
            .transpose()?;
        Ok(JointSpec {
            name: joint.name.clone(),
            child_link: joint.child.link.clone(),
            kind,
            parent_from_joint,
            axis,
            lower,
            upper,
            mimic,
        })
    }
}

/// Loads the chain `base_link → tip_link` from a URDF file.
pub fn load_urdf_chain(
    path: &Path,
    base_link: &str,
    tip_link: &str,
    tip_from_tool: Option<Isometry3<f64>>,
) -> Result<Chain, RobotError> {
    UrdfRobot::from_file(path)?.chain(base_link, tip_link, tip_from_tool)
}

/// Parses URDF text and extracts one chain; `source_name` names the text in errors.
pub fn parse_urdf_chain(
    text: &str,
    source_name: &str,
    base_link: &str,
    tip_link: &str,
) -> Result<Chain, RobotError> {
    UrdfRobot::from_xml(text, source_name)?.chain(base_link, tip_link, None)
}

/// Up to five names closest to `name` (by edit distance, or sharing a substring).
fn closest_names(name: &str, candidates: Vec<&str>) -> Vec<String> {
    let mut scored: Vec<(usize, &str)> = candidates
        .into_iter()
        .map(|c| {
            let mut d = strsim::levenshtein(name, c);
            if c.contains(name) || name.contains(c) {
                d = d.min(1);
            }
            (d, c)
        })
        .filter(|(d, c)| *d <= (name.len().max(c.len()) / 2).max(2))
        .collect();
    scored.sort();
    scored
        .into_iter()
        .take(5)
        .map(|(_, c)| c.to_string())
        .collect()
}
