//! IK speed on Baxter's left arm (built-in model): single poses from the mid-limits start
//! configuration (TRAC-IK's protocol), 50-sample trajectories (per-sample cost = time / 50),
//! and a batch of 16 trajectories solved together against one by one.

use criterion::{criterion_group, criterion_main, Criterion};
use graspath::robot::builtin::{baxter, Arm};
use graspath::robot::{
    solve_ik, solve_trajectories, solve_trajectory, Chain, IkOptions, TrajectoryIkOptions,
};
use nalgebra::Isometry3;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use std::hint::black_box;

fn random_targets(chain: &Chain, count: usize) -> Vec<Isometry3<f64>> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    (0..count)
        .map(|_| {
            let q: Vec<f64> = chain
                .lower()
                .iter()
                .zip(chain.upper())
                .map(|(&lo, &hi)| rng.random_range(lo..=hi))
                .collect();
            nalgebra::convert(chain.pose(&q).expect("fk"))
        })
        .collect()
}

/// A 50-sample wrist trajectory: a smooth joint-space sweep inside the limits.
fn trajectory(chain: &Chain) -> Vec<Isometry3<f64>> {
    shifted_trajectory(chain, 0.0)
}

/// [`trajectory`] with the first joint's sweep shifted by `shift` (rad).
fn shifted_trajectory(chain: &Chain, shift: f64) -> Vec<Isometry3<f64>> {
    (0..50)
        .map(|i| {
            let t = i as f64 / 49.0;
            let q = [
                0.2 + shift + 0.4 * t,
                -0.5 + 0.3 * t,
                0.1 - 0.6 * t,
                1.2 - 0.4 * t,
                0.3 * (3.0 * t).sin(),
                0.8 - 0.5 * t,
                -0.4 + 1.2 * t,
            ];
            nalgebra::convert(chain.pose(&q).expect("fk"))
        })
        .collect()
}

fn bench_ik(c: &mut Criterion) {
    let chain = baxter(Arm::Left);
    let mid = chain.mid_configuration();

    let targets = random_targets(&chain, 1024);
    let options = IkOptions::default();
    let mut next = 0usize;
    c.bench_function("ik/baxter_single_pose_from_mid", |b| {
        b.iter(|| {
            next = (next + 1) % targets.len();
            black_box(solve_ik(&chain, &targets[next], &mid, &options).expect("valid"))
        });
    });

    let poses = trajectory(&chain);
    for branches in [1usize, 4] {
        let options = TrajectoryIkOptions {
            branches,
            ..TrajectoryIkOptions::default()
        };
        c.bench_function(
            &format!("ik/baxter_trajectory_50_samples_{branches}_branch"),
            |b| {
                b.iter(|| {
                    black_box(solve_trajectory(&chain, &poses, &mid, &options).expect("valid"))
                });
            },
        );
    }
    // Warm-started tracking alone: started at the first sample's solution, one branch.
    let start: Vec<f64> = vec![0.2, -0.5, 0.1, 1.2, 0.0, 0.8, -0.4];
    let options = TrajectoryIkOptions {
        branches: 1,
        ..TrajectoryIkOptions::default()
    };
    c.bench_function("ik/baxter_trajectory_50_samples_seeded_at_start", |b| {
        b.iter(|| black_box(solve_trajectory(&chain, &poses, &start, &options).expect("valid")));
    });
}

/// 16 trajectories (the sweep, its first joint shifted by up to 0.3 rad), one branch each, as
/// a selection's first solve: together ([`solve_trajectories`], tracked in vector lanes) and
/// one by one.
fn bench_batch(c: &mut Criterion) {
    let chain = baxter(Arm::Left);
    let mid = chain.mid_configuration();
    let trajectories: Vec<Vec<Isometry3<f64>>> = (0..16)
        .map(|k| shifted_trajectory(&chain, 0.02 * k as f64))
        .collect();
    let batch: Vec<&[Isometry3<f64>]> = trajectories.iter().map(Vec::as_slice).collect();
    let options = TrajectoryIkOptions {
        branches: 1,
        ..TrajectoryIkOptions::default()
    };
    let mut group = c.benchmark_group("ik/baxter_16_trajectories_50_samples");
    group.bench_function("together", |b| {
        b.iter(|| black_box(solve_trajectories(&chain, &batch, &mid, &options).expect("valid")));
    });
    group.bench_function("one_by_one", |b| {
        b.iter(|| {
            batch
                .iter()
                .map(|poses| solve_trajectory(&chain, poses, &mid, &options).expect("valid"))
                .collect::<Vec<_>>()
        });
    });
    group.finish();
}

criterion_group!(benches, bench_ik, bench_batch);
criterion_main!(benches);
