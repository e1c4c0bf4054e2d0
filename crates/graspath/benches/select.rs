//! The selection workload: 1000 face candidates on a 6×6×20 cm box at (0.70, 0.25, −0.05) m,
//! lift 0.2 m, move +0.3 m along y, place 0.2 m down, 50 samples, Baxter's left arm
//! (`examples/workload_1000_faces.yaml`), on all cores; and the same workload in a scene
//! (`examples/workload_1000_faces_scene.yaml`: a table, three obstacles, a 0.10 m approach and
//! retreat, the Baxter gripper), and the collision-free workload with `ik.redundancy: first`
//! and `optimize` (the self-motion search), all measured in the same run.
//!
//! `cargo bench -p graspath --bench select`

use criterion::{criterion_group, criterion_main, Criterion};
use graspath::select::select;
use graspath::spelling::Spelled;
use graspath::task::{Redundancy, Task, TaskFile};
use std::collections::BTreeMap;
use std::hint::black_box;
use std::path::PathBuf;

fn load(name: &str) -> Task {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    let task = Task::load(&path).expect("the workload task loads");
    let selection = select(&task, &|| {}).unwrap();
    let arm = &selection.arms[0];
    // What the workload does: how many candidates are feasible and why the others are not.
    let mut why: BTreeMap<String, usize> = BTreeMap::new();
    for failure in arm.scores.iter().filter_map(|s| s.failure.as_ref()) {
        let bodies = failure
            .bodies
            .as_ref()
            .map(|[a, b]| format!(" ({a} / {b})"))
            .unwrap_or_default();
        *why.entry(format!(
            "{} in {}{bodies}",
            failure.reason.as_str(),
            failure.phase.as_str()
        ))
        .or_default() += 1;
    }
    eprintln!(
        "{name}: {} candidates, {} feasible",
        task.candidate_count(),
        arm.feasible_count()
    );
    for (what, count) in why {
        eprintln!("  {count:5}  {what}");
    }
    task
}

fn workload(c: &mut Criterion) {
    let free = load("workload_1000_faces.yaml");
    let scene = load("workload_1000_faces_scene.yaml");
    let with_redundancy = |redundancy: Redundancy| {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples/workload_1000_faces.yaml");
        let mut file = TaskFile::load(&path).expect("the workload task loads");
        file.ik.redundancy = Some(redundancy.as_str().into());
        Task::from_file(
            &file,
            "workload_1000_faces.yaml",
            path.parent().expect("a folder"),
        )
        .expect("the workload task builds")
    };
    let (first, optimize) = (
        with_redundancy(Redundancy::First),
        with_redundancy(Redundancy::Optimize),
    );
    let mut group = c.benchmark_group("select");
    group.sample_size(10);
    group.bench_function("workload_1000_faces_left_arm", |b| {
        b.iter(|| black_box(select(black_box(&free), &|| {}).unwrap()));
    });
    group.bench_function("workload_1000_faces_scene_left_arm", |b| {
        b.iter(|| black_box(select(black_box(&scene), &|| {}).unwrap()));
    });
    group.bench_function("workload_1000_faces_redundancy_first", |b| {
        b.iter(|| black_box(select(black_box(&first), &|| {}).unwrap()));
    });
    group.bench_function("workload_1000_faces_redundancy_optimize", |b| {
        b.iter(|| black_box(select(black_box(&optimize), &|| {}).unwrap()));
    });
    group.finish();
}

criterion_group!(benches, workload);
criterion_main!(benches);
