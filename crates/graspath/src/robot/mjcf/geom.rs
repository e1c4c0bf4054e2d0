//! Geoms as collision shapes: MJCF's size conventions (half-sizes; radius and half-length;
//! `fromto`), visual-only geoms left out, unsupported kinds kept as skipped with the reason.

use super::dom::Element;
use super::parse::{Geom, GeomKind, Reader};
use super::values::z_onto;
use crate::geometry::shape::Shape;
use crate::robot::chain::unit_axis;
use crate::robot::error::RobotError;
use nalgebra::{Isometry3, Translation3, Vector3};

impl Reader<'_> {
    /// A colliding geom, or `None` for a visual-only one (`contype` and `conaffinity` both 0).
    pub(super) fn geom(
        &self,
        element: &Element,
        childclass: &str,
    ) -> Result<Option<Geom>, RobotError> {
        let class = self.class_of(element, childclass)?;
        let get = |key: &str| self.value(element, class, key);
        let mask = |key: &str| -> Result<i64, RobotError> {
            match get(key) {
                None => Ok(1),
                Some(text) => text
                    .trim()
                    .parse()
                    .map_err(|_| self.error(element, key, format!("'{text}' is not an integer"))),
            }
        };
        if mask("contype")? == 0 && mask("conaffinity")? == 0 {
            return Ok(None);
        }
        let mesh = get("mesh");
        let kind_name = get("type").unwrap_or(if mesh.is_some() { "mesh" } else { "sphere" });
        if mesh.is_some() && kind_name != "mesh" && get("size").is_none() {
            return Ok(Some(Geom {
                name: element.get("name").map(str::to_string),
                line: element.line,
                body_from_geom: self.pose(element, Some(class))?,
                kind: GeomKind::Skipped(format!(
                    "a {kind_name} fitted to a mesh (type=\"{kind_name}\" with mesh=) is not supported"
                )),
            }));
        }
        let size = match get("size") {
            Some(text) => self.numbers(element, "size", text, 1..=3)?,
            None => Vec::new(),
        };
        let fromto = match get("fromto") {
            Some(text) => Some(self.numbers(element, "fromto", text, 6..=6)?),
            None => None,
        };
        let mut body_from_geom = self.pose(element, Some(class))?;
        let need = |count: usize| -> Result<&[f64], RobotError> {
            if size.len() < count {
                Err(self.error(
                    element,
                    "size",
                    format!(
                        "a {kind_name} geom needs {count} size values, got {}",
                        size.len()
                    ),
                ))
            } else {
                Ok(&size[..count])
            }
        };
        let bad_size =
            |e: crate::geometry::shape::ShapeError| self.error(element, "size", e.to_string());
        // `fromto`: the geom is centred between the two points, its z axis along the segment
        // and pointing from the second point to the first (MuJoCo's compiler: the smallest
        // rotation taking z onto `from − to`).
        let mut half_length = None;
        if let Some(ft) = &fromto {
            if !matches!(kind_name, "capsule" | "cylinder" | "box") {
                return Err(self.error(
                    element,
                    "fromto",
                    format!("a {kind_name} geom takes no fromto"),
                ));
            }
            let (from, to) = (
                Vector3::new(ft[0], ft[1], ft[2]),
                Vector3::new(ft[3], ft[4], ft[5]),
            );
            let along = from - to;
            let z = unit_axis(&along).ok_or_else(|| {
                self.error(element, "fromto", "the two points are the same".into())
            })?;
            body_from_geom =
                Isometry3::from_parts(Translation3::from((from + to) / 2.0), z_onto(&z));
            half_length = Some(along.norm() / 2.0);
        }
        let shape = match kind_name {
            "sphere" => Shape::sphere(need(1)?[0]).map_err(bad_size)?,
            "capsule" | "cylinder" => {
                let (radius, half) = match half_length {
                    Some(h) => (need(1)?[0], h),
                    None => {
                        let s = need(2)?;
                        (s[0], s[1])
                    }
                };
                if kind_name == "capsule" {
                    Shape::capsule(radius, 2.0 * half).map_err(bad_size)?
                } else {
                    Shape::cylinder(radius, 2.0 * half).map_err(bad_size)?
                }
            }
            "box" => {
                let half = match half_length {
                    Some(h) => {
                        let s = need(2)?;
                        [s[0], s[1], h]
                    }
                    None => {
                        let s = need(3)?;
                        [s[0], s[1], s[2]]
                    }
                };
                Shape::cuboid(half.map(|h| 2.0 * h)).map_err(bad_size)?
            }
            "mesh" => {
                let Some(mesh) = mesh else {
                    return Err(self.error(element, "mesh", "a mesh geom needs a mesh attribute".into()));
                };
                let Some(asset) = self.meshes.get(mesh) else {
                    return Err(self.error(element, "mesh", format!("no <mesh name=\"{mesh}\"> in <asset>")));
                };
                let kind = match &asset.file {
                    Some(file) => GeomKind::Mesh {
                        file: file.clone(),
                        scale: asset.scale,
                    },
                    None => GeomKind::Skipped(format!(
                        "mesh '{mesh}' has inline vertex data, not a file"
                    )),
                };
                return Ok(Some(Geom {
                    name: element.get("name").map(str::to_string),
                    line: element.line,
                    body_from_geom,
                    kind,
                }));
            }
            "plane" | "hfield" | "ellipsoid" | "sdf" => {
                return Ok(Some(Geom {
                    name: element.get("name").map(str::to_string),
                    line: element.line,
                    body_from_geom,
                    kind: GeomKind::Skipped(format!("{kind_name} geoms are not collision shapes here")),
                }))
            }
            other => {
                return Err(self.error(
                    element,
                    "type",
                    format!("'{other}' is not a geom type (plane, hfield, sphere, capsule, ellipsoid, cylinder, box, mesh, sdf)"),
                ))
            }
        };
        Ok(Some(Geom {
            name: element.get("name").map(str::to_string),
            line: element.line,
            body_from_geom,
            kind: GeomKind::Shape(shape),
        }))
    }
}
