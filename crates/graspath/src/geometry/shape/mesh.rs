//! Mesh shapes: the convex hull of points ([`ConvexMesh`]) and a general triangle mesh
//! ([`TriMesh`]). Distances are exact, by a pass over the triangles (a bounding-volume
//! hierarchy is the collision layer's business).

use super::hull::{convex_hull, Facet, HullError};
use super::{Proximity, ShapeError};
use nalgebra::{Point3, Vector3};
use std::collections::HashMap;

fn check_points(points: &[Point3<f64>], field: &str) -> Result<(), ShapeError> {
    for (i, p) in points.iter().enumerate() {
        if let Some(&v) = p.coords.iter().find(|v| !v.is_finite()) {
            return Err(ShapeError::NotFinite {
                field: format!("{field}[{i}]"),
                value: v,
            });
        }
    }
    Ok(())
}

/// The point of `points` farthest along `d` (the first of equals; the origin when empty).
fn support_of(points: &[Point3<f64>], d: &Vector3<f64>) -> Point3<f64> {
    let mut best = (f64::NEG_INFINITY, Point3::origin());
    for p in points {
        let s = p.coords.dot(d);
        if s > best.0 {
            best = (s, *p);
        }
    }
    best.1
}

/// The convex hull of a set of points (m, in the shape frame).
/// File: `{convex_mesh: {points: [[x, y, z], ...]}}`; at least four points not all on a plane.
///
/// The hull's facets are computed once, when the shape is built: the signed distance is then
/// exact (outside: the distance to the nearest hull triangle among those whose plane the point
/// lies above; inside: minus the distance to the nearest facet plane) and the support is the
/// hull vertex farthest along the direction.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "ConvexMeshFile", into = "ConvexMeshFile")]
pub struct ConvexMesh {
    points: Vec<Point3<f64>>,
    hull_vertices: Vec<Point3<f64>>,
    facets: Vec<Facet>,
}

#[derive(Clone, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ConvexMeshFile {
    points: Vec<[f64; 3]>,
}

impl TryFrom<ConvexMeshFile> for ConvexMesh {
    type Error = ShapeError;
    fn try_from(f: ConvexMeshFile) -> Result<Self, ShapeError> {
        ConvexMesh::new(f.points.into_iter().map(Point3::from).collect())
    }
}

impl From<ConvexMesh> for ConvexMeshFile {
    fn from(m: ConvexMesh) -> Self {
        ConvexMeshFile {
            points: m.points.iter().map(|p| [p.x, p.y, p.z]).collect(),
        }
    }
}

impl ConvexMesh {
    /// The hull of `points` (finite; at least four, spanning a volume).
    pub fn new(points: Vec<Point3<f64>>) -> Result<Self, ShapeError> {
        check_points(&points, "convex_mesh.points")?;
        let facets = convex_hull(&points).map_err(|HullError::Flat| ShapeError::BadMesh {
            field: "convex_mesh.points".into(),
            message: format!(
                "the {} points span no volume (a convex mesh needs at least four points not on one plane)",
                points.len()
            ),
        })?;
        let mut used: Vec<usize> = facets.iter().flat_map(|f| f.vertices).collect();
        used.sort_unstable();
        used.dedup();
        let hull_vertices = used.into_iter().map(|i| points[i]).collect();
        Ok(Self {
            points,
            hull_vertices,
            facets,
        })
    }

    /// The points the hull was built from (m).
    pub fn points(&self) -> &[Point3<f64>] {
        &self.points
    }

    /// The points that are hull vertices (m).
    pub fn hull_vertices(&self) -> &[Point3<f64>] {
        &self.hull_vertices
    }

    /// The hull's triangles as corner points, counter-clockwise seen from outside.
    pub fn hull_triangles(&self) -> impl Iterator<Item = [Point3<f64>; 3]> + '_ {
        self.facets
            .iter()
            .map(|f| f.vertices.map(|i| self.points[i]))
    }

    /// Signed distance (m) from `p` (mesh frame); negative inside the hull.
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        self.proximity(p).signed_distance
    }

    /// The hull triangles whose plane `p` lies strictly above: outside the hull, the closest
    /// point lies on one of them (it lies on a facet `f` with `n_f · (p − closest) > 0`).
    fn facing(&self, p: &Point3<f64>) -> impl Iterator<Item = [Point3<f64>; 3]> + '_ {
        let p = p.coords;
        self.facets
            .iter()
            .filter(move |f| f.normal.dot(&p) - f.offset > 0.0)
            .map(|f| f.vertices.map(|i| self.points[i]))
    }

    /// Signed distance and closest surface point of `p` (mesh frame): outside, the closest
    /// point of the nearest hull triangle; inside, the foot of `p` on the nearest facet plane.
    pub fn proximity(&self, p: &Point3<f64>) -> Proximity {
        let mut deepest = (f64::NEG_INFINITY, Vector3::zeros());
        for f in &self.facets {
            let h = f.normal.dot(&p.coords) - f.offset;
            if h > deepest.0 {
                deepest = (h, f.normal);
            }
        }
        if deepest.0 <= 0.0 {
            return Proximity {
                signed_distance: deepest.0,
                closest: p - deepest.1 * deepest.0,
            };
        }
        let (distance, closest) = nearest_on_triangles(p, self.facing(p));
        Proximity {
            signed_distance: distance,
            closest,
        }
    }

    /// The hull vertex farthest along `d`.
    pub fn support(&self, d: &Vector3<f64>) -> Point3<f64> {
        support_of(&self.hull_vertices, d)
    }
}

/// A triangle mesh (m, in the shape frame): vertices and triangles (three vertex indices
/// each). File: `{triangle_mesh: {vertices: [[x, y, z], ...], triangles: [[i, j, k], ...]}}`.
///
/// **Signed distance = unsigned distance with an inside test.** The magnitude is the exact
/// distance to the nearest triangle. The sign is negative when the mesh is *closed* (every
/// edge shared by exactly two triangles) and the point's generalised winding number
/// (the triangles' signed solid angles over 4π) has magnitude above ½, so either consistent
/// orientation works. An open mesh (or one with an edge on three triangles) bounds no volume:
/// its distance is unsigned, as for a surface; [`TriMesh::is_closed`] tells which.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "TriMeshFile", into = "TriMeshFile")]
pub struct TriMesh {
    vertices: Vec<Point3<f64>>,
    triangles: Vec<[u32; 3]>,
    closed: bool,
}

#[derive(Clone, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct TriMeshFile {
    vertices: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
}

impl TryFrom<TriMeshFile> for TriMesh {
    type Error = ShapeError;
    fn try_from(f: TriMeshFile) -> Result<Self, ShapeError> {
        TriMesh::new(
            f.vertices.into_iter().map(Point3::from).collect(),
            f.triangles,
        )
    }
}

impl From<TriMesh> for TriMeshFile {
    fn from(m: TriMesh) -> Self {
        TriMeshFile {
            vertices: m.vertices.iter().map(|p| [p.x, p.y, p.z]).collect(),
            triangles: m.triangles,
        }
    }
}

impl TriMesh {
    /// A mesh of finite `vertices` and at least one triangle, every index in range.
    pub fn new(vertices: Vec<Point3<f64>>, triangles: Vec<[u32; 3]>) -> Result<Self, ShapeError> {
        check_points(&vertices, "triangle_mesh.vertices")?;
        if triangles.is_empty() {
            return Err(ShapeError::BadMesh {
                field: "triangle_mesh.triangles".into(),
                message: "a mesh needs at least one triangle".into(),
            });
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&i) = tri.iter().find(|&&i| i as usize >= vertices.len()) {
                return Err(ShapeError::BadMesh {
                    field: format!("triangle_mesh.triangles[{t}]"),
                    message: format!(
                        "vertex index {i} is out of range (the mesh has {} vertices)",
                        vertices.len()
                    ),
                });
            }
        }
        let mut edge_count: HashMap<(u32, u32), u32> = HashMap::new();
        for tri in &triangles {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                *edge_count.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let closed = edge_count.values().all(|&n| n == 2);
        Ok(Self {
            vertices,
            triangles,
            closed,
        })
    }

    /// Vertex positions (m).
    pub fn vertices(&self) -> &[Point3<f64>] {
        &self.vertices
    }

    /// Vertex indices of each triangle.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Whether every edge is shared by exactly two triangles (then the mesh has an inside).
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    fn corners(&self, t: &[u32; 3]) -> [Point3<f64>; 3] {
        t.map(|i| self.vertices[i as usize])
    }

    /// The unsigned distance (m) from `p` to the nearest triangle.
    pub fn distance(&self, p: &Point3<f64>) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = self.corners(t);
                (p - closest_on_triangle(p, &a, &b, &c)).norm()
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The generalised winding number of the mesh about `p`: ±1 inside a closed mesh
    /// (the sign follows the orientation), 0 outside.
    pub fn winding_number(&self, p: &Point3<f64>) -> f64 {
        let mut total = 0.0;
        for t in &self.triangles {
            let [a, b, c] = self.corners(t).map(|v| v - p);
            let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
            let numerator = a.dot(&b.cross(&c));
            let denominator = la * lb * lc + a.dot(&b) * lc + a.dot(&c) * lb + b.dot(&c) * la;
            total += 2.0 * numerator.atan2(denominator);
        }
        total / (4.0 * std::f64::consts::PI)
    }

    /// Signed distance (m) from `p`: see [`TriMesh`] for the sign.
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        let d = self.distance(p);
        if self.closed && d > 0.0 && self.winding_number(p).abs() > 0.5 {
            -d
        } else {
            d
        }
    }

    /// Signed distance (as [`TriMesh::signed_distance`]) and the closest point of the
    /// nearest triangle (mesh frame).
    pub fn proximity(&self, p: &Point3<f64>) -> Proximity {
        let (d, closest) = nearest_on_triangles(p, self.triangles.iter().map(|t| self.corners(t)));
        let inside = self.closed && d > 0.0 && self.winding_number(p).abs() > 0.5;
        Proximity {
            signed_distance: if inside { -d } else { d },
            closest,
        }
    }

    /// The vertex farthest along `d`.
    pub fn support(&self, d: &Vector3<f64>) -> Point3<f64> {
        support_of(&self.vertices, d)
    }
}

/// The distance from `p` to the nearest of `triangles` and the closest point on it (the first
/// of equals; infinity and `p` itself for none).
#[inline]
fn nearest_on_triangles(
    p: &Point3<f64>,
    triangles: impl Iterator<Item = [Point3<f64>; 3]>,
) -> (f64, Point3<f64>) {
    let mut best = (f64::INFINITY, *p);
    for [a, b, c] in triangles {
        let q = closest_on_triangle(p, &a, &b, &c);
        let d = (p - q).norm();
        if d < best.0 {
            best = (d, q);
        }
    }
    best
}

/// The closest point of triangle `abc` to `p` (Ericson, *Real-Time Collision Detection*
/// §5.1.5); also right for degenerate triangles.
#[inline]
pub(super) fn closest_on_triangle(
    p: &Point3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> Point3<f64> {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if denom == 0.0 || !denom.is_finite() {
        // A degenerate triangle that the edge tests did not settle: nearest of its edges.
        let candidates = [
            closest_on_segment(p, a, b),
            closest_on_segment(p, b, c),
            closest_on_segment(p, c, a),
        ];
        return candidates
            .into_iter()
            .min_by(|x, y| (p - x).norm_squared().total_cmp(&(p - y).norm_squared()))
            .unwrap_or(*a);
    }
    a + ab * (vb / denom) + ac * (vc / denom)
}

fn closest_on_segment(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>) -> Point3<f64> {
    let ab = b - a;
    let l2 = ab.norm_squared();
    if l2 == 0.0 {
        return *a;
    }
    a + ab * ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
}
