//! Convex collision shapes of hand links, with signed distances, closest points and
//! penetration depths. Each shape is expressed in its own frame (metres).

use crate::cloud::TriangleMesh;
use nalgebra::{Point3, Vector2, Vector3};

/// A convex solid in its own frame (metres).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// A box centred on the origin with half edge lengths `half` along x, y, z.
    Box {
        /// Half edge lengths (m).
        half: [f64; 3],
    },
    /// A sphere centred on the origin.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// A capped cylinder along z, centred on the origin (URDF convention).
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Half the length along z (m).
        half_length: f64,
    },
    /// A convex triangle mesh (its hull is assumed; triangles wound counter-clockwise seen
    /// from outside).
    ConvexMesh {
        /// The mesh.
        mesh: TriangleMesh,
        /// Outward unit face normals and offsets `(n, d)`: inside means `n·p ≤ d` for all.
        planes: Vec<([f64; 3], f64)>,
    },
}

/// The closest point of a shape's surface to a query point, and the signed distance
/// (negative inside).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Proximity {
    /// Signed distance (m): positive outside, negative inside (minus the penetration depth).
    pub signed_distance: f64,
    /// The closest surface point (shape frame, m).
    pub closest: Point3<f64>,
}

impl Shape {
    /// A convex mesh shape; face planes are computed from the triangles, oriented away from
    /// the vertex centroid (so the winding need not be consistent).
    pub fn convex_mesh(mesh: TriangleMesh) -> Self {
        let centroid = if mesh.vertices.is_empty() {
            Point3::origin()
        } else {
            Point3::from(
                mesh.vertices.iter().map(|v| v.coords).sum::<Vector3<f64>>()
                    / mesh.vertices.len() as f64,
            )
        };
        let mut planes = Vec::new();
        for t in 0..mesh.triangles.len() {
            let [a, b, c] = mesh.corners(t);
            let n = (b - a).cross(&(c - a));
            if n.norm() < 1e-15 {
                continue;
            }
            let mut n = n.normalize();
            if n.dot(&(a - centroid)) < 0.0 {
                n = -n;
            }
            planes.push(([n.x, n.y, n.z], n.dot(&a.coords)));
        }
        Shape::ConvexMesh { mesh, planes }
    }

    /// Signed distance and closest surface point of `p` (shape frame).
    pub fn proximity(&self, p: &Point3<f64>) -> Proximity {
        match self {
            Shape::Box { half } => box_proximity(&Vector3::from(*half), p),
            Shape::Sphere { radius } => {
                let r = p.coords.norm();
                let dir = if r > 1e-15 {
                    p.coords / r
                } else {
                    Vector3::z()
                };
                Proximity {
                    signed_distance: r - radius,
                    closest: Point3::from(dir * *radius),
                }
            }
            Shape::Cylinder {
                radius,
                half_length,
            } => cylinder_proximity(*radius, *half_length, p),
            Shape::ConvexMesh { mesh, planes } => mesh_proximity(mesh, planes, p),
        }
    }

    /// How deep `p` lies inside the shape grown by `offset` (m): `max(0, offset − sd(p))`.
    #[inline]
    pub fn depth(&self, p: &Point3<f64>, offset: f64) -> f64 {
        let sd = match self {
            Shape::Box { half } => {
                let q = p.coords.abs() - Vector3::from(*half);
                let outside = q.sup(&Vector3::zeros()).norm();
                outside + q.max().min(0.0)
            }
            _ => self.proximity(p).signed_distance,
        };
        (offset - sd).max(0.0)
    }

    /// The radius of a sphere about the shape origin that contains the shape (m).
    pub fn bounding_radius(&self) -> f64 {
        match self {
            Shape::Box { half } => Vector3::from(*half).norm(),
            Shape::Sphere { radius } => *radius,
            Shape::Cylinder {
                radius,
                half_length,
            } => radius.hypot(*half_length),
            Shape::ConvexMesh { mesh, .. } => mesh
                .vertices
                .iter()
                .map(|v| v.coords.norm())
                .fold(0.0, f64::max),
        }
    }
}

fn box_proximity(half: &Vector3<f64>, p: &Point3<f64>) -> Proximity {
    let q = p.coords.abs() - half;
    if q.max() > 0.0 {
        let closest = Point3::from(p.coords.zip_map(half, |c, h| c.clamp(-h, h)));
        Proximity {
            signed_distance: (p - closest).norm(),
            closest,
        }
    } else {
        // Inside: the nearest face is the one with the largest (least negative) q.
        let axis = q.imax();
        let mut closest = *p;
        closest[axis] = half[axis].copysign(p[axis]);
        Proximity {
            signed_distance: q[axis],
            closest,
        }
    }
}

fn cylinder_proximity(radius: f64, half_length: f64, p: &Point3<f64>) -> Proximity {
    let radial = Vector2::new(p.x, p.y);
    let r = radial.norm();
    let dir = if r > 1e-15 { radial / r } else { Vector2::x() };
    let dr = r - radius;
    let dz = p.z.abs() - half_length;
    if dr <= 0.0 && dz <= 0.0 {
        if dr > dz {
            let c = dir * radius;
            Proximity {
                signed_distance: dr,
                closest: Point3::new(c.x, c.y, p.z),
            }
        } else {
            Proximity {
                signed_distance: dz,
                closest: Point3::new(p.x, p.y, half_length.copysign(p.z)),
            }
        }
    } else {
        let cr = r.min(radius);
        let cz = p.z.clamp(-half_length, half_length);
        let closest = Point3::new(dir.x * cr, dir.y * cr, cz);
        Proximity {
            signed_distance: (p - closest).norm(),
            closest,
        }
    }
}

fn mesh_proximity(mesh: &TriangleMesh, planes: &[([f64; 3], f64)], p: &Point3<f64>) -> Proximity {
    let mut best = (f64::INFINITY, *p);
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let q = closest_on_triangle(p, &a, &b, &c);
        let d = (p - q).norm();
        if d < best.0 {
            best = (d, q);
        }
    }
    let inside = !planes.is_empty()
        && planes
            .iter()
            .all(|(n, d)| Vector3::from(*n).dot(&p.coords) <= *d);
    Proximity {
        signed_distance: if inside { -best.0 } else { best.0 },
        closest: best.1,
    }
}

/// The closest point of triangle `abc` to `p` (Ericson, Real-Time Collision Detection §5.1.5).
pub(crate) fn closest_on_triangle(
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
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::{sample_primitive, Primitive, SampleOptions};

    fn cube_mesh(h: f64) -> TriangleMesh {
        let v = |x: f64, y: f64, z: f64| Point3::new(x * h, y * h, z * h);
        TriangleMesh {
            vertices: vec![
                v(-1., -1., -1.),
                v(1., -1., -1.),
                v(1., 1., -1.),
                v(-1., 1., -1.),
                v(-1., -1., 1.),
                v(1., -1., 1.),
                v(1., 1., 1.),
                v(-1., 1., 1.),
            ],
            triangles: vec![
                [0, 3, 2],
                [0, 2, 1],
                [4, 5, 6],
                [4, 6, 7],
                [0, 1, 5],
                [0, 5, 4],
                [1, 2, 6],
                [1, 6, 5],
                [2, 3, 7],
                [2, 7, 6],
                [3, 0, 4],
                [3, 4, 7],
            ],
        }
    }

    #[test]
    fn box_and_cube_mesh_agree_everywhere() {
        let boxed = Shape::Box { half: [0.02; 3] };
        let mesh = Shape::convex_mesh(cube_mesh(0.02));
        let probe = sample_primitive(
            &Primitive::Sphere { radius: 0.03 },
            &SampleOptions {
                points: 200,
                seed: 1,
                ..Default::default()
            },
        )
        .expect("probe");
        for (k, p) in probe.points.iter().enumerate() {
            let p = Point3::from(p.coords * (k as f64 / 200.0 + 0.2));
            let a = boxed.proximity(&p);
            let b = mesh.proximity(&p);
            assert!((a.signed_distance - b.signed_distance).abs() < 1e-12, "{p}");
            assert!((boxed.depth(&p, 0.001) - (0.001 - a.signed_distance).max(0.0)).abs() < 1e-12);
        }
    }

    #[test]
    fn cylinder_distances_match_closed_forms() {
        let c = Shape::Cylinder {
            radius: 0.02,
            half_length: 0.05,
        };
        let side = c.proximity(&Point3::new(0.05, 0.0, 0.01));
        assert!((side.signed_distance - 0.03).abs() < 1e-15);
        let inside = c.proximity(&Point3::new(0.0, 0.015, 0.0));
        assert!((inside.signed_distance + 0.005).abs() < 1e-15);
        let corner = c.proximity(&Point3::new(0.05, 0.0, 0.09));
        assert!((corner.signed_distance - 0.05).abs() < 1e-15);
        let sphere = Shape::Sphere { radius: 0.1 };
        assert!(
            (sphere
                .proximity(&Point3::new(0.0, 0.3, 0.0))
                .signed_distance
                - 0.2)
                .abs()
                < 1e-15
        );
    }
}
