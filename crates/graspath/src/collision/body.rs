//! A rigid body ready for collision queries: its geometry in its own frame (converted once for
//! the exact queries) and a bounding sphere for the cheap ones.

use super::bridge;
use super::CollisionError;
use crate::geometry::shape::Shape;
use nalgebra::{Isometry3, IsometryMatrix3, Point3, Vector3};
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
    /// Spheres `(centre, radius)` whose union contains the body, body frame (m): a few along
    /// the long axis of a box, cylinder or capsule, else the bounding sphere.
    cover: Vec<(Point3<f64>, f64)>,
    /// The largest radius in `cover` (m).
    cover_radius: f64,
    /// The shape, when its point distance has a closed form (box, cylinder, capsule, sphere).
    primitive: Option<Shape>,
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
        let primitive = matches!(
            shape,
            Shape::Box(_) | Shape::Cylinder(_) | Shape::Capsule(_) | Shape::Sphere(_)
        )
        .then(|| shape.clone());
        let cover = cover(shape).unwrap_or_else(|| vec![(centre, radius)]);
        Self {
            name: name.into(),
            kind,
            geometry,
            body_from_geometry,
            centre,
            radius,
            cover_radius: cover.iter().map(|c| c.1).fold(0.0, f64::max),
            cover,
            primitive,
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
            cover: vec![(centre, max_distance(&centre, points) + radius)],
            cover_radius: max_distance(&centre, points) + radius,
            primitive: None,
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

/// The most spheres a body's cover has.
const MAX_COVER: usize = 4;

/// Spheres covering a box, cylinder or capsule: `k` equal slices along its longest axis, each
/// inside the sphere about its centre through its farthest corner (a capsule's slice reaches
/// `radius` beyond its piece of the segment in every direction); `None` for other shapes.
fn cover(shape: &Shape) -> Option<Vec<(Point3<f64>, f64)>> {
    // (axis, half length along it, radius of a slice of half length `s`)
    let (axis, half, slice): (usize, f64, Box<dyn Fn(f64) -> f64>) = match shape {
        Shape::Sphere(s) => return Some(vec![(Point3::origin(), s.radius())]),
        Shape::Cylinder(c) => {
            let r = c.radius();
            (2, c.length() / 2.0, Box::new(move |s: f64| r.hypot(s)))
        }
        Shape::Capsule(c) => {
            let r = c.radius();
            (2, c.length() / 2.0, Box::new(move |s: f64| r + s))
        }
        Shape::Box(b) => {
            let h = b.half_extents();
            let axis = h.imax();
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let cross = h[u].hypot(h[v]);
            (axis, h[axis], Box::new(move |s: f64| cross.hypot(s)))
        }
        _ => return None,
    };
    // Slices about as long as the body is thick.
    let thick = slice(0.0).max(1e-9);
    let k = ((half / thick).ceil() as usize).clamp(1, MAX_COVER);
    let s = half / k as f64;
    Some(
        (0..k)
            .map(|i| {
                let mut c = Point3::origin();
                c[axis] = -half + (2 * i + 1) as f64 * s;
                // A hair more than the exact corner distance: the cover must contain the body.
                (c, slice(s) * (1.0 + 1e-12) + 1e-15)
            })
            .collect(),
    )
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
    pub(crate) fn new(body: &'a Body, world_from_body: IsometryMatrix3<f64>) -> Self {
        Self {
            body,
            centre: world_from_body * body.centre,
            world_from_body,
        }
    }

    /// A lower bound of the distance to `other` (m): the bounding spheres' gap (or a sphere's
    /// height above a half-space).
    pub(crate) fn gap(&self, other: &Placed<'_>) -> f64 {
        match (self.plane(), other.plane()) {
            (Some(h), None) => other.centre.z - other.body.radius - h,
            (None, Some(h)) => self.centre.z - self.body.radius - h,
            _ => (self.centre - other.centre).norm() - self.body.radius - other.body.radius,
        }
    }

    /// A lower bound of the distance to `other` (m), at least [`Placed::gap`] and usually much
    /// tighter: the smaller-sphered body's cover against the other's exact point distance
    /// (a box, cylinder, capsule or sphere), or cover against cover; the exact signed distance
    /// against a half-space. Each cover sphere `(c, ρ)` holds points no nearer to `other` than
    /// `signed_distance(c) − ρ` (a point distance is 1-Lipschitz).
    pub(crate) fn lower_bound(&self, other: &Placed<'_>) -> f64 {
        if let Some(d) = self.plane_distance(other) {
            return d;
        }
        let (a, b) = (self.body, other.body);
        if a.cover.is_empty() || b.cover.is_empty() {
            // A half-space against a body without a known shape.
            return self.gap(other);
        }
        let bound = match (&a.primitive, &b.primitive) {
            (Some(sa), Some(sb)) => {
                if a.cover_radius <= b.cover_radius {
                    self.cover_to(other, sb)
                } else {
                    other.cover_to(self, sa)
                }
            }
            (None, Some(sb)) => self.cover_to(other, sb),
            (Some(sa), None) => other.cover_to(self, sa),
            (None, None) => {
                let mut best = f64::INFINITY;
                for (ca, ra) in &a.cover {
                    let wa = self.world_from_body * ca;
                    for (cb, rb) in &b.cover {
                        let wb = other.world_from_body * cb;
                        best = best.min((wa - wb).norm() - ra - rb);
                    }
                }
                best
            }
        };
        bound.max(self.gap(other))
    }

    /// A lower bound of the distance to `other` (m) by separating directions: for a unit `u`,
    /// no two points of the bodies are nearer than `min_other u·y − max_self u·x` (each the
    /// height of a support point). The directions are the face normals of either body that is
    /// a box, turned towards the other body, and the line between the centres: a box's face
    /// against a large flat obstacle makes the bound exact, where sphere covers are loose.
    /// `-∞` unless both shapes have closed-form distances and one of them is a box.
    pub(crate) fn separation(&self, other: &Placed<'_>) -> f64 {
        let (Some(sa), Some(sb)) = (&self.body.primitive, &other.body.primitive) else {
            return f64::NEG_INFINITY;
        };
        let box_axes = |placed: &Placed<'_>, shape: &Shape| match shape {
            Shape::Box(_) => Some(placed.world_from_body.rotation.into_inner()),
            _ => None,
        };
        let (axes_a, axes_b) = (box_axes(self, sa), box_axes(other, sb));
        if axes_a.is_none() && axes_b.is_none() {
            return f64::NEG_INFINITY;
        }
        // The largest `u · x` over the body (world frame, unit `u`).
        let height = |placed: &Placed<'_>, shape: &Shape, u: &Vector3<f64>| {
            let local = placed.world_from_body.rotation.inverse_transform_vector(u);
            local.dot(&shape.support(&local).coords)
                + u.dot(&placed.world_from_body.translation.vector)
        };
        // The gap along `u`, with `self` on its negative side.
        let along = |u: &Vector3<f64>| -height(other, sb, &-u) - height(self, sa, u);
        let towards = other.centre - self.centre;
        let mut best = towards
            .try_normalize(0.0)
            .map_or(f64::NEG_INFINITY, |u| along(&u));
        for axes in [axes_a, axes_b].into_iter().flatten() {
            for axis in axes.column_iter() {
                let u = if axis.dot(&towards) >= 0.0 {
                    axis.into_owned()
                } else {
                    -axis
                };
                best = best.max(along(&u));
            }
        }
        best
    }

    /// The smallest `signed_distance(c) − ρ` over this body's cover spheres, against
    /// `other`, whose shape is `shape`.
    fn cover_to(&self, other: &Placed<'_>, shape: &Shape) -> f64 {
        let other_from_self = other.world_from_body.inv_mul(&self.world_from_body);
        self.body
            .cover
            .iter()
            .map(|(c, r)| shape.signed_distance(&(other_from_self * c)) - r)
            .fold(f64::INFINITY, f64::min)
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
                    .inverse_transform_vector(&-Vector3::z());
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
    pub(crate) fn distance(&self, other: &Placed<'_>) -> f64 {
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
    pub(crate) fn signed_distance(&self, other: &Placed<'_>) -> f64 {
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
                    cover: Vec::new(),
                    cover_radius: f64::INFINITY,
                    primitive: None,
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

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};
    use rand::{rngs::StdRng, RngExt, SeedableRng};

    fn shapes() -> Vec<Shape> {
        vec![
            Shape::cuboid([0.04, 0.4, 0.5]).unwrap(),
            Shape::cuboid([0.02, 0.03, 0.11]).unwrap(),
            Shape::cylinder(0.06, 0.273).unwrap(),
            Shape::cylinder(0.06, 0.12).unwrap(),
            Shape::capsule(0.03, 0.3).unwrap(),
            Shape::sphere(0.05).unwrap(),
        ]
    }

    fn random_pose(rng: &mut StdRng, spread: f64) -> IsometryMatrix3<f64> {
        let iso = Isometry3::from_parts(
            Translation3::new(
                rng.random_range(-spread..spread),
                rng.random_range(-spread..spread),
                rng.random_range(-spread..spread),
            ),
            UnitQuaternion::from_euler_angles(
                rng.random_range(-3.0..3.0),
                rng.random_range(-1.5..1.5),
                rng.random_range(-3.0..3.0),
            ),
        );
        nalgebra::convert(iso)
    }

    #[test]
    fn every_point_of_a_shape_lies_in_its_cover() {
        // Oracle: points drawn in the shape's bounding box and kept when the shape's own
        // signed distance says they are inside or on it.
        let mut rng = StdRng::seed_from_u64(11);
        for shape in shapes() {
            let body = Body::from_shape("s", &shape);
            let aabb = shape.aabb();
            let mut inside = 0;
            for _ in 0..20_000 {
                let p = Point3::new(
                    rng.random_range(aabb.min.x..=aabb.max.x),
                    rng.random_range(aabb.min.y..=aabb.max.y),
                    rng.random_range(aabb.min.z..=aabb.max.z),
                );
                if shape.signed_distance(&p) > 0.0 {
                    continue;
                }
                inside += 1;
                assert!(
                    body.cover.iter().any(|(c, r)| (p - c).norm() <= *r),
                    "{}: {p} outside every cover sphere",
                    shape.kind()
                );
            }
            assert!(inside > 1000, "{}: too few inside points", shape.kind());
            // The cover is no looser than the bounding sphere.
            assert!(body.cover_radius <= body.radius + 1e-12);
        }
    }

    #[test]
    fn the_lower_bound_is_at_least_the_gap_and_at_most_the_exact_distance() {
        // Oracle for the exact distance: parry's distance on the converted shapes.
        let mut rng = StdRng::seed_from_u64(12);
        let bodies: Vec<Body> = shapes().iter().map(|s| Body::from_shape("s", s)).collect();
        let mut tighter = 0;
        for _ in 0..4000 {
            let a = &bodies[rng.random_range(0..bodies.len())];
            let b = &bodies[rng.random_range(0..bodies.len())];
            let pa = Placed::new(a, random_pose(&mut rng, 0.4));
            let pb = Placed::new(b, random_pose(&mut rng, 0.4));
            let bound = pa.lower_bound(&pb);
            let exact = pa.distance(&pb);
            let gap = pa.gap(&pb);
            assert!(bound >= gap, "bound {bound} below the gap {gap}");
            if bound > 0.0 {
                assert!(
                    bound <= exact + 1e-9,
                    "bound {bound} above the distance {exact}"
                );
            }
            if bound > gap + 0.01 {
                tighter += 1;
            }
        }
        assert!(
            tighter > 400,
            "the cover bound is rarely tighter: {tighter}"
        );
    }

    #[test]
    fn the_separation_never_exceeds_the_exact_distance_and_is_exact_face_on() {
        // Oracle: parry's distance on the converted shapes.
        let mut rng = StdRng::seed_from_u64(13);
        let bodies: Vec<Body> = shapes().iter().map(|s| Body::from_shape("s", s)).collect();
        let mut positive = 0;
        for _ in 0..4000 {
            let a = &bodies[rng.random_range(0..bodies.len())];
            let b = &bodies[rng.random_range(0..bodies.len())];
            let pa = Placed::new(a, random_pose(&mut rng, 0.4));
            let pb = Placed::new(b, random_pose(&mut rng, 0.4));
            let separation = pa.separation(&pb);
            let exact = pa.distance(&pb);
            if separation > 0.0 {
                positive += 1;
                assert!(
                    separation <= exact + 1e-9,
                    "separation {separation} above the distance {exact}"
                );
            }
        }
        assert!(
            positive > 400,
            "the separation is rarely positive: {positive}"
        );
        // Face on: a small box (any yaw about the wall's normal) in front of a wall's face is
        // exactly its distance from the face plane, which sphere covers cannot see.
        let wall = Body::from_shape("wall", &Shape::cuboid([0.04, 0.8, 0.8]).unwrap());
        let palm = Body::from_shape("palm", &Shape::cuboid([0.02, 0.06, 0.12]).unwrap());
        for k in 0..20 {
            let gap = 0.001 + 0.002 * k as f64;
            let yaw = 0.3 * k as f64;
            let palm_pose = Isometry3::from_parts(
                Translation3::new(0.02 + gap + 0.01, 0.1, -0.05),
                UnitQuaternion::from_euler_angles(yaw, 0.0, 0.0),
            );
            let pw = Placed::new(&wall, IsometryMatrix3::identity());
            let pp = Placed::new(&palm, nalgebra::convert(palm_pose));
            // The palm's lowest x: its centre less the half-extent seen along x.
            let rotation = palm_pose.rotation.to_rotation_matrix();
            let half = [0.01, 0.03, 0.06];
            let reach: f64 = (0..3).map(|i| half[i] * rotation[(0, i)].abs()).sum();
            let expected = palm_pose.translation.x - reach - 0.02;
            if expected > 0.0 {
                assert!((pw.separation(&pp) - expected).abs() < 1e-12);
                assert!((pp.separation(&pw) - expected).abs() < 1e-12);
            }
        }
    }
}
