//! Grasp generation at the spec's default budget (50 000 initial grasps, 500 annealing steps,
//! 5 000 query kernels per link) for the built-in Baxter gripper on a 5 000-point cloud, plus the
//! feature pipeline alone; and generation on the T-shape cloud without outliers and with 200
//! outliers at 10 m, 1 km and 1e20 m (the same clouds as `examples/outlier_clouds.rs`): the
//! times must agree within ±20 %.

use criterion::{criterion_group, criterion_main, Criterion};
use graspath::cloud::{compute_features, sample_shape, FeatureParams, SampleOptions};
use graspath::geometry::shape::Shape;
use graspath::grasp::model::{generate, train_file, GenerateOptions};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

#[path = "../examples/shared/t_shape_outliers.rs"]
mod shared;

fn bench(c: &mut Criterion) {
    let demo = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/grasp/demo_box.json");
    let model = train_file(&demo).expect("train");
    let cloud = sample_shape(
        &Shape::cylinder(0.022, 0.12).expect("cylinder"),
        &SampleOptions {
            points: 5000,
            seed: 2,
            ..Default::default()
        },
    )
    .expect("cloud");
    let mut group = c.benchmark_group("generate");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(40))
        .warm_up_time(Duration::from_secs(1));
    group.bench_function("baxter_gripper_5000_points_default_budget", |b| {
        b.iter(|| {
            let options = GenerateOptions {
                seed: 1,
                ..GenerateOptions::default()
            };
            black_box(generate(&model, &cloud, &options, "cylinder", &|_| {}).expect("generate"))
        });
    });
    group.finish();
    let mut group = c.benchmark_group("generate_outliers");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(20))
        .warm_up_time(Duration::from_secs(1));
    for (name, cloud) in shared::t_shape_outlier_clouds() {
        group.bench_function(format!("t_shape_outliers_{name}"), |b| {
            b.iter(|| {
                let options = GenerateOptions {
                    seed: 1,
                    ..GenerateOptions::default()
                };
                black_box(generate(&model, &cloud, &options, "t", &|_| {}).expect("generate"))
            });
        });
    }
    group.finish();
    let mut group = c.benchmark_group("features");
    group.sample_size(10);
    group.bench_function("normals_and_curvatures_5000_points", |b| {
        let params = FeatureParams {
            recompute_normals: true,
            ..FeatureParams::default()
        };
        b.iter(|| black_box(compute_features(&cloud, &params, "cylinder").expect("features")));
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
