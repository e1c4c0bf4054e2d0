//! A 10 × 10 placement map of the paper's two-arm cuboid Pick-and-Place
//! (`examples/pick_and_place_both.yaml`: 21 edge candidates, both arms, 31 samples, up to 8
//! IK branches compared): the object's start swept over x 0.55…0.95 m and y −0.25…0.25 m, on
//! all cores.
//!
//! `cargo bench -p graspath --bench placement_map`

use criterion::{criterion_group, criterion_main, Criterion};
use graspath::placement::{placement_map, FamilyParameter, GridAxis, PlacementGrid};
use graspath::task::{builder_from_file, TaskFile};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

fn map_10x10(c: &mut Criterion) {
    let examples = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let path = examples.join("pick_and_place_both.yaml");
    let file = TaskFile::load(&path).expect("the example loads");
    let builder = builder_from_file(&file, "pick_and_place_both.yaml", &examples)
        .expect("the example builds");
    let candidates = builder
        .clone()
        .build()
        .expect("the example builds")
        .all_candidates()
        .expect("held candidates")
        .into_owned();
    let parameter = FamilyParameter::from_task_file(&file, &candidates);
    let grid = PlacementGrid {
        x: GridAxis::new(0.55, 0.95, 10, "--x").unwrap(),
        y: GridAxis::new(-0.25, 0.25, 10, "--y").unwrap(),
        z: None,
        yaw: None,
    };
    let map = placement_map(&builder, &grid, parameter.clone(), &|| {}).unwrap();
    let selected = map.records.iter().filter(|r| !r.nothing_selected).count();
    eprintln!(
        "10 x 10 map: {} placements, a pair selected at {selected}; {} candidates, {} arms, {} threads",
        map.records.len(),
        candidates.len(),
        map.arms.len(),
        rayon::current_num_threads()
    );
    let mut group = c.benchmark_group("placement_map");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(20));
    group.bench_function("pick_and_place_both_10x10", |b| {
        b.iter(|| black_box(placement_map(&builder, &grid, parameter.clone(), &|| {}).unwrap()));
    });
    group.finish();
}

criterion_group!(benches, map_10x10);
criterion_main!(benches);
