//! Clouds sampled from primitives: box, cylinder, sphere and T-shape, centred on the object
//! origin, uniformly over their (outer) surface, with exact outward normals, optional Gaussian
//! noise and an optional single-view simulation (only points seen from a viewpoint are kept,
//! with self-occlusion traced).

use super::{CloudError, PointCloud};
use nalgebra::{Point3, Vector3};
use rand::{rngs::StdRng, RngExt, SeedableRng};
use rand_distr::{Distribution, Normal, StandardNormal};
use std::f64::consts::PI;

/// A solid primitive, centred on the object origin (metres).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Primitive {
    /// An axis-aligned box of edge lengths `size` (x, y, z).
    Box {
        /// Edge lengths (m).
        size: [f64; 3],
    },
    /// A capped cylinder along `z`.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Length along `z` (m).
        height: f64,
    },
    /// A sphere.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// A T: a `stem` box standing on `z`, with a `bar` box on top of it, both centred on the
    /// `z` axis; the whole is shifted so that its bounding box is centred on the origin.
    TShape {
        /// Edge lengths of the vertical stem (m).
        stem: [f64; 3],
        /// Edge lengths of the top bar (m).
        bar: [f64; 3],
    },
}

/// The most points a cloud sampled from a primitive or a mesh may have: grasp generation never
/// needs more than a few tens of thousands, and sampling time grows with the count.
pub const MAX_SAMPLED_POINTS: usize = 1_000_000;

/// The largest noise standard deviation (m): beyond it the cloud no longer shows the shape.
pub const MAX_NOISE: f64 = 1.0;

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

#[derive(Debug, Clone, Copy)]
enum Part {
    Box {
        centre: Vector3<f64>,
        half: Vector3<f64>,
    },
    Cylinder {
        radius: f64,
        half_height: f64,
    },
    Sphere {
        radius: f64,
    },
}

impl Part {
    fn area(&self) -> f64 {
        match *self {
            Part::Box { half, .. } => 8.0 * (half.x * half.y + half.y * half.z + half.x * half.z),
            Part::Cylinder {
                radius,
                half_height,
            } => 2.0 * PI * radius * (radius + 2.0 * half_height),
            Part::Sphere { radius } => 4.0 * PI * radius * radius,
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
            } => {
                let side = 2.0 * half_height;
                let u = rng.random::<f64>() * (side + radius);
                if u < side {
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
                }
            }
            Part::Sphere { radius } => {
                let v = Vector3::from_fn(|_, _| StandardNormal.sample(rng)).normalize();
                (Point3::from(v * radius), v)
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
            } => p.z.abs() <= half_height + TOL && p.x.hypot(p.y) <= radius + TOL,
            Part::Sphere { radius } => p.coords.norm() <= radius + TOL,
        }
    }

    /// Whether the open segment from `a` to `b` passes through the solid's interior.
    fn blocks(&self, a: &Point3<f64>, b: &Point3<f64>) -> bool {
        // Sample the segment finely: the primitives are convex, so a chord through the interior
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
            } => p.z.abs() < half_height - TOL && p.x.hypot(p.y) < radius - TOL,
            Part::Sphere { radius } => p.coords.norm() < radius - TOL,
        }
    }
}

fn positive(field: &str, v: f64) -> Result<f64, CloudError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(CloudError::BadOption {
            field: field.into(),
            message: format!("must be a positive length in metres, got {v}"),
        })
    }
}

fn parts(shape: &Primitive) -> Result<Vec<Part>, CloudError> {
    let half = |field: &str, s: [f64; 3]| -> Result<Vector3<f64>, CloudError> {
        Ok(Vector3::new(
            positive(field, s[0])? / 2.0,
            positive(field, s[1])? / 2.0,
            positive(field, s[2])? / 2.0,
        ))
    };
    Ok(match shape {
        Primitive::Box { size } => vec![Part::Box {
            centre: Vector3::zeros(),
            half: half("box.size", *size)?,
        }],
        Primitive::Cylinder { radius, height } => vec![Part::Cylinder {
            radius: positive("cylinder.radius", *radius)?,
            half_height: positive("cylinder.height", *height)? / 2.0,
        }],
        Primitive::Sphere { radius } => vec![Part::Sphere {
            radius: positive("sphere.radius", *radius)?,
        }],
        Primitive::TShape { stem, bar } => {
            let hs = half("t_shape.stem", *stem)?;
            let hb = half("t_shape.bar", *bar)?;
            let total = 2.0 * (hs.z + hb.z);
            let shift = -total / 2.0;
            vec![
                Part::Box {
                    centre: Vector3::new(0.0, 0.0, shift + hs.z),
                    half: hs,
                },
                Part::Box {
                    centre: Vector3::new(0.0, 0.0, shift + 2.0 * hs.z + hb.z),
                    half: hb,
                },
            ]
        }
    })
}

/// Samples `options.points` points on the outer surface of `shape` with their exact outward
/// normals. With `options.view`, a point is kept only if its normal faces the viewpoint and
/// the segment to the viewpoint crosses no part of the solid; with `options.noise`, positions
/// get isotropic Gaussian noise (the normals stay exact).
pub fn sample_primitive(
    shape: &Primitive,
    options: &SampleOptions,
) -> Result<PointCloud, CloudError> {
    options.check()?;
    let parts = parts(shape)?;
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
        let cloud = sample_primitive(
            &Primitive::Box {
                size: [0.1, 0.2, 0.3],
            },
            &options,
        )
        .expect("box");
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
    fn single_view_of_a_t_keeps_only_visible_points() {
        let shape = Primitive::TShape {
            stem: [0.03, 0.03, 0.1],
            bar: [0.15, 0.03, 0.03],
        };
        let view = [0.0, 0.0, -1.0];
        let options = SampleOptions {
            points: 2000,
            seed: 2,
            view: Some(view),
            ..Default::default()
        };
        let cloud = sample_primitive(&shape, &options).expect("t");
        let normals = cloud.normals.expect("normals");
        for (p, n) in cloud.points.iter().zip(&normals) {
            assert!(n.dot(&(Point3::from(view) - p)) > 0.0);
        }
        // From below, the underside of the bar is visible except where the stem hides it; the
        // top of the bar never is.
        assert!(cloud.points.iter().all(|p| p.z < 0.065 - 1e-9));
        assert!(cloud.points.iter().any(|p| p.z > 0.03 && p.x.abs() > 0.03));
    }

    #[test]
    fn t_shape_has_no_interior_faces() {
        let shape = Primitive::TShape {
            stem: [0.03, 0.03, 0.1],
            bar: [0.15, 0.03, 0.03],
        };
        let cloud = sample_primitive(
            &shape,
            &SampleOptions {
                points: 4000,
                seed: 3,
                ..Default::default()
            },
        )
        .expect("t");
        // The stem's top face (z = 0.1 − 0.065 = 0.035, |x|,|y| < 0.015) is inside the T.
        assert!(!cloud.points.iter().any(|p| (p.z - 0.035).abs() < 1e-9
            && p.x.abs() < 0.015 - 1e-6
            && p.y.abs() < 0.015 - 1e-6));
    }

    #[test]
    fn bad_sizes_are_named() {
        let err = sample_primitive(
            &Primitive::Sphere { radius: -1.0 },
            &SampleOptions::default(),
        )
        .unwrap_err();
        assert!(err.to_string().contains("sphere.radius"), "{err}");
    }
}
