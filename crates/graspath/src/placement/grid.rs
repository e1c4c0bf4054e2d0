//! The grid of object placements a map sweeps: x and y (and optionally z and yaw) of the
//! object's start pose in the world frame.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// Largest number of placements one map may ask for (the product of the axes' counts).
pub const MAX_PLACEMENTS: usize = 1_000_000;

/// An axis of the grid given on the command line or in code that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct AxisError {
    /// The axis (`--x`, `--yaw-deg`, …).
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl crate::fault::Classify for AxisError {
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        Some(crate::fault::ErrorKind::Content)
    }

    fn field(&self) -> Option<&str> {
        Some(&self.field)
    }
}

/// `count` evenly spaced values from `start` to `end`, both included (one value: `start`).
/// The unit is the axis's: metres for x, y, z; radians for yaw in code, degrees on the command
/// line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridAxis {
    /// The first value.
    pub start: f64,
    /// The last value (equal to `start` when `count` is 1).
    pub end: f64,
    /// How many values (≥ 1).
    pub count: usize,
}

impl GridAxis {
    /// A checked axis; `field` names it in errors.
    pub fn new(start: f64, end: f64, count: usize, field: &str) -> Result<Self, AxisError> {
        let err = |message: String| AxisError {
            field: field.to_string(),
            message,
        };
        if !(start.is_finite() && end.is_finite()) {
            return Err(err(format!("start {start} and end {end} must be finite")));
        }
        if count == 0 {
            return Err(err("the count must be at least 1".into()));
        }
        if count > MAX_PLACEMENTS {
            return Err(err(format!(
                "{count} values are more than the {MAX_PLACEMENTS} placements a map may have"
            )));
        }
        if count == 1 && start != end {
            return Err(err(format!(
                "one value cannot span {start}..{end}; give START:END:COUNT with COUNT ≥ 2 or \
                 a single value"
            )));
        }
        Ok(Self { start, end, count })
    }

    /// One value (`count` 1).
    pub fn single(value: f64, field: &str) -> Result<Self, AxisError> {
        Self::new(value, value, 1, field)
    }

    /// Parses `START:END:COUNT` or a single value `V`; `field` names the axis in errors.
    pub fn parse(text: &str, field: &str) -> Result<Self, AxisError> {
        let err = |message: String| AxisError {
            field: field.to_string(),
            message,
        };
        let number = |part: &str, what: &str| -> Result<f64, AxisError> {
            part.trim()
                .parse::<f64>()
                .map_err(|_| err(format!("{what} '{part}' is not a number")))
        };
        let parts: Vec<&str> = text.split(':').collect();
        match parts.as_slice() {
            [v] => Self::single(number(v, "value")?, field),
            [start, end, count] => {
                let count = count
                    .trim()
                    .parse::<usize>()
                    .map_err(|_| err(format!("count '{count}' is not a whole number")))?;
                Self::new(number(start, "start")?, number(end, "end")?, count, field)
            }
            _ => Err(err(format!(
                "'{text}' is not START:END:COUNT (e.g. 0.5:0.9:10) or a single value"
            ))),
        }
    }

    /// The values, `start + k (end − start) / (count − 1)`, the last exactly `end`.
    pub fn values(&self) -> Vec<f64> {
        if self.count == 1 {
            return vec![self.start];
        }
        let n = (self.count - 1) as f64;
        (0..self.count)
            .map(|k| {
                if k + 1 == self.count {
                    self.end
                } else {
                    self.start + (self.end - self.start) * (k as f64 / n)
                }
            })
            .collect()
    }

    /// The same axis with every value multiplied by `factor` (degrees to radians).
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            start: self.start * factor,
            end: self.end * factor,
            count: self.count,
        }
    }
}

/// Where the object starts, swept: its origin's world x and y (m), optionally z (m; else the
/// task's), and optionally a yaw (rad) about the world vertical through its origin, applied
/// on top of the task's start orientation (else none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacementGrid {
    /// World x of the object's origin (m).
    pub x: GridAxis,
    /// World y of the object's origin (m).
    pub y: GridAxis,
    /// World z of the object's origin (m); `None`: the task's.
    pub z: Option<GridAxis>,
    /// Extra yaw about the world z axis (rad); `None`: the task's orientation.
    pub yaw: Option<GridAxis>,
}

/// One placement of the grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Position in the grid: (x, y, z, yaw) indices (0 for an axis not swept).
    pub index: [usize; 4],
    /// The object's start pose, `world_from_object`.
    pub world_from_object: Isometry3<f64>,
    /// The extra yaw about the world vertical (rad), 0 when yaw is not swept.
    pub yaw: f64,
}

impl PlacementGrid {
    /// How many placements (checked against [`MAX_PLACEMENTS`] by [`placements`](Self::placements)).
    pub fn len(&self) -> usize {
        [Some(self.x), Some(self.y), self.z, self.yaw]
            .iter()
            .flatten()
            .fold(1usize, |n, a| n.saturating_mul(a.count))
    }

    /// Always false: every axis has at least one value.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Every placement, the task's start pose `world_from_object` moved to it: x fastest, then
    /// y, then yaw, then z (so `placements[((iz · n_yaw + iyaw) · n_y + iy) · n_x + ix]`).
    pub fn placements(
        &self,
        world_from_object: &Isometry3<f64>,
    ) -> Result<Vec<Placement>, AxisError> {
        let n = self.len();
        if n > MAX_PLACEMENTS {
            return Err(AxisError {
                field: "grid".into(),
                message: format!(
                    "{n} placements are more than the limit {MAX_PLACEMENTS}; use fewer values"
                ),
            });
        }
        let xs = self.x.values();
        let ys = self.y.values();
        let zs = self
            .z
            .map_or_else(|| vec![world_from_object.translation.z], |a| a.values());
        let yaws = self.yaw.map_or_else(|| vec![0.0], |a| a.values());
        let mut out = Vec::with_capacity(n);
        for (iz, &z) in zs.iter().enumerate() {
            for (iyaw, &yaw) in yaws.iter().enumerate() {
                let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw)
                    * world_from_object.rotation;
                for (iy, &y) in ys.iter().enumerate() {
                    for (ix, &x) in xs.iter().enumerate() {
                        out.push(Placement {
                            index: [ix, iy, iz, iyaw],
                            world_from_object: Isometry3::from_parts(
                                Translation3::new(x, y, z),
                                rotation,
                            ),
                            yaw,
                        });
                    }
                }
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_parse_and_space_their_values_evenly() {
        let a = GridAxis::parse("0.5:0.9:5", "--x").unwrap();
        let v = a.values();
        assert_eq!(v.len(), 5);
        assert_eq!(v[0], 0.5);
        assert_eq!(v[4], 0.9);
        for (k, value) in v.iter().enumerate() {
            assert!((value - (0.5 + 0.1 * k as f64)).abs() < 1e-15);
        }
        assert_eq!(
            GridAxis::parse(" -0.2 ", "--y").unwrap().values(),
            vec![-0.2]
        );
        for bad in [
            "", "a:1:2", "0:1:0", "0:1", "0:1:x", "0:1:1", "0:inf:3", "0:1:2:3",
        ] {
            let e = GridAxis::parse(bad, "--z").unwrap_err();
            assert_eq!(e.field, "--z", "{bad}");
        }
    }

    #[test]
    fn placements_run_x_fastest_and_turn_about_the_world_vertical() {
        let grid = PlacementGrid {
            x: GridAxis::new(0.6, 0.8, 3, "x").unwrap(),
            y: GridAxis::new(-0.1, 0.1, 2, "y").unwrap(),
            z: None,
            yaw: Some(GridAxis::new(0.0, std::f64::consts::FRAC_PI_2, 2, "yaw").unwrap()),
        };
        let start = Isometry3::translation(0.0, 0.0, -0.1);
        let p = grid.placements(&start).unwrap();
        assert_eq!(p.len(), 12);
        assert_eq!(grid.len(), 12);
        let last = &p[11];
        assert_eq!(last.index, [2, 1, 0, 1]);
        assert_eq!(
            last.world_from_object.translation.vector,
            Vector3::new(0.8, 0.1, -0.1)
        );
        // A quarter turn about world z maps the object's x axis to world y.
        let x_axis = last.world_from_object.rotation * Vector3::x();
        assert!((x_axis - Vector3::y()).norm() < 1e-15);
        assert_eq!(p[4].index, [1, 1, 0, 0]);
    }
}
