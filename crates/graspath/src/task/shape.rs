//! Primitive object shapes, in the object frame (metres).

use nalgebra::{Point3, Vector3};

/// A primitive object shape. The object frame is at the shape's centre (for the T-shape: the
/// centre of the bar), with `z` up when the object stands on a table. In a task file:
/// `{box: {size: [x, y, z]}}`, `{cylinder: {radius, length}}` or
/// `{t_shape: {bar, handle_radius, handle_length}}`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ObjectShape {
    /// A box with edge lengths along the object's `x`, `y`, `z` axes.
    Box {
        /// Edge lengths (m).
        size: [f64; 3],
    },
    /// A cylinder with its axis along the object's `z`.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Length along `z` (m).
        length: f64,
    },
    /// A T-shaped object: a horizontal bar (a box centred on the origin) with a cylindrical
    /// handle standing on it along `+z`.
    TShape {
        /// Bar edge lengths along `x`, `y`, `z` (m).
        bar: [f64; 3],
        /// Handle radius (m).
        handle_radius: f64,
        /// Handle length above the bar's top face (m).
        handle_length: f64,
    },
}

impl ObjectShape {
    /// Whether every dimension is finite and positive.
    pub fn is_valid(&self) -> bool {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        match *self {
            ObjectShape::Box { size } => size.iter().all(|&v| positive(v)),
            ObjectShape::Cylinder { radius, length } => positive(radius) && positive(length),
            ObjectShape::TShape {
                bar,
                handle_radius,
                handle_length,
            } => {
                bar.iter().all(|&v| positive(v))
                    && positive(handle_radius)
                    && positive(handle_length)
            }
        }
    }

    /// The axis-aligned bounding box in the object frame, `(min, max)`.
    pub fn bounds(&self) -> (Point3<f64>, Point3<f64>) {
        match *self {
            ObjectShape::Box { size } => {
                let h = Vector3::from(size) / 2.0;
                (Point3::from(-h), Point3::from(h))
            }
            ObjectShape::Cylinder { radius, length } => (
                Point3::new(-radius, -radius, -length / 2.0),
                Point3::new(radius, radius, length / 2.0),
            ),
            ObjectShape::TShape {
                bar, handle_length, ..
            } => (
                Point3::new(-bar[0] / 2.0, -bar[1] / 2.0, -bar[2] / 2.0),
                Point3::new(bar[0] / 2.0, bar[1] / 2.0, bar[2] / 2.0 + handle_length),
            ),
        }
    }

    /// The signed distance (m) from a point in the object frame to the surface: negative inside.
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        fn box_distance(p: &Vector3<f64>, half: &Vector3<f64>) -> f64 {
            let q = p.abs() - half;
            let outside = q.map(|v| v.max(0.0)).norm();
            outside + q.max().min(0.0)
        }
        fn cylinder_distance(p: &Vector3<f64>, radius: f64, half_length: f64) -> f64 {
            let radial = (p.x * p.x + p.y * p.y).sqrt() - radius;
            let axial = p.z.abs() - half_length;
            let outside = (radial.max(0.0).powi(2) + axial.max(0.0).powi(2)).sqrt();
            outside + radial.max(axial).min(0.0)
        }
        match *self {
            ObjectShape::Box { size } => box_distance(&p.coords, &(Vector3::from(size) / 2.0)),
            ObjectShape::Cylinder { radius, length } => {
                cylinder_distance(&p.coords, radius, length / 2.0)
            }
            ObjectShape::TShape {
                bar,
                handle_radius,
                handle_length,
            } => {
                let bar_d = box_distance(&p.coords, &(Vector3::from(bar) / 2.0));
                let centre = Vector3::new(0.0, 0.0, bar[2] / 2.0 + handle_length / 2.0);
                let handle_d =
                    cylinder_distance(&(p.coords - centre), handle_radius, handle_length / 2.0);
                bar_d.min(handle_d)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_distances_of_known_points() {
        let b = ObjectShape::Box {
            size: [0.2, 0.4, 0.6],
        };
        assert!((b.signed_distance(&Point3::origin()) + 0.1).abs() < 1e-15);
        assert!((b.signed_distance(&Point3::new(0.2, 0.0, 0.0)) - 0.1).abs() < 1e-15);
        assert!(
            (b.signed_distance(&Point3::new(0.4, 0.6, 0.3)) - (0.09f64 + 0.16).sqrt()).abs()
                < 1e-12
        );
        let c = ObjectShape::Cylinder {
            radius: 0.05,
            length: 0.2,
        };
        assert!((c.signed_distance(&Point3::new(0.0, 0.15, 0.0)) - 0.1).abs() < 1e-15);
        assert!((c.signed_distance(&Point3::new(0.0, 0.0, 0.0)) + 0.05).abs() < 1e-15);
        let t = ObjectShape::TShape {
            bar: [0.1, 0.3, 0.04],
            handle_radius: 0.02,
            handle_length: 0.1,
        };
        assert!(
            t.signed_distance(&Point3::new(0.0, 0.0, 0.07)) < 0.0,
            "inside the handle"
        );
        assert!(
            t.signed_distance(&Point3::new(0.0, 0.1, 0.07)) > 0.0,
            "beside the handle"
        );
    }
}
