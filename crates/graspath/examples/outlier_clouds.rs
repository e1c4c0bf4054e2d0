//! Writes the T-shape cloud of `examples/grasp/t_shape.json` (5 000 points with normals) as
//! PLY, alone and with 200 outliers at 10 m, 1 km and 1e20 m from the object (random
//! directions, seeded; normals pointing back at the object), for measuring `graspath
//! generate` on scans with far outliers (BENCHMARKS.md).
//!
//! ```text
//! cargo run --release -p graspath --example outlier_clouds -- DIR
//! ```
//!
//! writes `DIR/t_shape.ply`, `DIR/t_shape_10m.ply`, `DIR/t_shape_1km.ply`,
//! `DIR/t_shape_1e20m.ply`. The `generate` criterion bench builds the same clouds in memory.

use graspath::cloud::{sample_primitive, write_cloud, PointCloud, Primitive, SampleOptions};
use nalgebra::{Point3, Vector3};
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use std::path::PathBuf;

/// The T-shape cloud plus `count` points at distance `distance` (m) in random directions.
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

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    let clean = sample_primitive(
        &Primitive::TShape {
            stem: [0.04, 0.045, 0.1],
            bar: [0.16, 0.045, 0.04],
        },
        &SampleOptions {
            points: 5000,
            seed: 3,
            ..Default::default()
        },
    )
    .expect("t-shape");
    write_cloud(&dir.join("t_shape.ply"), &clean).expect("write");
    for (name, distance) in [("10m", 10.0), ("1km", 1e3), ("1e20m", 1e20)] {
        let cloud = with_outliers(&clean, distance, 200);
        let path = dir.join(format!("t_shape_{name}.ply"));
        write_cloud(&path, &cloud).expect("write");
        println!("wrote {} ({} points)", path.display(), cloud.len());
    }
}
