//! Surface features against closed forms: normals and PCL principal curvatures on a plane, a
//! sphere and a cylinder of known radius; robustness to noise and sampling density;
//! identical results at any thread count.

use graspath::cloud::{
    compute_features, estimate_normals, principal_curvatures, CloudShape, FeatureParams,
    LegacyTShape, NormalOrientation, PointCloud, PointIndex, SampleOptions, SurfaceFeature,
};
use graspath::geometry::shape::Shape;
use nalgebra::{Point3, Vector3};

const R_NEIGHBOURS: f64 = 0.015;

fn cloud(shape: CloudShape, points: usize, noise: f64) -> PointCloud {
    shape
        .sample(&SampleOptions {
            points,
            seed: 11,
            view: None,
            noise,
        })
        .expect("sample")
}

/// For a surface of radius R and a neighbourhood ball of radius r ≪ R, the projected normals
/// vary by `sin φ ≈ s/R` over a disc of radius r in arc length: variance `r²/(4R²)` per curved
/// direction.
fn expected_pc(radius: f64) -> f64 {
    R_NEIGHBOURS * R_NEIGHBOURS / (4.0 * radius * radius)
}

fn features(cloud: &PointCloud, recompute: bool) -> Vec<SurfaceFeature> {
    let params = FeatureParams {
        recompute_normals: recompute,
        ..FeatureParams::default()
    };
    compute_features(cloud, &params, "test").expect("features")
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[test]
fn plane_has_zero_curvature_and_the_face_normal() {
    let c = cloud(Shape::cuboid([0.3, 0.3, 0.02]).unwrap().into(), 8000, 0.0);
    let f = features(&c, true);
    for x in f
        .iter()
        .filter(|x| x.position.z > 0.0099 && x.position.x.abs() < 0.12 && x.position.y.abs() < 0.12)
    {
        assert!(x.curvature[0] < 1e-12, "pc1 = {}", x.curvature[0]);
        assert!(
            (x.normal - Vector3::z()).norm() < 1e-9,
            "normal {}",
            x.normal
        );
    }
}

#[test]
fn sphere_curvatures_are_equal_and_match_the_closed_form() {
    let radius = 0.05;
    let c = cloud(Shape::sphere(radius).unwrap().into(), 12000, 0.0);
    let f = features(&c, false);
    let pc1 = median(f.iter().map(|x| x.curvature[0]).collect());
    let pc2 = median(f.iter().map(|x| x.curvature[1]).collect());
    let expected = expected_pc(radius);
    assert!(
        (pc1 / expected - 1.0).abs() < 0.2,
        "pc1 {pc1} vs {expected}"
    );
    assert!(
        (pc2 / expected - 1.0).abs() < 0.25,
        "pc2 {pc2} vs {expected}"
    );
    // Estimated normals against the exact ones.
    let index = PointIndex::new(&c.points);
    let estimated = estimate_normals(
        &c.points,
        &index,
        R_NEIGHBOURS,
        NormalOrientation::AwayFromCentroid,
    );
    let exact = c.normals.as_ref().expect("normals");
    for (e, n) in estimated.iter().zip(exact) {
        assert!(e.angle(n).to_degrees() < 2.0);
    }
}

#[test]
fn cylinder_curves_one_way_along_the_circumference() {
    for radius in [0.025, 0.04] {
        let c = cloud(Shape::cylinder(radius, 0.3).unwrap().into(), 15000, 0.0);
        let f = features(&c, false);
        let side: Vec<&SurfaceFeature> = f.iter().filter(|x| x.position.z.abs() < 0.1).collect();
        let pc1 = median(side.iter().map(|x| x.curvature[0]).collect());
        let pc2 = median(side.iter().map(|x| x.curvature[1]).collect());
        let expected = expected_pc(radius);
        assert!(
            (pc1 / expected - 1.0).abs() < 0.2,
            "R={radius}: pc1 {pc1} vs {expected}"
        );
        assert!(pc2 < 0.05 * pc1, "R={radius}: pc2 {pc2} vs pc1 {pc1}");
        // The principal direction (frame x) is the circumferential tangent: ⟂ axis and ⟂ normal.
        for x in &side {
            let d = x.frame * Vector3::x();
            assert!(d.z.abs() < 0.05, "direction {d} at {}", x.position);
            let radial = Vector3::new(x.position.x, x.position.y, 0.0).normalize();
            assert!(d.dot(&radial).abs() < 0.05);
        }
    }
    // Ordering: a thinner cylinder curves more, a sphere curves both ways.
    let thin = features(
        &cloud(Shape::cylinder(0.02, 0.3).unwrap().into(), 12000, 0.0),
        false,
    );
    let thick = features(
        &cloud(Shape::cylinder(0.05, 0.3).unwrap().into(), 12000, 0.0),
        false,
    );
    let m = |f: &[SurfaceFeature], k: usize| {
        median(
            f.iter()
                .filter(|x| x.position.z.abs() < 0.1)
                .map(|x| x.curvature[k])
                .collect(),
        )
    };
    assert!(m(&thin, 0) > 3.0 * m(&thick, 0));
}

#[test]
fn robust_to_noise_and_sampling_density() {
    let radius = 0.04;
    let expected = expected_pc(radius);
    for (points, noise) in [(3000, 0.0), (30000, 0.0), (12000, 0.0005)] {
        let mut c = cloud(Shape::cylinder(radius, 0.3).unwrap().into(), points, noise);
        let exact = c.normals.take().expect("normals");
        let f = features(&c, true);
        let side: Vec<usize> = (0..f.len())
            .filter(|&i| f[i].position.z.abs() < 0.1)
            .collect();
        let angle = median(
            side.iter()
                .map(|&i| f[i].normal.angle(&exact[i]).to_degrees())
                .collect(),
        );
        assert!(
            angle < 3.0,
            "{points} points, noise {noise}: median normal error {angle}°"
        );
        let pc1 = median(side.iter().map(|&i| f[i].curvature[0]).collect());
        assert!(
            (pc1 / expected - 1.0).abs() < 0.35,
            "{points} points, noise {noise}: pc1 {pc1} vs {expected}"
        );
    }
}

#[test]
fn same_bits_at_any_thread_count() {
    let c = cloud(
        CloudShape::LegacyT(LegacyTShape::new([0.03, 0.03, 0.1], [0.12, 0.03, 0.03]).unwrap()),
        4000,
        0.0003,
    );
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| features(&c, true))
    };
    assert_eq!(run(1), run(2));
    let index = PointIndex::new(&c.points);
    let n = c.normals.clone().expect("normals");
    let a = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool")
        .install(|| principal_curvatures(&c.points, &n, &index, 0.015));
    let b = principal_curvatures(&c.points, &n, &index, 0.015);
    assert_eq!(a, b);
    let _ = Point3::<f64>::origin();
}
