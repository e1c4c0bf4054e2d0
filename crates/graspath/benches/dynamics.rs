//! The dynamics kernels per call: gravity torques `g(q)`, inverse dynamics (RNEA) and the mass
//! matrix (CRBA), beside FK + Jacobian and `g(q)` + Jacobian (fused, and the two kernels apart), on the built-in Panda and
//! Baxter left arm; RNEA and gravity also with a payload at the tool. The configurations are
//! the kinematics bench's (64 spread inside the limits); the velocities and accelerations a
//! fixed pattern. `examples/peers/pinocchio_dynamics.cpp` times Pinocchio on the same states.
//!
//! `cargo bench -p graspath --bench dynamics`

use criterion::{criterion_group, criterion_main, Criterion};
use graspath::robot::builtin::{baxter, Arm, BuiltinRobot, ARM_CHAIN};
use graspath::robot::{Chain, RigidBody};

fn panda() -> Chain {
    let spec = BuiltinRobot::Panda
        .chain_spec(ARM_CHAIN)
        .expect("Panda has an arm chain");
    Chain::from_spec(&spec).expect("a valid chain")
}
use nalgebra::{DMatrix, Matrix3, Matrix6xX, Vector3};
use std::hint::black_box;

fn configurations(chain: &Chain) -> Vec<Vec<f64>> {
    (0..64)
        .map(|k| {
            chain
                .lower()
                .iter()
                .zip(chain.upper())
                .enumerate()
                .map(|(j, (&lo, &hi))| {
                    let (lo, hi) = (lo.max(-3.0), hi.min(3.0));
                    let t = ((k * 7 + j * 13) % 64) as f64 / 63.0;
                    lo + t * (hi - lo)
                })
                .collect()
        })
        .collect()
}

/// Joint velocities (rad/s) and accelerations (rad/s²) in `[-1, 1]` and `[-2, 2]`, the same
/// pattern as the Pinocchio peer.
fn rates(n: usize, k: usize, scale: f64) -> Vec<f64> {
    (0..n)
        .map(|j| scale * (((k * 5 + j * 11) % 21) as f64 / 10.0 - 1.0))
        .collect()
}

fn bench_chain(c: &mut Criterion, name: &str, chain: &Chain) {
    let dynamics = chain.dynamics().expect("built-in arms have inertial data");
    let n = dynamics.dof();
    let qs = configurations(chain);
    let qds: Vec<Vec<f64>> = (0..64).map(|k| rates(n, k, 1.0)).collect();
    let qdds: Vec<Vec<f64>> = (0..64).map(|k| rates(n, k + 3, 2.0)).collect();
    let mut data = dynamics.data();
    let mut tau = vec![0.0; n];
    let mut mass = DMatrix::zeros(n, n);
    let mut jacobian = Matrix6xX::zeros(n);
    let mut k = 0;
    c.bench_function(&format!("fk_jacobian/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % 64;
            let pose = chain
                .pose_and_jacobian_into(black_box(&qs[k]), &mut jacobian)
                .expect("valid configuration");
            black_box((pose, &jacobian));
        });
    });
    c.bench_function(&format!("gravity/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % 64;
            dynamics
                .gravity_torques_into(&mut data, black_box(&qs[k]), &mut tau)
                .expect("valid configuration");
            black_box(&tau);
        });
    });
    c.bench_function(&format!("gravity_jacobian/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % 64;
            dynamics
                .gravity_torques_and_jacobian_into(
                    &mut data,
                    black_box(&qs[k]),
                    &mut tau,
                    &mut jacobian,
                )
                .expect("valid configuration");
            black_box((&tau, &jacobian));
        });
    });
    c.bench_function(&format!("gravity_then_jacobian/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % 64;
            dynamics
                .gravity_torques_into(&mut data, black_box(&qs[k]), &mut tau)
                .expect("valid configuration");
            let pose = chain
                .pose_and_jacobian_into(&qs[k], &mut jacobian)
                .expect("valid configuration");
            black_box((&tau, pose, &jacobian));
        });
    });
    c.bench_function(&format!("rnea/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % 64;
            dynamics
                .inverse_dynamics_into(
                    &mut data,
                    black_box(&qs[k]),
                    black_box(&qds[k]),
                    black_box(&qdds[k]),
                    &mut tau,
                )
                .expect("valid state");
            black_box(&tau);
        });
    });
    c.bench_function(&format!("crba/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % 64;
            dynamics
                .mass_matrix_into(&mut data, black_box(&qs[k]), &mut mass)
                .expect("valid configuration");
            black_box(&mass);
        });
    });
    let payload = RigidBody::new(
        2.0,
        Vector3::new(0.0, 0.02, 0.1),
        Matrix3::from_diagonal(&Vector3::new(0.01, 0.012, 0.004)),
    );
    data.set_payload(Some(payload)).expect("a valid payload");
    c.bench_function(&format!("gravity_payload/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % 64;
            dynamics
                .gravity_torques_into(&mut data, black_box(&qs[k]), &mut tau)
                .expect("valid configuration");
            black_box(&tau);
        });
    });
    c.bench_function(&format!("rnea_payload/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % 64;
            dynamics
                .inverse_dynamics_into(
                    &mut data,
                    black_box(&qs[k]),
                    black_box(&qds[k]),
                    black_box(&qdds[k]),
                    &mut tau,
                )
                .expect("valid state");
            black_box(&tau);
        });
    });
}

fn dynamics(c: &mut Criterion) {
    bench_chain(c, "panda", &panda());
    bench_chain(c, "baxter_left", &baxter(Arm::Left));
}

criterion_group!(benches, dynamics);
criterion_main!(benches);
