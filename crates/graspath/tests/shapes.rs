//! The shape vocabulary against oracles that share none of its code: closed forms at chosen
//! points, brute-force distances to densely sampled surfaces (parametrised here, in the test),
//! support values against the samples, bounds under random poses, hulls against boxes and
//! meshes against boxes, and the file syntax.

use graspath::geometry::shape::{ConvexMesh, Shape, ShapeError, Stem, TShape, TriMesh};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use rand::{rngs::StdRng, RngExt, SeedableRng};
use std::f64::consts::PI;

/// Points on a box surface on a grid of about `step` (m).
fn box_surface(half: [f64; 3], centre: [f64; 3], step: f64) -> Vec<Point3<f64>> {
    let mut out = Vec::new();
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let nu = (2.0 * half[u] / step).ceil() as usize;
        let nv = (2.0 * half[v] / step).ceil() as usize;
        for side in [-1.0, 1.0] {
            for i in 0..=nu {
                for j in 0..=nv {
                    let mut p = [0.0; 3];
                    p[axis] = side * half[axis];
                    p[u] = -half[u] + 2.0 * half[u] * i as f64 / nu as f64;
                    p[v] = -half[v] + 2.0 * half[v] * j as f64 / nv as f64;
                    out.push(Point3::new(
                        p[0] + centre[0],
                        p[1] + centre[1],
                        p[2] + centre[2],
                    ));
                }
            }
        }
    }
    out
}

/// Points on a capped cylinder's surface (side, both caps) about `z`, centred at `z0`.
fn cylinder_surface(radius: f64, length: f64, z0: f64, step: f64) -> Vec<Point3<f64>> {
    let mut out = Vec::new();
    let na = (2.0 * PI * radius / step).ceil() as usize;
    let nz = (length / step).ceil() as usize;
    for a in 0..na {
        let t = 2.0 * PI * a as f64 / na as f64;
        for k in 0..=nz {
            let z = -length / 2.0 + length * k as f64 / nz as f64;
            out.push(Point3::new(radius * t.cos(), radius * t.sin(), z0 + z));
        }
        let nr = (radius / step).ceil() as usize;
        for r in 0..=nr {
            let rr = radius * r as f64 / nr as f64;
            for side in [-1.0, 1.0] {
                out.push(Point3::new(
                    rr * t.cos(),
                    rr * t.sin(),
                    z0 + side * length / 2.0,
                ));
            }
        }
    }
    out
}

/// Points on a sphere of `radius` about `centre` (latitude–longitude grid).
fn sphere_surface(radius: f64, centre: Vector3<f64>, step: f64) -> Vec<Point3<f64>> {
    let n = (PI * radius / step).ceil() as usize;
    let mut out = Vec::new();
    for i in 0..=n {
        let polar = PI * i as f64 / n as f64;
        let m = ((2.0 * n as f64 * polar.sin()).ceil() as usize).max(1);
        for j in 0..m {
            let az = 2.0 * PI * j as f64 / m as f64;
            out.push(Point3::from(
                centre
                    + radius
                        * Vector3::new(polar.sin() * az.cos(), polar.sin() * az.sin(), polar.cos()),
            ));
        }
    }
    out
}

/// A capsule's surface: the cylinder side plus the two hemispheres.
fn capsule_surface(radius: f64, length: f64, step: f64) -> Vec<Point3<f64>> {
    let mut out: Vec<Point3<f64>> = cylinder_surface(radius, length, 0.0, step)
        .into_iter()
        .filter(|p| (p.x.hypot(p.y) - radius).abs() < 1e-12)
        .collect();
    for (sign, z) in [(1.0, length / 2.0), (-1.0, -length / 2.0)] {
        out.extend(
            sphere_surface(radius, Vector3::new(0.0, 0.0, z), step)
                .into_iter()
                .filter(|p| sign * (p.z - z) >= 0.0),
        );
    }
    out
}

fn nearest(samples: &[Point3<f64>], p: &Point3<f64>) -> f64 {
    samples
        .iter()
        .map(|s| (s - p).norm())
        .fold(f64::INFINITY, f64::min)
}

/// A test-side membership oracle.
type Inside = Box<dyn Fn(&Point3<f64>) -> bool>;

/// The shapes under test with their sampled surfaces, the spacing bound (m) of the samples
/// and a test-side membership oracle.
struct Case {
    shape: Shape,
    surface: Vec<Point3<f64>>,
    spacing: f64,
    inside: Inside,
}

fn cases() -> Vec<Case> {
    let step = 0.004;
    let (br, bl) = (0.03, 0.12);
    let t_bar = [0.08, 0.24, 0.03];
    let (tr, tl) = (0.02, 0.12);
    let t_z0 = t_bar[2] / 2.0 + tl / 2.0;
    let in_box =
        |p: &Point3<f64>, h: [f64; 3], c: [f64; 3]| (0..3).all(|k| (p[k] - c[k]).abs() <= h[k]);
    let t_surface: Vec<Point3<f64>> = box_surface([0.04, 0.12, 0.015], [0.0; 3], step)
        .into_iter()
        .filter(|p| !(p.x.hypot(p.y) < tr && p.z > 0.0))
        .chain(
            cylinder_surface(tr, tl, t_z0, step)
                .into_iter()
                .filter(|p| p.z > t_bar[2] / 2.0 + 1e-12),
        )
        .collect();
    let box_t_surface: Vec<Point3<f64>> = box_surface([0.08, 0.02, 0.02], [0.0; 3], step)
        .into_iter()
        .filter(|p| !(p.x.abs() < 0.015 && p.y.abs() < 0.015 && p.z < 0.0))
        .chain(
            box_surface([0.015, 0.015, 0.05], [0.0, 0.0, -0.07], step)
                .into_iter()
                .filter(|p| p.z < -0.02 - 1e-12),
        )
        .collect();
    vec![
        Case {
            shape: Shape::cuboid([0.06, 0.1, 0.2]).unwrap(),
            surface: box_surface([0.03, 0.05, 0.1], [0.0; 3], step),
            spacing: step,
            inside: Box::new(move |p| in_box(p, [0.03, 0.05, 0.1], [0.0; 3])),
        },
        Case {
            shape: Shape::cylinder(br, bl).unwrap(),
            surface: cylinder_surface(br, bl, 0.0, step),
            spacing: step,
            inside: Box::new(move |p| p.x.hypot(p.y) <= br && p.z.abs() <= bl / 2.0),
        },
        Case {
            shape: Shape::sphere(0.05).unwrap(),
            surface: sphere_surface(0.05, Vector3::zeros(), step),
            spacing: step,
            inside: Box::new(|p| p.coords.norm() <= 0.05),
        },
        Case {
            shape: Shape::capsule(0.04, 0.1).unwrap(),
            surface: capsule_surface(0.04, 0.1, step),
            spacing: step,
            inside: Box::new(|p| {
                let z = p.z.clamp(-0.05, 0.05);
                (p.coords - Vector3::new(0.0, 0.0, z)).norm() <= 0.04
            }),
        },
        Case {
            shape: Shape::TShape(TShape::with_round_stem(t_bar, tr, tl).unwrap()),
            surface: t_surface,
            spacing: step,
            inside: Box::new(move |p| {
                in_box(p, [0.04, 0.12, 0.015], [0.0; 3])
                    || (p.x.hypot(p.y) <= tr && (p.z - t_z0).abs() <= tl / 2.0)
            }),
        },
        Case {
            // A T upside down in its own frame is still a T-shape; here a square stem.
            shape: Shape::TShape(
                TShape::new(
                    [0.16, 0.04, 0.04],
                    serde_json::from_str::<Stem>(r#"{"box": {"size": [0.03, 0.03, 0.1]}}"#)
                        .unwrap(),
                )
                .unwrap(),
            ),
            surface: box_t_surface
                .into_iter()
                .map(|p| Point3::new(p.x, -p.y, -p.z))
                .collect(),
            spacing: step,
            inside: Box::new(move |p| {
                in_box(p, [0.08, 0.02, 0.02], [0.0; 3])
                    || in_box(p, [0.015, 0.015, 0.05], [0.0, 0.0, 0.07])
            }),
        },
    ]
}

fn random_point(rng: &mut StdRng, scale: f64) -> Point3<f64> {
    Point3::new(
        (rng.random::<f64>() * 2.0 - 1.0) * scale,
        (rng.random::<f64>() * 2.0 - 1.0) * scale,
        (rng.random::<f64>() * 2.0 - 1.0) * scale,
    )
}

#[test]
fn closed_forms_at_chosen_points() {
    let b = Shape::cuboid([0.2, 0.4, 0.6]).unwrap();
    assert!((b.signed_distance(&Point3::origin()) + 0.1).abs() < 1e-15);
    assert!(
        (b.signed_distance(&Point3::new(0.4, 0.6, 0.3)) - (0.09f64 + 0.16).sqrt()).abs() < 1e-12
    );
    let c = Shape::cylinder(0.05, 0.2).unwrap();
    assert!((c.signed_distance(&Point3::new(0.0, 0.15, 0.0)) - 0.1).abs() < 1e-15);
    assert!((c.signed_distance(&Point3::new(0.0, 0.0, 0.09)) + 0.01).abs() < 1e-15);
    // Beyond the rim: 3-4-5.
    assert!((c.signed_distance(&Point3::new(0.08, 0.0, 0.14)) - 0.05).abs() < 1e-12);
    let s = Shape::sphere(0.1).unwrap();
    assert!((s.signed_distance(&Point3::new(0.0, 0.3, 0.0)) - 0.2).abs() < 1e-15);
    let k = Shape::capsule(0.05, 0.3).unwrap();
    assert!((k.signed_distance(&Point3::new(0.0, 0.0, 0.25)) - 0.05).abs() < 1e-15);
    assert!((k.signed_distance(&Point3::new(0.03, 0.04, 0.15 + 0.0)) - 0.0).abs() < 1e-15);
    assert!((k.signed_distance(&Point3::new(0.0, 0.0, 0.0)) + 0.05).abs() < 1e-15);
    let t = Shape::TShape(TShape::with_round_stem([0.1, 0.3, 0.04], 0.02, 0.1).unwrap());
    assert!(
        t.signed_distance(&Point3::new(0.0, 0.0, 0.07)) < 0.0,
        "inside the stem"
    );
    // Beside the stem, above the bar: 0.03 m from the stem's side, 0.01 m above the bar.
    assert!((t.signed_distance(&Point3::new(0.0, 0.05, 0.03)) - 0.01).abs() < 1e-15);
    assert!((t.signed_distance(&Point3::new(0.0, 0.0, 0.17)) - 0.05).abs() < 1e-15);
}

#[test]
fn signed_distances_match_sampled_surfaces() {
    let mut rng = StdRng::seed_from_u64(11);
    for case in cases() {
        let bound = case.shape.aabb();
        let scale = (bound.max - bound.min).norm();
        for _ in 0..400 {
            let p = random_point(&mut rng, scale);
            let sd = case.shape.signed_distance(&p);
            let brute = nearest(&case.surface, &p);
            let inside = (case.inside)(&p);
            assert_eq!(
                sd <= 0.0,
                inside,
                "{}: sign at {p}: {sd}",
                case.shape.kind()
            );
            if inside && matches!(case.shape, Shape::TShape(_)) {
                // Inside a T the depth is a lower bound (see TShape).
                assert!(
                    -sd <= brute + case.spacing,
                    "{}: {sd} vs {brute}",
                    case.shape.kind()
                );
            } else {
                // The true distance lies within the sample spacing below the nearest sample.
                assert!(
                    sd.abs() <= brute + 1e-12 && sd.abs() >= brute - case.spacing,
                    "{}: at {p}: {sd} vs sampled {brute}",
                    case.shape.kind()
                );
            }
        }
    }
}

#[test]
fn supports_and_bounds_match_sampled_surfaces() {
    let mut rng = StdRng::seed_from_u64(12);
    for case in cases() {
        for _ in 0..60 {
            let d = random_point(&mut rng, 1.0).coords;
            let s = case.shape.support(&d);
            let best = case
                .surface
                .iter()
                .map(|p| p.coords.dot(&d))
                .fold(f64::NEG_INFINITY, f64::max);
            let value = s.coords.dot(&d);
            assert!(
                value >= best - 1e-12,
                "{}: support {value} < {best}",
                case.shape.kind()
            );
            assert!(
                value <= best + case.spacing * d.norm(),
                "{}",
                case.shape.kind()
            );
            assert!(
                case.shape.signed_distance(&s).abs() < 1e-9,
                "{} support on surface",
                case.shape.kind()
            );
        }
        for _ in 0..20 {
            let pose = Isometry3::from_parts(
                Translation3::from(random_point(&mut rng, 1.0).coords),
                UnitQuaternion::from_scaled_axis(random_point(&mut rng, 3.0).coords),
            );
            let aabb = case.shape.aabb_at(&pose);
            let moved: Vec<Point3<f64>> = case.surface.iter().map(|p| pose * p).collect();
            assert!(
                moved.iter().all(|p| aabb.contains(p, 1e-12)),
                "{}",
                case.shape.kind()
            );
            for k in 0..3 {
                let hi = moved.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max);
                let lo = moved.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
                assert!(aabb.max[k] - hi <= case.spacing && lo - aabb.min[k] <= case.spacing);
            }
        }
    }
}

fn cube_corners(h: f64) -> Vec<Point3<f64>> {
    let mut v = Vec::new();
    for z in [-h, h] {
        for y in [-h, h] {
            for x in [-h, h] {
                v.push(Point3::new(x, y, z));
            }
        }
    }
    v
}

/// The 12 triangles of a cube over [`cube_corners`], outward.
fn cube_triangles() -> Vec<[u32; 3]> {
    vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [1, 3, 7],
        [1, 7, 5],
        [3, 2, 6],
        [3, 6, 7],
        [2, 0, 4],
        [2, 4, 6],
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The hull of a cube's corners plus interior points is the cube.
    #[test]
    fn hull_of_a_cube_is_the_box(seed in 0u64..1000, x in -0.2..0.2f64, y in -0.2..0.2f64, z in -0.2..0.2f64) {
        let mut rng = StdRng::seed_from_u64(seed);
        let mut points = cube_corners(0.05);
        for _ in 0..30 {
            points.push(random_point(&mut rng, 0.049));
        }
        // Shuffle so the hull's start does not depend on the order above.
        for i in (1..points.len()).rev() {
            let j = rng.random_range(0..=i);
            points.swap(i, j);
        }
        let hull = ConvexMesh::new(points).unwrap();
        prop_assert_eq!(hull.hull_vertices().len(), 8);
        let cube = Shape::cuboid([0.1; 3]).unwrap();
        let p = Point3::new(x, y, z);
        let a = cube.signed_distance(&p);
        let b = Shape::ConvexMesh(hull.clone()).signed_distance(&p);
        prop_assert!((a - b).abs() < 1e-12, "{} vs {}", a, b);
        let closed = TriMesh::new(cube_corners(0.05), cube_triangles()).unwrap();
        prop_assert!(closed.is_closed());
        prop_assert!((closed.signed_distance(&p) - a).abs() < 1e-12);
        // Reversed orientation: the same signed distance.
        let flipped: Vec<[u32; 3]> = cube_triangles().into_iter().map(|[a, b, c]| [a, c, b]).collect();
        let inward = TriMesh::new(cube_corners(0.05), flipped).unwrap();
        prop_assert!((inward.signed_distance(&p) - a).abs() < 1e-12);
        // Without its top: a surface, distances unsigned.
        let open = TriMesh::new(cube_corners(0.05), cube_triangles()[..10].to_vec()).unwrap();
        prop_assert!(!open.is_closed());
        prop_assert!(open.signed_distance(&p) >= 0.0);
    }

    /// Every input point lies in its hull, the support equals the brute-force maximum over the
    /// points, and hull vertices lie on the hull's surface.
    #[test]
    fn random_hulls_hold_their_points(seed in 0u64..10_000, n in 4usize..80) {
        let mut rng = StdRng::seed_from_u64(seed);
        let points: Vec<Point3<f64>> = (0..n).map(|_| random_point(&mut rng, 0.1)).collect();
        let Ok(hull) = ConvexMesh::new(points.clone()) else { return Ok(()) };
        let shape = Shape::ConvexMesh(hull.clone());
        for p in &points {
            prop_assert!(shape.signed_distance(p) <= 1e-9);
        }
        for v in hull.hull_vertices() {
            prop_assert!(shape.signed_distance(v).abs() <= 1e-9);
        }
        for _ in 0..10 {
            let d = random_point(&mut rng, 1.0).coords;
            let best = points.iter().map(|p| p.coords.dot(&d)).fold(f64::NEG_INFINITY, f64::max);
            prop_assert!((shape.support(&d).coords.dot(&d) - best).abs() < 1e-12);
        }
    }
}

#[test]
fn hull_of_sphere_points_approaches_the_sphere() {
    let points = sphere_surface(0.1, Vector3::zeros(), 0.01);
    let hull = Shape::ConvexMesh(ConvexMesh::new(points).unwrap());
    let sphere = Shape::sphere(0.1).unwrap();
    let mut rng = StdRng::seed_from_u64(3);
    for _ in 0..200 {
        let p = random_point(&mut rng, 0.2);
        let (a, b) = (sphere.signed_distance(&p), hull.signed_distance(&p));
        // The hull lies inside the sphere, within the chord sag of a 0.01 m grid.
        assert!(b >= a - 1e-12 && b - a < 0.002, "{a} vs {b} at {p}");
    }
}

#[test]
fn file_syntax_reads_writes_and_names_the_field() {
    let texts = [
        r#"{"box":{"size":[0.1,0.2,0.3]}}"#,
        r#"{"cylinder":{"radius":0.03,"length":0.2}}"#,
        r#"{"sphere":{"radius":0.05}}"#,
        r#"{"capsule":{"radius":0.05,"length":0.3}}"#,
        r#"{"t_shape":{"bar":[0.08,0.24,0.03],"stem":{"cylinder":{"radius":0.02,"length":0.12}}}}"#,
        r#"{"convex_mesh":{"points":[[0.0,0.0,0.0],[1.0,0.0,0.0],[0.0,1.0,0.0],[0.0,0.0,1.0]]}}"#,
        r#"{"triangle_mesh":{"vertices":[[0.0,0.0,0.0],[1.0,0.0,0.0],[0.0,1.0,0.0]],"triangles":[[0,1,2]]}}"#,
    ];
    for text in texts {
        let shape: Shape = serde_json::from_str(text).unwrap();
        assert_eq!(serde_json::to_string(&shape).unwrap(), text);
        let yaml: Shape = serde_saphyr::from_str(text).unwrap();
        assert_eq!(yaml, shape);
    }
    let yaml: Shape = serde_saphyr::from_str(
        "t_shape: { bar: [0.08, 0.24, 0.03], stem: { box: { size: [0.02, 0.02, 0.1] } } }",
    )
    .unwrap();
    assert!((yaml.aabb().max.z - 0.115).abs() < 1e-15);
    let bad = [
        (r#"{"box":{"size":[0.1,-0.2,0.3]}}"#, "box.size[1]"),
        (r#"{"box":{"size":[0.1,0.2]}}"#, "array"),
        (
            r#"{"cylinder":{"radius":0.03,"height":0.2}}"#,
            "unknown field `height`",
        ),
        (r#"{"sphere":{"radius":0}}"#, "sphere.radius"),
        (r#"{"cone":{"radius":1}}"#, "unknown variant `cone`"),
        (
            r#"{"t_shape":{"bar":[1,1,1],"stem":{"box":{"size":[1,1,1]}},"handle_radius":1}}"#,
            "unknown field `handle_radius`",
        ),
        // The spelling of earlier task files, `{bar, handle_radius, handle_length}`, is gone.
        (
            r#"{"t_shape":{"bar":[1,1,1],"handle_radius":0.02,"handle_length":1}}"#,
            "unknown field `handle_radius`",
        ),
        (r#"{"t_shape":{"bar":[1,1,1]}}"#, "missing field `stem`"),
        (
            r#"{"convex_mesh":{"points":[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}}"#,
            "span no volume",
        ),
        (
            r#"{"triangle_mesh":{"vertices":[[0,0,0]],"triangles":[[0,1,2]]}}"#,
            "triangle_mesh.triangles[0]",
        ),
    ];
    for (text, fragment) in bad {
        let err = serde_json::from_str::<Shape>(text).unwrap_err().to_string();
        assert!(err.contains(fragment), "{text}: {err}");
    }
    assert!(matches!(
        Shape::capsule(f64::NAN, 1.0),
        Err(ShapeError::NotPositive { .. })
    ));
}
