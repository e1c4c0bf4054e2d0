//! Mass properties and effort limits: a body's `<inertial>` (`pos`, an orientation, `mass`,
//! and `diaginertia` in the inertial frame or `fullinertia` `ixx iyy izz ixy ixz iyz` in the
//! body frame), a joint's `actuatorfrcrange`, and the `forcerange` of the actuators that drive
//! a joint (times their first `gear` entry). Defaults classes supply actuator attributes by
//! the actuator's element name (`motor`, `position`, `general`, ...).

use super::defaults::ORIENTATIONS;
use super::dom::Element;
use super::parse::Reader;
use crate::robot::error::RobotError;
use crate::robot::spec::RigidBody;
use nalgebra::{Matrix3, Vector3};

/// The actuator elements that act on a joint through `joint="..."`.
const ACTUATORS: [&str; 9] = [
    "general",
    "motor",
    "position",
    "velocity",
    "intvelocity",
    "damper",
    "cylinder",
    "muscle",
    "adhesion",
];

impl Reader<'_> {
    /// A body's `<inertial>` in the body frame (the frame of the element's parent).
    pub(super) fn inertial(&self, element: &Element) -> Result<RigidBody, RobotError> {
        if element.get("pos").is_none() {
            return Err(self.error(element, "pos", "an <inertial> needs a pos".into()));
        }
        let Some(mass_text) = element.get("mass") else {
            return Err(self.error(element, "mass", "an <inertial> needs a mass".into()));
        };
        let mass = self.numbers(element, "mass", mass_text, 1..=1)?[0];
        if mass < 0.0 {
            return Err(self.error(element, "mass", format!("{mass} is negative")));
        }
        let body_from_inertial = self.pose(element, None)?;
        let inertia = match (element.get("diaginertia"), element.get("fullinertia")) {
            (Some(_), Some(_)) => {
                return Err(self.error(
                    element,
                    "fullinertia",
                    "give diaginertia or fullinertia, not both".into(),
                ))
            }
            (Some(text), None) => {
                let d = self.numbers(element, "diaginertia", text, 3..=3)?;
                Matrix3::from_diagonal(&Vector3::new(d[0], d[1], d[2]))
            }
            (None, Some(text)) => {
                let has_orientation = ORIENTATIONS.iter().any(|k| element.get(k).is_some());
                if has_orientation {
                    return Err(self.error(
                        element,
                        "fullinertia",
                        "fullinertia is in the body frame: it takes no orientation".into(),
                    ));
                }
                let v = self.numbers(element, "fullinertia", text, 6..=6)?;
                Matrix3::new(v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2])
            }
            (None, None) => {
                return Err(self.error(
                    element,
                    "diaginertia",
                    "an <inertial> needs diaginertia or fullinertia".into(),
                ))
            }
        };
        let body = RigidBody::new(mass, Vector3::zeros(), inertia).transformed(&body_from_inertial);
        if !body.is_valid() {
            return Err(self.error(
                element,
                "-",
                "the inertia must have a non-negative diagonal".into(),
            ));
        }
        Ok(body)
    }

    /// The largest magnitude of a `lo hi` force range times `gear` (`None` for an empty
    /// range `0 0`, which MuJoCo reads as unlimited).
    pub(super) fn force_range(
        &self,
        element: &Element,
        attribute: &str,
        text: &str,
        gear: f64,
    ) -> Result<Option<f64>, RobotError> {
        let v = self.numbers(element, attribute, text, 2..=2)?;
        if v[0] > v[1] {
            return Err(self.error(
                element,
                attribute,
                format!("lower {} is above upper {}", v[0], v[1]),
            ));
        }
        let largest = v[0].abs().max(v[1].abs()) * gear.abs();
        Ok((largest > 0.0).then_some(largest))
    }

    /// The `<actuator>` section: each actuator with `joint="J"` and a force range limits J's
    /// effort (the smallest limit wins when several drive one joint, or with the joint's own
    /// `actuatorfrcrange`).
    pub(super) fn actuators(&mut self, section: &Element) -> Result<(), RobotError> {
        for element in section
            .children
            .iter()
            .filter(|c| ACTUATORS.contains(&c.name.as_str()))
        {
            let class = self.class_of(element, "main")?.to_string();
            let Some(joint) = self.value(element, &class, "joint").map(str::to_string) else {
                continue;
            };
            let limited = match self
                .value(element, &class, "forcelimited")
                .unwrap_or("auto")
            {
                "auto" => self.compiler.auto_limits,
                value => self.boolean(element, "forcelimited", value)?,
            };
            let Some(text) = self
                .value(element, &class, "forcerange")
                .map(str::to_string)
            else {
                continue;
            };
            if !limited {
                continue;
            }
            let gear = match self.value(element, &class, "gear") {
                Some(g) => self.numbers(element, "gear", g, 1..=6)?[0],
                None => 1.0,
            };
            let Some(effort) = self.force_range(element, "forcerange", &text, gear)? else {
                continue;
            };
            if let Some(&(body, k, _)) = self.joint_index.get(&joint) {
                let target = &mut self.bodies[body].joints[k];
                target.effort = Some(target.effort.map_or(effort, |e| e.min(effort)));
            }
        }
        Ok(())
    }
}
