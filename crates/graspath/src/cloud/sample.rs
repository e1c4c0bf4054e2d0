//! Clouds sampled on the surface of a [`Shape`], in the shape's own frame (see
//! [`crate::geometry::shape`]): uniformly over the outer surface, with exact outward normals,
//! optional Gaussian noise and an optional single-view simulation (only points seen from a
//! viewpoint are kept, with self-occlusion traced for the primitives).
//!
//! Box, cylinder, sphere, capsule and T-shape are sampled in closed form; convex and triangle
//! meshes by triangle area ([`super::TriangleMesh::sample`]). The upright T of earlier cloud
//! files, `{t_shape: {stem: [x, y, z], bar: [x, y, z]}}`, is a [`LegacyTShape`].

use super::{CloudError, PointCloud, TriangleMesh};
use crate::geometry::shape::{Shape, Stem};
use nalgebra::{Point3, Vector3};
use rand::{rngs::StdRng, RngExt, SeedableRng};
use rand_distr::{Distribution, Normal, StandardNormal};
use std::f64::consts::PI;

/// The most points a cloud sampled from a primitive or a mesh may have: grasp generation never
/// needs more than a few tens of thousands, and sampling time grows with the count.
pub const MAX_SAMPLED_POINTS: usize = 1_000_000;

/// The largest noise standard deviation (m): beyond it the cloud no longer shows the shape.
pub(super) const MAX_NOISE: f64 = 1.0;

/// How many points to draw, the seed, noise and the simulated viewpoint.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SampleOptions {
    /// The number of points in the cloud (after the view filter; 5 000 by default, at most
    /// [`MAX_SAMPLED_POINTS`]).
    pub points: usize,
    /// Seed of the random draws.
    pub seed: u64,
    /// A sensor origin (object frame, m): keep only the points it sees.
    pub view: Option<[f64; 3]>,
    /// Standard deviation of isotropic Gaussian noise added to positions (m).
    pub noise: f64,
}

impl Default for SampleOptions {
    fn default() -> Self {
        Self {
            points: 5000,
            seed: 0,
            view: None,
            noise: 0.0,
        }
    }
}

impl SampleOptions {
    pub(crate) fn check(&self) -> Result<(), CloudError> {
        if self.points == 0 {
            return Err(CloudError::BadOption {
                field: "points".into(),
                message: "must be at least 1".into(),
            });
        }
        if self.points > MAX_SAMPLED_POINTS {
            return Err(CloudError::BadOption {
                field: "points".into(),
                message: format!(
                    "{} exceeds the limit of {MAX_SAMPLED_POINTS} points",
                    self.points
                ),
            });
        }
        if !(self.noise.is_finite() && (0.0..=MAX_NOISE).contains(&self.noise)) {
            return Err(CloudError::BadOption {
                field: "noise".into(),
                message: format!("must be a length in [0, {MAX_NOISE}] m, got {}", self.noise),
            });
        }
        if let Some(v) = self.view {
            if v.iter().any(|c| !c.is_finite()) {
                return Err(CloudError::BadOption {
                    field: "view".into(),
                    message: "must be three finite numbers".into(),
                });
            }
        }
        Ok(())
    }
}

/// One convex piece of a sampled solid, in the cloud frame. A solid of several pieces (a T)
/// drops the points of one piece that lie inside another (its interior faces).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Part {
    /// An axis-aligned box of half edges `half` about `centre`.
    Box {
        centre: Vector3<f64>,
        half: Vector3<f64>,
    },
    /// A capped cylinder along `z` about `(0, 0, centre_z)`.
    Cylinder {
        radius: f64,
        half_height: f64,
        centre_z: f64,
    },
    /// A sphere about the origin.
    Sphere { radius: f64 },
    /// A capsule about the segment `z ∈ [−half_length, half_length]`.
    Capsule { radius: f64, half_length: f64 },
}

impl Part {
    fn area(&self) -> f64 {
        match *self {
            Part::Box { half, .. } => 8.0 * (half.x * half.y + half.y * half.z + half.x * half.z),
            Part::Cylinder {
                radius,
                half_height,
                ..
            } => 2.0 * PI * radius * (radius + 2.0 * half_height),
            Part::Sphere { radius } => 4.0 * PI * radius * radius,
            Part::Capsule {
                radius,
                half_length,
            } => 4.0 * PI * radius * (radius + half_length),
        }
    }

    fn sample(&self, rng: &mut StdRng) -> (Point3<f64>, Vector3<f64>) {
        match *self {
            Part::Box { centre, half } => {
                let areas = [half.y * half.z, half.x * half.z, half.x * half.y];
                let total: f64 = areas.iter().sum();
                let u = rng.random::<f64>() * total;
                let axis = if u < areas[0] {
                    0
                } else if u < areas[0] + areas[1] {
                    1
                } else {
                    2
                };
                let sign = if rng.random::<bool>() { 1.0 } else { -1.0 };
                let mut p = Vector3::zeros();
                for k in 0..3 {
                    p[k] = if k == axis {
                        sign * half[k]
                    } else {
                        (2.0 * rng.random::<f64>() - 1.0) * half[k]
                    };
                }
                let mut n = Vector3::zeros();
                n[axis] = sign;
                (Point3::from(centre + p), n)
            }
            Part::Cylinder {
                radius,
                half_height,
                centre_z,
            } => {
                let side = 2.0 * half_height;
                let u = rng.random::<f64>() * (side + radius);
                let (mut p, n) = if u < side {
                    let a = 2.0 * PI * rng.random::<f64>();
                    let z = (2.0 * rng.random::<f64>() - 1.0) * half_height;
                    let n = Vector3::new(a.cos(), a.sin(), 0.0);
                    (Point3::new(radius * n.x, radius * n.y, z), n)
                } else {
                    let r = radius * rng.random::<f64>().sqrt();
                    let a = 2.0 * PI * rng.random::<f64>();
                    let sign = if rng.random::<bool>() { 1.0 } else { -1.0 };
                    (
                        Point3::new(r * a.cos(), r * a.sin(), sign * half_height),
                        Vector3::new(0.0, 0.0, sign),
                    )
                };
                // A centred cylinder's points are left untouched (bit for bit as before).
                if centre_z != 0.0 {
                    p.z += centre_z;
                }
                (p, n)
            }
            Part::Sphere { radius } => {
                let v = Vector3::from_fn(|_, _| StandardNormal.sample(rng)).normalize();
                (Point3::from(v * radius), v)
            }
            Part::Capsule {
                radius,
                half_length,
            } => {
                // Side area 2π r · 2h, the two caps together a sphere's 4π r²: in proportion
                // `2h : 2r`.
                let u = rng.random::<f64>() * (half_length + radius);
                if u < half_length {
                    let a = 2.0 * PI * rng.random::<f64>();
                    let z = (2.0 * rng.random::<f64>() - 1.0) * half_length;
                    let n = Vector3::new(a.cos(), a.sin(), 0.0);
                    (Point3::new(radius * n.x, radius * n.y, z), n)
                } else {
                    let v = Vector3::from_fn(|_, _| StandardNormal.sample(rng)).normalize();
                    let shift = if v.z >= 0.0 {
                        half_length
                    } else {
                        -half_length
                    };
                    (
                        Point3::new(radius * v.x, radius * v.y, radius * v.z + shift),
                        v,
                    )
                }
            }
        }
    }

    /// Whether `p` is inside or on the closed solid (with a small tolerance).
    fn contains(&self, p: &Point3<f64>) -> bool {
        const TOL: f64 = 1e-9;
        match *self {
            Part::Box { centre, half } => {
                let d = p.coords - centre;
                (0..3).all(|k| d[k].abs() <= half[k] + TOL)
            }
            Part::Cylinder {
                radius,
                half_height,
                centre_z,
            } => (p.z - centre_z).abs() <= half_height + TOL && p.x.hypot(p.y) <= radius + TOL,
            Part::Sphere { radius } => p.coords.norm() <= radius + TOL,
            Part::Capsule {
                radius,
                half_length,
            } => capsule_distance(p, radius, half_length) <= TOL,
        }
    }

    /// Whether the open segment from `a` to `b` passes through the solid's interior.
    fn blocks(&self, a: &Point3<f64>, b: &Point3<f64>) -> bool {
        // Sample the segment finely: the parts are convex, so a chord through the interior
        // spans an interval; 256 probes resolve any chord longer than 1/256 of the segment.
        const STEPS: usize = 256;
        (1..STEPS).any(|i| {
            let t = i as f64 / STEPS as f64;
            let q = a + (b - a) * t;
            self.strictly_contains(&q)
        })
    }

    fn strictly_contains(&self, p: &Point3<f64>) -> bool {
        const TOL: f64 = 1e-7;
        match *self {
            Part::Box { centre, half } => {
                let d = p.coords - centre;
                (0..3).all(|k| d[k].abs() < half[k] - TOL)
            }
            Part::Cylinder {
                radius,
                half_height,
                centre_z,
            } => (p.z - centre_z).abs() < half_height - TOL && p.x.hypot(p.y) < radius - TOL,
            Part::Sphere { radius } => p.coords.norm() < radius - TOL,
            Part::Capsule {
                radius,
                half_length,
            } => capsule_distance(p, radius, half_length) < -TOL,
        }
    }
}

/// The signed distance of `p` to a capsule about `z ∈ [−half_length, half_length]`.
fn capsule_distance(p: &Point3<f64>, radius: f64, half_length: f64) -> f64 {
    let axis = Vector3::new(0.0, 0.0, p.z.clamp(-half_length, half_length));
    (p.coords - axis).norm() - radius
}

/// The parts of a primitive shape in its own frame; `None` for the meshes.
fn parts(shape: &Shape) -> Option<Vec<Part>> {
    let cuboid = |centre: Vector3<f64>, half: Vector3<f64>| Part::Box { centre, half };
    Some(match shape {
        Shape::Box(b) => vec![cuboid(Vector3::zeros(), b.half_extents())],
        Shape::Cylinder(c) => vec![Part::Cylinder {
            radius: c.radius(),
            half_height: c.length() / 2.0,
            centre_z: 0.0,
        }],
        Shape::Sphere(s) => vec![Part::Sphere { radius: s.radius() }],
        Shape::Capsule(c) => vec![Part::Capsule {
            radius: c.radius(),
            half_length: c.length() / 2.0,
        }],
        Shape::TShape(t) => {
            let stem = match t.stem() {
                Stem::Box(b) => cuboid(Vector3::new(0.0, 0.0, t.stem_centre()), b.half_extents()),
                Stem::Cylinder(c) => Part::Cylinder {
                    radius: c.radius(),
                    half_height: c.length() / 2.0,
                    centre_z: t.stem_centre(),
                },
            };
            vec![stem, cuboid(Vector3::zeros(), t.bar().half_extents())]
        }
        Shape::ConvexMesh(_) | Shape::TriangleMesh(_) => return None,
    })
}

/// Samples `options.points` points on the outer surface of `shape` (shape frame, m) with their
/// exact outward normals. With `options.view`, a point is kept only if its normal faces the
/// viewpoint and (for the primitives) the segment to the viewpoint crosses no part of the
/// solid; with `options.noise`, positions get isotropic Gaussian noise (the normals stay exact).
///
/// Convex meshes are sampled on their hull's triangles, triangle meshes on their own (normals
/// from each triangle's winding, counter-clockwise seen from outside), both by area with
/// back-face culling for a view ([`TriangleMesh::sample`]).
///
/// ```
/// use graspath::cloud::{sample_shape, SampleOptions};
/// use graspath::geometry::shape::Shape;
/// let shape = Shape::cylinder(0.02, 0.1)?;
/// let cloud = sample_shape(&shape, &SampleOptions { points: 100, seed: 1, ..Default::default() })?;
/// for p in &cloud.points {
///     assert!(shape.signed_distance(p).abs() < 1e-12);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sample_shape(shape: &Shape, options: &SampleOptions) -> Result<PointCloud, CloudError> {
    options.check()?;
    match parts(shape) {
        Some(parts) => sample_parts(&parts, options),
        None => mesh_of(shape).sample(options, shape.kind()),
    }
}

/// The surface triangles of a mesh shape (a convex mesh's hull, outward).
fn mesh_of(shape: &Shape) -> TriangleMesh {
    match shape {
        Shape::ConvexMesh(m) => {
            let vertices: Vec<Point3<f64>> = m.hull_triangles().flatten().collect();
            let triangles = (0..vertices.len() as u32 / 3)
                .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
                .collect();
            TriangleMesh {
                vertices,
                triangles,
            }
        }
        Shape::TriangleMesh(m) => TriangleMesh {
            vertices: m.vertices().to_vec(),
            triangles: m.triangles().to_vec(),
        },
        _ => TriangleMesh::default(),
    }
}

/// Samples the outer surface of the union of `parts` (cloud frame).
pub(crate) fn sample_parts(
    parts: &[Part],
    options: &SampleOptions,
) -> Result<PointCloud, CloudError> {
    options.check()?;
    let areas: Vec<f64> = parts.iter().map(Part::area).collect();
    let total: f64 = areas.iter().sum();
    let mut rng = StdRng::seed_from_u64(options.seed);
    let noise = Normal::new(0.0, options.noise).map_err(|e| CloudError::BadOption {
        field: "noise".into(),
        message: e.to_string(),
    })?;
    let mut points = Vec::with_capacity(options.points);
    let mut normals = Vec::with_capacity(options.points);
    let mut attempts = 0usize;
    while points.len() < options.points {
        attempts += 1;
        if attempts > 100 * options.points + 1000 {
            return Err(CloudError::BadOption {
                field: "view".into(),
                message: "almost no surface is visible from the viewpoint".into(),
            });
        }
        let mut u = rng.random::<f64>() * total;
        let mut which = parts.len() - 1;
        for (k, a) in areas.iter().enumerate() {
            if u < *a {
                which = k;
                break;
            }
            u -= a;
        }
        let (p, n) = parts[which].sample(&mut rng);
        let hidden = parts
            .iter()
            .enumerate()
            .any(|(k, other)| k != which && other.contains(&p));
        if hidden {
            continue;
        }
        if let Some(v) = options.view {
            let v = Point3::from(v);
            if n.dot(&(v - p)) <= 0.0 {
                continue;
            }
            let start = p + n * 1e-6;
            if parts.iter().any(|part| part.blocks(&start, &v)) {
                continue;
            }
        }
        let jitter = if options.noise > 0.0 {
            Vector3::from_fn(|_, _| noise.sample(&mut rng))
        } else {
            Vector3::zeros()
        };
        points.push(p + jitter);
        normals.push(n);
    }
    Ok(PointCloud {
        points,
        normals: Some(normals),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_points_lie_on_the_faces_with_area_shares() {
        let options = SampleOptions {
            points: 6000,
            seed: 1,
            ..Default::default()
        };
        let shape = Shape::cuboid([0.1, 0.2, 0.3]).expect("box");
        let cloud = sample_shape(&shape, &options).expect("box");
        let normals = cloud.normals.expect("normals");
        let mut on_z = 0;
        for (p, n) in cloud.points.iter().zip(&normals) {
            let axis = n.iamax();
            let half = [0.05, 0.1, 0.15][axis];
            assert!((p[axis] * n[axis] - half).abs() < 1e-12);
            on_z += usize::from(axis == 2);
        }
        // z faces: 2·0.1·0.2 of 2·(0.02 + 0.06 + 0.03) = 0.04 / 0.22.
        let expected = 6000.0 * 0.04 / 0.22;
        assert!(
            (on_z as f64 - expected).abs() < 5.0 * expected.sqrt(),
            "{on_z}"
        );
    }

    #[test]
    fn bad_options_are_named() {
        let shape = Shape::sphere(0.1).expect("sphere");
        let options = SampleOptions {
            points: 0,
            ..Default::default()
        };
        let err = sample_shape(&shape, &options).unwrap_err();
        assert!(err.to_string().contains("points"), "{err}");
    }
}
