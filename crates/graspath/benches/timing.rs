//! Time-optimal timing of one 50-sample Panda path (TOPP-RA on the natural cubic spline, the
//! grid = the knots and their midpoints, collocation as toppra's default): velocity and
//! acceleration limits, and with the torque limits (inverse dynamics of the built-in Panda,
//! whose parameters are example-robot-data's). The spline is built once, outside the timing,
//! as in the peer. `examples/peers/toppra_bench.py OUT.json` times toppra on the same problem
//! and writes it; with `GRASPATH_TOPPRA_PROBLEM=OUT.json` this bench times exactly that path
//! and those limits (otherwise a built-in 50-sample path).
//!
//! `cargo bench -p graspath --bench timing`

use criterion::{criterion_group, criterion_main, Criterion};
use graspath::robot::builtin::{BuiltinRobot, ARM_CHAIN};
use graspath::robot::Chain;
use graspath::timing::{time_optimal, Discretization, JointSpline, PathLimits, TorqueLimits};
use std::hint::black_box;

/// The path (50 × 7) and the acceleration limits: from the peer's problem file, or built in.
fn problem() -> (Vec<Vec<f64>>, Vec<f64>) {
    if let Some(path) = std::env::var_os("GRASPATH_TOPPRA_PROBLEM") {
        let text = std::fs::read_to_string(&path).expect("the problem file");
        let json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        let numbers = |v: &serde_json::Value| -> Vec<f64> {
            v.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        };
        let problem = &json["problem"];
        let waypoints = problem["waypoints"]
            .as_array()
            .unwrap()
            .iter()
            .map(numbers)
            .collect();
        return (waypoints, numbers(&problem["acceleration_limits"]));
    }
    let waypoints = (0..50)
        .map(|k| {
            let t = k as f64 / 49.0;
            (0..7)
                .map(|j| {
                    let j = j as f64;
                    0.3 * (j + 1.0) * (t - 0.5) + 0.2 * (std::f64::consts::PI * t * (j + 1.0)).sin()
                })
                .collect()
        })
        .collect();
    (waypoints, vec![30.0; 7])
}

fn timing(c: &mut Criterion) {
    let spec = BuiltinRobot::Panda
        .chain_spec(ARM_CHAIN)
        .expect("Panda has an arm chain");
    let chain = Chain::from_spec(&spec).expect("a valid chain");
    let dynamics = chain.dynamics().expect("Panda has inertias");
    let (waypoints, acceleration) = problem();
    let spline = JointSpline::through(&waypoints).expect("a path");
    let velocity: Vec<Option<f64>> = chain.motion_limits().iter().map(|l| l.velocity).collect();
    let effort: Vec<Option<f64>> = chain.motion_limits().iter().map(|l| l.effort).collect();
    let acceleration: Vec<Option<f64>> = acceleration.into_iter().map(Some).collect();
    let limits = |torque: bool| PathLimits {
        velocity: &velocity,
        acceleration: &acceleration,
        torque: torque.then_some(TorqueLimits {
            dynamics: &dynamics,
            effort: &effort,
            payload: None,
        }),
        object: None,
        subdivisions: 2,
        discretization: Discretization::Collocation,
    };
    let mut group = c.benchmark_group("timing");
    for (name, torque) in [("vel_acc", false), ("vel_acc_torque", true)] {
        let limits = limits(torque);
        group.bench_function(format!("topp_ra_50_samples_{name}"), |b| {
            b.iter(|| {
                let constraints = limits.constraints(black_box(&spline)).unwrap();
                black_box(time_optimal(&constraints).unwrap().duration());
            });
        });
    }
    let checked = limits(true);
    group.bench_function("time_50_samples_vel_acc_torque_checked", |b| {
        b.iter(|| black_box(checked.time(black_box(&spline)).unwrap().duration()));
    });
    group.finish();
}

criterion_group!(benches, timing);
criterion_main!(benches);
