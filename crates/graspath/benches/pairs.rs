//! Two-arm pair ranking at dataset scale: 20 000 scored candidates per arm (20 000 × 20 000 =
//! 4 × 10⁸ possible pairs), the best 10 pairs with grasps at least 8 cm apart, found by the
//! best-first search over each arm's sorted candidates.
//!
//! `cargo bench -p graspath --bench pairs`

use criterion::{criterion_group, criterion_main, Criterion};
use graspath::grasp::Candidate;
use graspath::manipulability::PathNorms;
use graspath::select::{rank_candidates, rank_pairs, CandidateScore};
use graspath::task::SelectionOptions;
use nalgebra::{Isometry3, Point3};
use std::hint::black_box;
use std::sync::Arc;

/// `n` feasible scored candidates with seeded norms and contact points along a 40 cm edge.
fn arm(n: usize, seed: u64) -> Vec<CandidateScore> {
    (0..n)
        .map(|i| {
            let r = graspath::random::derive_seed(seed, 0, i as u64);
            let norm = 3.0 + (r >> 11) as f64 / (1u64 << 53) as f64;
            let y = ((r >> 3) % 4000) as f64 * 1e-4 - 0.2;
            CandidateScore {
                norms: Some(PathNorms {
                    l2: norm,
                    rms: norm,
                    linf: 1.0,
                    l1: norm,
                    evaluated: 1,
                    skipped: 0,
                }),
                feasible_branches: 1,
                ..CandidateScore::unscored(Arc::new(Candidate {
                    id: i,
                    label: format!("c{i}"),
                    object_from_wrist: Isometry3::translation(0.0, y, 0.0),
                    log_likelihood: 0.0,
                    contact: Some(Point3::new(0.0, y, 0.0)),
                    hand_joints: Vec::new(),
                    width: None,
                }))
            }
        })
        .collect()
}

fn pairs(c: &mut Criterion) {
    let options = SelectionOptions::default();
    let (a, b) = (arm(20_000, 1), arm(20_000, 2));
    let mut group = c.benchmark_group("pairs");
    group.sample_size(10);
    group.bench_function("rank_and_top10_of_20k_x_20k", |bench| {
        bench.iter(|| {
            let (ra, rb) = (
                rank_candidates(black_box(&a), &options),
                rank_candidates(black_box(&b), &options),
            );
            black_box(rank_pairs((&a, &ra), (&b, &rb), &options, &|_, _| true))
        });
    });
    group.finish();
}

criterion_group!(benches, pairs);
criterion_main!(benches);
