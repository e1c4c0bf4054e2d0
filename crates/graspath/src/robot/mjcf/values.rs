//! Attribute values: numbers (finite, counted), booleans, angles in the compiler's unit, and
//! poses (`pos` with one of `quat`, `axisangle`, `euler`, `xyaxes`, `zaxis`).

use super::defaults::ORIENTATIONS;
use super::dom::Element;
use super::parse::Reader;
use crate::robot::chain::unit_axis;
use crate::robot::error::RobotError;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3};

impl Reader<'_> {
    pub(super) fn boolean(
        &self,
        element: &Element,
        attribute: &str,
        value: &str,
    ) -> Result<bool, RobotError> {
        match value {
            "true" => Ok(true),
            "false" => Ok(false),
            other => Err(self.error(
                element,
                attribute,
                format!("'{other}' is neither true nor false"),
            )),
        }
    }

    /// `count` finite numbers (any count within `counts`), or an error naming the attribute.
    pub(super) fn numbers(
        &self,
        element: &Element,
        key: &str,
        text: &str,
        counts: std::ops::RangeInclusive<usize>,
    ) -> Result<Vec<f64>, RobotError> {
        let mut out = Vec::new();
        for word in text.split_ascii_whitespace() {
            let value: f64 = word.parse().map_err(|_| {
                self.error(
                    element,
                    key,
                    format!("'{word}' is not a number (in \"{text}\")"),
                )
            })?;
            if !value.is_finite() {
                return Err(self.error(
                    element,
                    key,
                    format!("must be finite, got {word} (in \"{text}\")"),
                ));
            }
            out.push(value);
            if out.len() > *counts.end() {
                break;
            }
        }
        if !counts.contains(&out.len()) {
            let expected = if counts.start() == counts.end() {
                counts.start().to_string()
            } else {
                format!("{} to {}", counts.start(), counts.end())
            };
            return Err(self.error(
                element,
                key,
                format!("expected {expected} numbers, got \"{text}\""),
            ));
        }
        Ok(out)
    }

    pub(super) fn vector(
        &self,
        element: &Element,
        key: &str,
        text: &str,
    ) -> Result<Vector3<f64>, RobotError> {
        let v = self.numbers(element, key, text, 3..=3)?;
        Ok(Vector3::new(v[0], v[1], v[2]))
    }

    pub(super) fn angle(&self, value: f64) -> f64 {
        if self.compiler.degrees {
            value.to_radians()
        } else {
            value
        }
    }

    /// The one orientation attribute an element gives itself (`quat`, `axisangle`, `euler`,
    /// `xyaxes` or `zaxis`), if any; two are an error, as in MuJoCo.
    pub(super) fn orientation_attribute(
        &self,
        element: &Element,
    ) -> Result<Option<&'static str>, RobotError> {
        let mut given = ORIENTATIONS
            .into_iter()
            .filter(|k| element.get(k).is_some());
        let first = given.next();
        if let (Some(first), Some(second)) = (first, given.next()) {
            return Err(self.error(
                element,
                second,
                format!("give one orientation, not {first} and {second}"),
            ));
        }
        Ok(first)
    }

    /// `pos` and the orientation of a body, geom or frame, each as written on the element or
    /// else (when `class` is given) from its default class. As in MuJoCo's compiler, the
    /// element's own orientation replaces the class's, whatever kind each is (a `quat` on a
    /// geom wins over its class's `euler`).
    pub(super) fn pose(
        &self,
        element: &Element,
        class: Option<&str>,
    ) -> Result<Isometry3<f64>, RobotError> {
        let get = |key: &str| match class {
            Some(class) => self.value(element, class, key),
            None => element.get(key),
        };
        let pos = match get("pos") {
            Some(text) => self.vector(element, "pos", text)?,
            None => Vector3::zeros(),
        };
        // The class gives at most one orientation (checked where the class is read).
        let key = match self.orientation_attribute(element)? {
            Some(key) => Some(key),
            None => class.and_then(|_| ORIENTATIONS.into_iter().find(|k| get(k).is_some())),
        };
        let rotation = match key {
            None => UnitQuaternion::identity(),
            Some(key) => self.orientation(element, key, get(key).unwrap_or_default())?,
        };
        Ok(Isometry3::from_parts(Translation3::from(pos), rotation))
    }

    pub(super) fn orientation(
        &self,
        element: &Element,
        key: &str,
        text: &str,
    ) -> Result<UnitQuaternion<f64>, RobotError> {
        let zero = |what: &str| self.error(element, key, format!("{what} is zero: \"{text}\""));
        match key {
            "quat" => {
                let v = self.numbers(element, key, text, 4..=4)?;
                let mut q = nalgebra::Quaternion::new(v[0], v[1], v[2], v[3]);
                if !q.norm_squared().is_finite() {
                    // Entries so large that the norm overflows: the same rotation, scaled down.
                    q = q / q.coords.amax();
                }
                if q.norm() < 1e-12 {
                    return Err(zero("the quaternion"));
                }
                Ok(UnitQuaternion::from_quaternion(q))
            }
            "axisangle" => {
                let v = self.numbers(element, key, text, 4..=4)?;
                let axis =
                    unit_axis(&Vector3::new(v[0], v[1], v[2])).ok_or_else(|| zero("the axis"))?;
                Ok(UnitQuaternion::from_axis_angle(
                    &Unit::new_unchecked(axis),
                    self.angle(v[3]),
                ))
            }
            "euler" => {
                let v = self.numbers(element, key, text, 3..=3)?;
                let mut q = UnitQuaternion::identity();
                for (axis, angle) in self.compiler.euler_seq.iter().zip(&v) {
                    let unit = match axis.to_ascii_lowercase() {
                        b'x' => Vector3::x_axis(),
                        b'y' => Vector3::y_axis(),
                        _ => Vector3::z_axis(),
                    };
                    let turn = UnitQuaternion::from_axis_angle(&unit, self.angle(*angle));
                    // Lower case: about the moving (already turned) axes; upper: the fixed ones.
                    q = if axis.is_ascii_lowercase() {
                        q * turn
                    } else {
                        turn * q
                    };
                }
                Ok(q)
            }
            "xyaxes" => {
                let v = self.numbers(element, key, text, 6..=6)?;
                let x = unit_axis(&Vector3::new(v[0], v[1], v[2])).ok_or_else(|| zero("x"))?;
                let y = Vector3::new(v[3], v[4], v[5]);
                let y = unit_axis(&(y - x * x.dot(&y)))
                    .ok_or_else(|| zero("the part of y orthogonal to x"))?;
                let z = x.cross(&y);
                let m = Matrix3::from_columns(&[x, y, z]);
                Ok(UnitQuaternion::from_rotation_matrix(
                    &Rotation3::from_matrix_unchecked(m),
                ))
            }
            _ => {
                let v = self.vector(element, key, text)?;
                let z = unit_axis(&v).ok_or_else(|| zero("the axis"))?;
                Ok(z_onto(&z))
            }
        }
    }
}

/// The smallest rotation taking `z` onto the unit vector `axis` (half a turn about `x` for `−z`),
/// as MuJoCo's `zaxis` and `fromto`.
pub(super) fn z_onto(axis: &Vector3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::rotation_between(&Vector3::z(), axis).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    })
}
