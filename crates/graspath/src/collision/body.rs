//! A rigid body ready for collision queries: its geometry in its own frame (converted once for
//! the exact queries) and a bounding sphere for the cheap ones.

use super::bridge;
use super::CollisionError;
use crate::geometry::shape::Shape;
use nalgebra::{Isometry3, IsometryMatrix3, Point3};
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::SharedShape;

/// The most points a cloud obstacle may have (each becomes a sphere).
pub const MAX_OBSTACLE_POINTS: usize = 2_000_000;

/// What a body is made of.
#[derive(Debug, Clone, PartialEq)]
pub enum BodyKind {
    /// A solid: one of the shape vocabulary's solids.
    Solid(Shape),
    /// A triangle mesh taken as a surface: a body wholly inside a closed mesh touches nothing
    /// until it crosses the surface.
    Surface(Shape),
    /// Everything below the plane `z = height` (m) of the body frame: an infinite table.
    HalfSpace {
        /// The plane's height (m).
        height: f64,
    },
    /// Points, each the centre of a sphere of `radius` (m): a scanned scene.
    Points {
        /// The centres, body frame (m).
        points: std::sync::Arc<Vec<Point3<f64>>>,
        /// The spheres' radius (m).
        radius: f64,
    },
}

/// A rigid body in its own frame (m), with a name for messages (`table`, `obstacle wall`,
/// `link left_wrist`, `object`).
#[derive(Clone)]
pub struct Body {
    name: String,
    kind: BodyKind,
    geometry: SharedShape,
    /// Where `geometry` sits in the body frame (a quarter turn for cylinders, which parry
    /// builds along `y`).
    body_from_geometry: Pose,
    /// Bounding sphere, body frame (m).
    centre: Point3<f64>,
    radius: f64,
}

impl std::fmt::Debug for Body {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Body")
            .field("name", &self.name)
            .field("kind", &self.kind)
            .field("centre", &self.centre)
            .field("radius", &self.radius)
            .finish_non_exhaustive()
    }
}

impl Body {
    /// A body of one of the vocabulary's shapes (a triangle mesh is a surface, every other
    /// shape a solid).
    pub fn from_shape(name: impl Into<String>, shape: &Shape) -> Self {
        let aabb = shape.aabb();
        let centre = nalgebra::center(&aabb.min, &aabb.max);
        let radius = match shape {
            Shape::Sphere(s) => s.radius(),
            Shape::ConvexMesh(m) => max_distance(&centre, m.hull_vertices()),
            Shape::TriangleMesh(m) => max_distance(&centre, m.vertices()),
            _ => (aabb.max - aabb.min).norm() / 2.0,
        };
        let kind = match shape {
            Shape::TriangleMesh(_) => BodyKind::Surface(shape.clone()),
            _ => BodyKind::Solid(shape.clone()),
        };
        let (body_from_geometry, geometry) = bridge::shape(shape);
        Self {
            name: name.into(),
            kind,
            geometry,
            body_from_geometry,
            centre,
            radius,
        }
    }

    /// A body made of spheres of `radius` (m) about `points` (body frame): a scanned scene as
    /// obstacles. `what` names the input in errors.
    pub fn from_points(
        name: impl Into<String>,
        points: &[Point3<f64>],
        radius: f64,
        what: &str,
    ) -> Result<Self, CollisionError> {
        let bad = |message: String| CollisionError::BadBody {
            what: what.to_string(),
            message,
        };
        if !(radius.is_finite() && radius > 0.0) {
            return Err(bad(format!(
                "radius: must be a positive finite length in metres, got {radius}"
            )));
        }
        if points.is_empty() {
            return Err(bad("the cloud has no points".into()));
        }
        if points.len() > MAX_OBSTACLE_POINTS {
            return Err(bad(format!(
                "{} points; at most {MAX_OBSTACLE_POINTS} may be used as obstacles",
                points.len()
            )));
        }
        if let Some(i) = points
            .iter()
            .position(|p| !p.coords.iter().all(|v| v.is_finite()))
        {
            return Err(bad(format!("point {i} is not finite")));
        }
        let (mut min, mut max) = (points[0], points[0]);
        for p in points {
            min = min.inf(p);
            max = max.sup(p);
        }
        let centre = nalgebra::center(&min, &max);
        let ball = SharedShape::ball(radius);
        let parts = points
            .iter()
            .map(|p| (Pose::from_translation(bridge::point(p)), ball.clone()))
            .collect();
        Ok(Self {
            name: name.into(),
            kind: BodyKind::Points {
                points: std::sync::Arc::new(points.to_vec()),
                radius,
            },
            geometry: SharedShape::compound(parts),
            body_from_geometry: Pose::identity(),
            centre,
            radius: max_distance(&centre, points) + radius,
        })
    }

    /// The body's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// What the body is made of.
    pub fn kind(&self) -> &BodyKind {
        &self.kind
    }

    /// The bounding sphere `(centre, radius)` in the body frame (m).
    pub fn bounding_sphere(&self) -> (Point3<f64>, f64) {
        (self.centre, self.radius)
    }

    /// The same body under another name.
    pub fn renamed(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }
}

fn max_distance(centre: &Point3<f64>, points: &[Point3<f64>]) -> f64 {
    points
        .iter()
        .map(|p| (p - centre).norm())
        .fold(0.0, f64::max)
}

/// A body placed in the world (`world_from_body`, m).
#[derive(Clone, Copy)]
pub(crate) struct Placed<'a> {
    pub body: &'a Body,
    pub world_from_body: IsometryMatrix3<f64>,
    /// The bounding sphere's centre in the world.
    pub centre: Point3<f64>,
}

impl<'a> Placed<'a> {
    pub fn new(body: &'a Body, world_from_body: IsometryMatrix3<f64>) -> Self {
        Self {
            body,
            centre: world_from_body * body.centre,
            world_from_body,
        }
    }

    /// A lower bound of the distance to `other` (m): the bounding spheres' gap (or a sphere's
    /// height above a half-space).
    pub fn gap(&self, other: &Placed<'_>) -> f64 {
        match (self.plane(), other.plane()) {
            (Some(h), None) => other.centre.z - other.body.radius - h,
            (None, Some(h)) => self.centre.z - self.body.radius - h,
            _ => (self.centre - other.centre).norm() - self.body.radius - other.body.radius,
        }
    }

    /// The world height of a half-space body's plane.
    fn plane(&self) -> Option<f64> {
        match self.body.kind {
            BodyKind::HalfSpace { height } => Some(height + self.world_from_body.translation.z),
            _ => None,
        }
    }

    /// The signed height (m) of this body's lowest point above the plane `z = height`, when
    /// its shape is known: exact, negative by the depth below the plane.
    fn height_above(&self, height: f64) -> Option<f64> {
        match &self.body.kind {
            BodyKind::Solid(shape) | BodyKind::Surface(shape) => {
                let down = self
                    .world_from_body
                    .rotation
                    .inverse_transform_vector(&-nalgebra::Vector3::z());
                Some((self.world_from_body * shape.support(&down)).z - height)
            }
            _ => None,
        }
    }

    /// The exact signed distance to a half-space body, when one of the two is one.
    fn plane_distance(&self, other: &Placed<'_>) -> Option<f64> {
        match (self.plane(), other.plane()) {
            (Some(h), None) => other.height_above(h),
            (None, Some(h)) => self.height_above(h),
            _ => None,
        }
    }

    /// parry's pose of the geometry.
    fn geometry_pose(&self) -> Pose {
        bridge::pose_from_matrix(&self.world_from_body) * self.body.body_from_geometry
    }

    /// The exact distance to `other` (m); 0 when they touch or overlap.
    pub fn distance(&self, other: &Placed<'_>) -> f64 {
        if let Some(d) = self.plane_distance(other) {
            return d.max(0.0);
        }
        query::distance(
            &self.geometry_pose(),
            self.body.geometry.as_ref(),
            &other.geometry_pose(),
            other.body.geometry.as_ref(),
        )
        .map(|d| d.distance)
        .unwrap_or(0.0)
    }

    /// The signed distance to `other` (m): negative by the penetration depth when they
    /// overlap (0 for pairs without a depth query).
    pub fn signed_distance(&self, other: &Placed<'_>) -> f64 {
        if let Some(d) = self.plane_distance(other) {
            return d;
        }
        let distance = self.distance(other);
        if distance > 0.0 {
            return distance;
        }
        match query::contact(
            &self.geometry_pose(),
            self.body.geometry.as_ref(),
            &other.geometry_pose(),
            other.body.geometry.as_ref(),
            0.0,
        ) {
            Ok(Some(contact)) => contact.dist.min(0.0),
            _ => 0.0,
        }
    }
}

/// The world's table: the half-space below a horizontal plane, or a slab with a footprint.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The top surface's height, world `z` (m).
    pub height: f64,
    /// The footprint `[x, y]` (m) and its centre `[x, y]` (m); `None`: infinite.
    pub footprint: Option<([f64; 2], [f64; 2])>,
    /// The slab's thickness below the top (m), when it has a footprint.
    pub thickness: f64,
}

impl Table {
    /// The table as a body and its pose `world_from_body`.
    pub(crate) fn body(&self) -> (Body, Isometry3<f64>) {
        match self.footprint {
            None => (
                Body {
                    name: "table".into(),
                    kind: BodyKind::HalfSpace {
                        height: self.height,
                    },
                    geometry: SharedShape::halfspace(parry3d_f64::math::Vector::Z),
                    body_from_geometry: Pose::from_translation(parry3d_f64::math::Vector::new(
                        0.0,
                        0.0,
                        self.height,
                    )),
                    centre: Point3::new(0.0, 0.0, self.height),
                    radius: f64::INFINITY,
                },
                Isometry3::identity(),
            ),
            Some((size, centre)) => {
                let shape = Shape::cuboid([size[0], size[1], self.thickness])
                    .expect("table sizes are checked when the scene is built");
                (
                    Body::from_shape("table", &shape),
                    Isometry3::translation(
                        centre[0],
                        centre[1],
                        self.height - self.thickness / 2.0,
                    ),
                )
            }
        }
    }
}
