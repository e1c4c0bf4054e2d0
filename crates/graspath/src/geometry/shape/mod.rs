//! The one shape vocabulary: box, cylinder, sphere, capsule, T-shape, convex mesh and triangle
//! mesh, each in its **own frame** (metres), with the operations every consumer needs:
//!
//! * [`Shape::signed_distance`] from a point (negative inside),
//! * [`Shape::support`]: the point of the shape farthest along a direction,
//! * [`Shape::aabb`] (shape frame) and [`Shape::aabb_at`] (under a pose `a_from_shape`),
//! * [`Shape::proximity`]: the signed distance with the closest surface point, and
//!   [`Shape::bounding_radius`] about the shape origin (the grasp model's contact and collision
//!   terms use both).
//!
//! Frames (all centred on the origin unless said otherwise, `z` the shape's axis):
//! * box: edge lengths `size` along `x, y, z`;
//! * cylinder: `radius`, `length` along `z` (capped);
//! * sphere: `radius`;
//! * capsule: the points within `radius` of the segment of `length` along `z`
//!   (total extent along `z` is `length + 2·radius`);
//! * T-shape: see [`TShape`] (origin at the bar's centre, stem along `+z`);
//! * convex mesh: the convex hull of its points, in their own coordinates;
//! * triangle mesh: vertices and triangles in their own coordinates.
//!
//! In files (task-file style, every struct `deny_unknown_fields`, sizes checked on reading):
//!
//! ```yaml
//! shape: { box: { size: [0.06, 0.06, 0.20] } }
//! shape: { cylinder: { radius: 0.03, length: 0.2 } }
//! shape: { sphere: { radius: 0.05 } }
//! shape: { capsule: { radius: 0.05, length: 0.3 } }
//! shape: { t_shape: { bar: [0.08, 0.24, 0.03], stem: { cylinder: { radius: 0.02, length: 0.12 } } } }
//! shape: { convex_mesh: { points: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]] } }
//! shape: { triangle_mesh: { vertices: [[...], ...], triangles: [[0, 1, 2], ...] } }
//! ```
//!
//! ```
//! use graspath::geometry::shape::Shape;
//! use nalgebra::{Point3, Vector3};
//! let shape: Shape = serde_json::from_str(r#"{"capsule": {"radius": 0.05, "length": 0.3}}"#)?;
//! // 0.1 m beside the segment: 0.05 m outside the surface.
//! assert!((shape.signed_distance(&Point3::new(0.1, 0.0, 0.1)) - 0.05).abs() < 1e-15);
//! // The top of the upper cap.
//! assert_eq!(shape.support(&Vector3::z()), Point3::new(0.0, 0.0, 0.2));
//! # Ok::<(), serde_json::Error>(())
//! ```

mod hull;
mod mass;
mod mesh;
mod primitive;

pub use mass::SolidMass;
pub use mesh::{ConvexMesh, TriMesh};
pub use primitive::{Capsule, Cuboid, Cylinder, Sphere, Stem, TShape};

use nalgebra::{Isometry3, Point3, Vector3};

/// An invalid shape: the field (in file spelling, e.g. `box.size[1]`) and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShapeError {
    /// A length that must be positive and finite is not.
    #[error("{field}: must be a positive finite length in metres, got {value}")]
    NotPositive {
        /// The field, e.g. `cylinder.radius`.
        field: String,
        /// The value given.
        value: f64,
    },
    /// A coordinate is NaN or infinite.
    #[error("{field}: must be finite, got {value}")]
    NotFinite {
        /// The field, e.g. `convex_mesh.points[3]`.
        field: String,
        /// The value given.
        value: f64,
    },
    /// A shape's fields do not describe one shape (e.g. a T-shape without a stem).
    #[error("{field}: {message}")]
    Malformed {
        /// The shape's field, e.g. `t_shape`.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A mesh cannot be used (too few points, no volume, an index out of range, ...).
    #[error("{field}: {message}")]
    BadMesh {
        /// The field, e.g. `triangle_mesh.triangles[7]`.
        field: String,
        /// What is wrong.
        message: String,
    },
}

impl crate::fault::Classify for ShapeError {
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        Some(crate::fault::ErrorKind::Content)
    }

    fn field(&self) -> Option<&str> {
        match self {
            Self::NotPositive { field, .. }
            | Self::NotFinite { field, .. }
            | Self::Malformed { field, .. }
            | Self::BadMesh { field, .. } => Some(field),
        }
    }
}

/// The largest distance of `points` from the origin (0 for none).
fn farthest(points: &[Point3<f64>]) -> f64 {
    points.iter().map(|v| v.coords.norm()).fold(0.0, f64::max)
}

/// Checks a positive finite length.
pub(crate) fn positive(field: impl FnOnce() -> String, value: f64) -> Result<f64, ShapeError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ShapeError::NotPositive {
            field: field(),
            value,
        })
    }
}

/// An axis-aligned box `[min, max]` (m), in whichever frame the call names.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// The corner with the smallest coordinates.
    pub min: Point3<f64>,
    /// The corner with the largest coordinates.
    pub max: Point3<f64>,
}

impl Aabb {
    /// Whether `p` lies inside or on the box, with a tolerance `tol` (m).
    pub fn contains(&self, p: &Point3<f64>, tol: f64) -> bool {
        (0..3).all(|k| p[k] >= self.min[k] - tol && p[k] <= self.max[k] + tol)
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.inf(&other.min),
            max: self.max.sup(&other.max),
        }
    }
}

/// The closest point of a shape's surface to a query point, with the signed distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Proximity {
    /// Signed distance (m): positive outside, negative inside (minus the penetration depth);
    /// bit for bit [`Shape::signed_distance`].
    pub signed_distance: f64,
    /// The closest surface point (shape frame, m); see [`Shape::proximity`] for the inside of
    /// a T-shape.
    pub closest: Point3<f64>,
}

/// A solid (or, for an open triangle mesh, a surface) in its own frame (m). See the module
/// documentation for each variant's frame and file spelling.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    /// A box centred on the origin (`{box: {size: [x, y, z]}}`).
    Box(Cuboid),
    /// A capped cylinder along `z`, centred (`{cylinder: {radius, length}}`).
    Cylinder(Cylinder),
    /// A sphere about the origin (`{sphere: {radius}}`).
    Sphere(Sphere),
    /// A capsule along `z`, centred (`{capsule: {radius, length}}`).
    Capsule(Capsule),
    /// A bar with a stem (`{t_shape: {bar, stem}}`).
    TShape(TShape),
    /// The convex hull of points (`{convex_mesh: {points}}`).
    ConvexMesh(ConvexMesh),
    /// A triangle mesh (`{triangle_mesh: {vertices, triangles}}`).
    TriangleMesh(TriMesh),
}

impl Shape {
    /// A box of edge lengths `size` (m).
    pub fn cuboid(size: [f64; 3]) -> Result<Self, ShapeError> {
        Ok(Shape::Box(Cuboid::new(size)?))
    }

    /// A cylinder of `radius` and `length` along `z` (m).
    pub fn cylinder(radius: f64, length: f64) -> Result<Self, ShapeError> {
        Ok(Shape::Cylinder(Cylinder::new(radius, length)?))
    }

    /// A sphere of `radius` (m).
    pub fn sphere(radius: f64) -> Result<Self, ShapeError> {
        Ok(Shape::Sphere(Sphere::new(radius)?))
    }

    /// A capsule of `radius` about a segment of `length` along `z` (m).
    pub fn capsule(radius: f64, length: f64) -> Result<Self, ShapeError> {
        Ok(Shape::Capsule(Capsule::new(radius, length)?))
    }

    /// The file name of the variant: `box`, `cylinder`, `sphere`, `capsule`, `t_shape`,
    /// `convex_mesh` or `triangle_mesh`.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Box(_) => "box",
            Shape::Cylinder(_) => "cylinder",
            Shape::Sphere(_) => "sphere",
            Shape::Capsule(_) => "capsule",
            Shape::TShape(_) => "t_shape",
            Shape::ConvexMesh(_) => "convex_mesh",
            Shape::TriangleMesh(_) => "triangle_mesh",
        }
    }

    /// The signed distance (m) from `p` (shape frame) to the surface: positive outside,
    /// negative inside, zero on the surface.
    ///
    /// Exact for every variant except inside a T-shape, where it is `min` of the bar's and the
    /// stem's distances: the sign is exact, and the depth is never more than the true depth
    /// (see [`TShape`]). An open triangle mesh has no inside: its distance is unsigned (see
    /// [`TriMesh`]).
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        match self {
            Shape::Box(s) => s.signed_distance(p),
            Shape::Cylinder(s) => s.signed_distance(p),
            Shape::Sphere(s) => s.signed_distance(p),
            Shape::Capsule(s) => s.signed_distance(p),
            Shape::TShape(s) => s.signed_distance(p),
            Shape::ConvexMesh(s) => s.signed_distance(p),
            Shape::TriangleMesh(s) => s.signed_distance(p),
        }
    }

    /// A point of the shape (shape frame, m) that maximises `direction · point`. `direction`
    /// need not be unit; for a zero direction some point of the shape is returned. Where the
    /// maximiser is not unique (a face or an edge facing `direction`), a vertex or boundary
    /// point of it is returned.
    pub fn support(&self, direction: &Vector3<f64>) -> Point3<f64> {
        match self {
            Shape::Box(s) => s.support(direction),
            Shape::Cylinder(s) => s.support(direction),
            Shape::Sphere(s) => s.support(direction),
            Shape::Capsule(s) => s.support(direction),
            Shape::TShape(s) => s.support(direction),
            Shape::ConvexMesh(s) => s.support(direction),
            Shape::TriangleMesh(s) => s.support(direction),
        }
    }

    /// The signed distance of `p` (shape frame) together with the closest point of the
    /// surface (shape frame, m). The distance is bit for bit [`Shape::signed_distance`].
    ///
    /// The closest point is exact for every variant, except inside a T-shape, where it is the
    /// closest point of the part (bar or stem) whose signed distance is the smaller: it may lie
    /// on a face of that part that the other part covers (as the depth, see [`TShape`]).
    pub fn proximity(&self, p: &Point3<f64>) -> Proximity {
        match self {
            Shape::Box(s) => s.proximity(p),
            Shape::Cylinder(s) => s.proximity(p),
            Shape::Sphere(s) => s.proximity(p),
            Shape::Capsule(s) => s.proximity(p),
            Shape::TShape(s) => s.proximity(p),
            Shape::ConvexMesh(s) => s.proximity(p),
            Shape::TriangleMesh(s) => s.proximity(p),
        }
    }

    /// The radius (m) of a sphere about the shape origin that contains the shape: the largest
    /// distance of a point of the shape from the origin.
    pub fn bounding_radius(&self) -> f64 {
        match self {
            Shape::Box(s) => s.half_extents().norm(),
            Shape::Cylinder(s) => s.radius().hypot(s.length() / 2.0),
            Shape::Sphere(s) => s.radius(),
            Shape::Capsule(s) => s.length() / 2.0 + s.radius(),
            Shape::TShape(s) => s.bounding_radius(),
            Shape::ConvexMesh(s) => farthest(s.hull_vertices()),
            Shape::TriangleMesh(s) => farthest(s.vertices()),
        }
    }

    /// The tight axis-aligned bounding box in the shape frame.
    pub fn aabb(&self) -> Aabb {
        self.aabb_at(&Isometry3::identity())
    }

    /// The tight axis-aligned bounding box, in frame `a`, of the shape placed at `a_from_shape`.
    pub fn aabb_at(&self, a_from_shape: &Isometry3<f64>) -> Aabb {
        let mut min = Point3::origin();
        let mut max = Point3::origin();
        for k in 0..3 {
            let axis = Vector3::ith(k, 1.0);
            let local = a_from_shape.rotation.inverse_transform_vector(&axis);
            max[k] = (a_from_shape * self.support(&local))[k];
            min[k] = (a_from_shape * self.support(&-local))[k];
        }
        Aabb { min, max }
    }
}
