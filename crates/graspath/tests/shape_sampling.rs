//! Clouds sampled on every shape of the one vocabulary, and the proximity queries the grasp
//! model uses, against independent oracles: the shapes' signed distances, finite differences,
//! closed-form area shares and brute force over dense surface samples.

use graspath::cloud::{sample_shape, PointCloud, SampleOptions};
use graspath::geometry::shape::{ConvexMesh, Cylinder, Shape, Stem, TShape, TriMesh};
use nalgebra::{Point3, Vector3};
use rand::{rngs::StdRng, RngExt, SeedableRng};

fn cube_corners(h: f64) -> Vec<Point3<f64>> {
    let mut v = Vec::new();
    for x in [-h, h] {
        for y in [-h, h] {
            for z in [-h, h] {
                v.push(Point3::new(x, y, z));
            }
        }
    }
    v
}

/// A closed cube mesh of half edge `h`, wound counter-clockwise seen from outside.
fn cube_mesh(h: f64) -> TriMesh {
    let v = |x: f64, y: f64, z: f64| Point3::new(x * h, y * h, z * h);
    TriMesh::new(
        vec![
            v(-1., -1., -1.),
            v(1., -1., -1.),
            v(1., 1., -1.),
            v(-1., 1., -1.),
            v(-1., -1., 1.),
            v(1., -1., 1.),
            v(1., 1., 1.),
            v(-1., 1., 1.),
        ],
        vec![
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
    )
    .unwrap()
}

fn shapes() -> Vec<(&'static str, Shape)> {
    vec![
        ("box", Shape::cuboid([0.05, 0.04, 0.14]).unwrap()),
        ("cylinder", Shape::cylinder(0.022, 0.12).unwrap()),
        ("sphere", Shape::sphere(0.05).unwrap()),
        ("capsule", Shape::capsule(0.02, 0.08).unwrap()),
        (
            "t_shape_box_stem",
            Shape::TShape(
                TShape::new(
                    [0.16, 0.045, 0.04],
                    Stem::Box(graspath::geometry::shape::Cuboid::new([0.04, 0.045, 0.1]).unwrap()),
                )
                .unwrap(),
            ),
        ),
        (
            "t_shape_round_stem",
            Shape::TShape(
                TShape::new(
                    [0.16, 0.06, 0.03],
                    Stem::Cylinder(Cylinder::new(0.015, 0.09).unwrap()),
                )
                .unwrap(),
            ),
        ),
        (
            "convex_mesh",
            Shape::ConvexMesh(ConvexMesh::new(cube_corners(0.03)).unwrap()),
        ),
        ("triangle_mesh", Shape::TriangleMesh(cube_mesh(0.03))),
    ]
}

fn sample(shape: &Shape, points: usize, seed: u64) -> PointCloud {
    sample_shape(
        shape,
        &SampleOptions {
            points,
            seed,
            ..Default::default()
        },
    )
    .unwrap()
}

#[test]
fn samples_lie_on_the_surface_with_outward_normals() {
    let h = 1e-7;
    for (name, shape) in shapes() {
        let cloud = sample(&shape, 3000, 4);
        assert_eq!(cloud.len(), 3000, "{name}");
        for (p, n) in cloud.points.iter().zip(cloud.normals.as_ref().unwrap()) {
            assert!(shape.signed_distance(p).abs() < 1e-12, "{name}: {p}");
            assert!((n.norm() - 1.0).abs() < 1e-12, "{name}");
            // Outward along the normal; and no interior face of a T (a step back along the
            // normal of an interior face would stay inside the other part, but a step forward
            // would not leave the solid).
            assert!(
                shape.signed_distance(&(p + n * h)) > 0.5 * h,
                "{name}: {p} {n}"
            );
            assert!(shape.signed_distance(&(p - n * h)) < 0.0, "{name}: {p} {n}");
        }
    }
}

#[test]
fn area_shares_match_closed_forms() {
    let points = 20000;
    let within = |count: usize, share: f64, name: &str| {
        let expected = points as f64 * share;
        let sigma = (expected * (1.0 - share)).sqrt();
        assert!(
            (count as f64 - expected).abs() < 5.0 * sigma,
            "{name}: {count} vs {expected}"
        );
    };
    // Capsule: caps (a sphere, 4πr²) against the side (2πr·l).
    let (r, l) = (0.02, 0.08);
    let cloud = sample(&Shape::capsule(r, l).unwrap(), points, 8);
    let on_caps = cloud.points.iter().filter(|p| p.z.abs() > l / 2.0).count();
    within(on_caps, 4.0 * r / (4.0 * r + 2.0 * l), "capsule caps");
    // T with a box stem: the stem's exposed area (four sides and its top; its bottom is on the
    // bar) over the T's outer area.
    let (bar, stem) = ([0.16, 0.045, 0.04], [0.04, 0.045, 0.1]);
    let shape = &shapes()[4].1;
    let cloud = sample(shape, points, 9);
    let on_stem = cloud
        .points
        .iter()
        .filter(|p| p.z > bar[2] / 2.0 + 1e-9)
        .count();
    let box_area = |s: [f64; 3]| 2.0 * (s[0] * s[1] + s[1] * s[2] + s[0] * s[2]);
    let stem_exposed = box_area(stem) - stem[0] * stem[1];
    // The bar loses the stem's footprint.
    let total = box_area(bar) - stem[0] * stem[1] + stem_exposed;
    within(on_stem, stem_exposed / total, "T stem");
}

#[test]
fn proximity_is_the_signed_distance_and_a_closest_surface_point() {
    let mut rng = StdRng::seed_from_u64(3);
    for (name, shape) in shapes() {
        let surface = sample(&shape, 40000, 6);
        let r = shape.bounding_radius();
        for _ in 0..150 {
            let p = Point3::from(Vector3::from_fn(|_, _| {
                (rng.random::<f64>() * 2.0 - 1.0) * 1.5 * r
            }));
            let prox = shape.proximity(&p);
            let sd = shape.signed_distance(&p);
            assert_eq!(prox.signed_distance.to_bits(), sd.to_bits(), "{name}: {p}");
            let inside_t = matches!(shape, Shape::TShape(_)) && sd < 0.0;
            assert!(
                shape.signed_distance(&prox.closest).abs() < 1e-12 || inside_t,
                "{name}"
            );
            if inside_t {
                continue;
            }
            assert!(
                ((p - prox.closest).norm() - sd.abs()).abs() < 1e-12,
                "{name}: {p}"
            );
            // Brute force: no surface sample is nearer than |sd|, and some is almost as near.
            let nearest = surface
                .points
                .iter()
                .map(|q| (p - q).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest >= sd.abs() - 1e-12, "{name}: {p}: {nearest} < {sd}");
            assert!(
                nearest < sd.abs() + 0.15 * r,
                "{name}: {p}: {nearest} vs {sd}"
            );
        }
    }
}

#[test]
fn bounding_radius_is_the_farthest_surface_point() {
    for (name, shape) in shapes() {
        let r = shape.bounding_radius();
        let cloud = sample(&shape, 40000, 2);
        let far = cloud
            .points
            .iter()
            .map(|p| p.coords.norm())
            .fold(0.0, f64::max);
        assert!(far <= r + 1e-12, "{name}: {far} > {r}");
        assert!(far > 0.97 * r, "{name}: {far} vs {r}");
        // The support points of the axes lie within the radius as well.
        for d in [Vector3::x(), Vector3::y(), Vector3::z(), -Vector3::z()] {
            assert!(shape.support(&d).coords.norm() <= r + 1e-12, "{name}");
        }
    }
}

#[test]
fn a_box_and_its_hull_agree_everywhere() {
    let boxed = Shape::cuboid([0.04; 3]).unwrap();
    let hull = Shape::ConvexMesh(ConvexMesh::new(cube_corners(0.02)).unwrap());
    let probe = sample(&Shape::sphere(0.03).unwrap(), 300, 1);
    for (k, p) in probe.points.iter().enumerate() {
        let p = Point3::from(p.coords * (k as f64 / 300.0 + 0.2));
        let a = boxed.proximity(&p);
        let b = hull.proximity(&p);
        assert!((a.signed_distance - b.signed_distance).abs() < 1e-12, "{p}");
        assert!((a.closest - b.closest).norm() < 1e-12, "{p}");
    }
}

#[test]
fn a_view_keeps_only_the_surface_it_sees() {
    let view = Point3::new(0.0, 0.0, -1.0);
    for (name, shape) in shapes() {
        let cloud = sample_shape(
            &shape,
            &SampleOptions {
                points: 1500,
                seed: 2,
                view: Some(view.coords.into()),
                ..Default::default()
            },
        )
        .unwrap();
        for (p, n) in cloud.points.iter().zip(cloud.normals.as_ref().unwrap()) {
            assert!(n.dot(&(view - p)) > 0.0, "{name}");
        }
    }
    // From below, the top of a T's stem is hidden by nothing but faces away; the underside of
    // the bar is seen, its top never.
    let t = &shapes()[4].1;
    let cloud = sample_shape(
        t,
        &SampleOptions {
            points: 1500,
            seed: 2,
            view: Some([0.0, 0.0, -1.0]),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(cloud.points.iter().all(|p| p.z < -0.02 + 1e-12));
}
