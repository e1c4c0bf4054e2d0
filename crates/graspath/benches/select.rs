//! The selection workload: 1000 face candidates on a 6×6×20 cm box at (0.70, 0.25, −0.05) m,
//! lift 0.2 m, move +0.3 m along y, place 0.2 m down, 50 samples, Baxter's left arm
//! (`examples/workload_1000_faces.yaml`), on all cores.
//!
//! `cargo bench -p graspath --bench select`

use criterion::{criterion_group, criterion_main, Criterion};
use graspath::select::select;
use graspath::task::Task;
use std::hint::black_box;
use std::path::PathBuf;

fn workload(c: &mut Criterion) {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/workload_1000_faces.yaml");
    let task = Task::load(&path).expect("the workload task loads");
    let feasible = select(&task, &|| {}).arms[0].feasible_count();
    eprintln!(
        "workload: {} candidates, {feasible} feasible",
        task.candidates.len()
    );
    let mut group = c.benchmark_group("select");
    group.sample_size(10);
    group.bench_function("workload_1000_faces_left_arm", |b| {
        b.iter(|| black_box(select(black_box(&task), &|| {})));
    });
    group.finish();
}

criterion_group!(benches, workload);
criterion_main!(benches);
