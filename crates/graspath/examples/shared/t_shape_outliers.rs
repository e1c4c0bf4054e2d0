//! The T-shape cloud of `examples/grasp/t_shape.json` (5 000 points with normals), alone and
//! with 200 outliers at 10 m, 1 km and 1e20 m from the object (random directions, seeded;
//! normals pointing back at the object). Shared by `examples/outlier_clouds.rs` and
//! `benches/generate.rs` (each includes this file with `#[path]`), so both measure the same
//! clouds.

use graspath::cloud::{load_cloud_argument, PointCloud};
use nalgebra::{Point3, Vector3};
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use std::path::Path;

/// The cloud plus `count` points at distance `distance` (m) in random directions (seed 17).
fn with_outliers(clean: &PointCloud, distance: f64, count: usize) -> PointCloud {
    let mut cloud = clean.clone();
    let mut rng = StdRng::seed_from_u64(17);
    let normals = cloud.normals.as_mut().expect("normals");
    for _ in 0..count {
        let v = Vector3::<f64>::from_fn(|_, _| StandardNormal.sample(&mut rng)).normalize();
        cloud.points.push(Point3::from(v * distance));
        normals.push(-v);
    }
    cloud
}

/// `("none", the T-shape cloud)`, then `("10m" | "1km" | "1e20m", the cloud with 200
/// outliers at that distance)`.
pub fn t_shape_outlier_clouds() -> Vec<(&'static str, PointCloud)> {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/grasp/t_shape.json");
    let clean = load_cloud_argument(&source).expect("examples/grasp/t_shape.json");
    let mut clouds = vec![("none", clean.clone())];
    for (name, distance) in [("10m", 10.0), ("1km", 1e3), ("1e20m", 1e20)] {
        clouds.push((name, with_outliers(&clean, distance, 200)));
    }
    clouds
}
