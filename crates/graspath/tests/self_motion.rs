//! The self-motion optimiser against a brute-force oracle: a planar 3R arm whose tip follows a
//! line (one redundant degree of freedom), every configuration of its self-motion enumerated
//! in closed form on a fine grid, and the best chain under the joint-step bound found by
//! exhaustive dynamic programming over that grid.

use graspath::robot::{optimize_self_motion, parse_urdf_chain, KeptRows, SelfMotionOptions};
use nalgebra::{Isometry3, Matrix6xX};

const L: [f64; 3] = [0.7, 0.5, 0.2];
const LIMIT: f64 = 3.1;

fn planar_3r() -> String {
    format!(
        r#"<robot name="planar3r">
      <link name="base"/><link name="a"/><link name="b"/><link name="c"/><link name="tip"/>
      <joint name="q1" type="revolute"><parent link="base"/><child link="a"/>
        <axis xyz="0 0 1"/><limit lower="-{LIMIT}" upper="{LIMIT}" effort="1" velocity="1"/></joint>
      <joint name="q2" type="revolute"><parent link="a"/><child link="b"/><origin xyz="{} 0 0"/>
        <axis xyz="0 0 1"/><limit lower="-{LIMIT}" upper="{LIMIT}" effort="1" velocity="1"/></joint>
      <joint name="q3" type="revolute"><parent link="b"/><child link="c"/><origin xyz="{} 0 0"/>
        <axis xyz="0 0 1"/><limit lower="-{LIMIT}" upper="{LIMIT}" effort="1" velocity="1"/></joint>
      <joint name="end" type="fixed"><parent link="c"/><child link="tip"/><origin xyz="{} 0 0"/></joint>
    </robot>"#,
        L[0], L[1], L[2]
    )
}

/// Both closed-form configurations with the tip at (x, y) and the last link at angle `phi`.
fn closed_form(x: f64, y: f64, phi: f64) -> Vec<[f64; 3]> {
    let (wx, wy) = (x - L[2] * phi.cos(), y - L[2] * phi.sin());
    let c2 = (wx * wx + wy * wy - L[0] * L[0] - L[1] * L[1]) / (2.0 * L[0] * L[1]);
    if c2.abs() > 1.0 {
        return Vec::new();
    }
    [1.0, -1.0]
        .into_iter()
        .map(|sign: f64| {
            let q2 = sign * c2.acos();
            let q1 = wy.atan2(wx) - (L[1] * q2.sin()).atan2(L[0] + L[1] * q2.cos());
            let q3 = phi - q1 - q2;
            // Wrap q3 into (−π, π].
            let q3 = (q3 + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI)
                - std::f64::consts::PI;
            [q1, q2, q3]
        })
        .filter(|q| q.iter().all(|v| v.abs() <= LIMIT))
        .collect()
}

/// `M_T` along +x (position rows), in closed form: the squared x-row of the planar Jacobian.
fn index(q: &[f64]) -> f64 {
    let s1 = q[0].sin();
    let s12 = (q[0] + q[1]).sin();
    let s123 = (q[0] + q[1] + q[2]).sin();
    [
        L[0] * s1 + L[1] * s12 + L[2] * s123,
        L[1] * s12 + L[2] * s123,
        L[2] * s123,
    ]
    .iter()
    .map(|v| v * v)
    .sum()
}

#[test]
fn the_optimum_along_a_line_equals_brute_force_over_the_self_motion() {
    // Finely traced: the programme's states alone are close to the optimum.
    optimum_along_a_line_equals_brute_force(0.05, 80);
}

#[test]
fn coarse_tracing_is_refined_to_the_brute_force_optimum() {
    // Traced at 0.25 rad: the optimum lies between states, and the refinement must find it.
    optimum_along_a_line_equals_brute_force(0.25, 16);
}

fn optimum_along_a_line_equals_brute_force(spacing: f64, reach: usize) {
    let chain = parse_urdf_chain(&planar_3r(), "planar3r.urdf", "base", "tip").unwrap();
    let samples = 6;
    let (y, x0, x1) = (0.35, 0.55, 0.85);
    let xs: Vec<f64> = (0..samples)
        .map(|i| x0 + (x1 - x0) * i as f64 / (samples - 1) as f64)
        .collect();
    let targets: Vec<Isometry3<f64>> = xs
        .iter()
        .map(|&x| Isometry3::translation(x, y, 0.0))
        .collect();
    let step = 0.25;
    // The seed: the last link level (phi = 0), elbow up, at every sample.
    let seed: Vec<Vec<f64>> = xs
        .iter()
        .map(|&x| closed_form(x, y, 0.0)[0].to_vec())
        .collect();
    let value = |_: usize, _: &[f64], j: &Matrix6xX<f64>| -> f64 {
        (0..j.ncols()).map(|c| j[(0, c)] * j[(0, c)]).sum()
    };
    let options = SelfMotionOptions {
        spacing,
        reach,
        max_joint_step: step,
        ..SelfMotionOptions::default()
    };
    let found = optimize_self_motion(
        &chain,
        &targets,
        &[&seed],
        KeptRows::Position,
        &value,
        &options,
    )
    .expect("a path");
    // Re-checked: on target by forward kinematics, inside the limits, within the step bound,
    // and its values are the closed-form index.
    for (i, q) in found.q.iter().enumerate() {
        let tip = chain.pose(q).unwrap().translation.vector;
        assert!(
            (tip.x - xs[i]).abs() < 1e-5 && (tip.y - y).abs() < 1e-5,
            "{tip}"
        );
        assert!(q.iter().all(|v| v.abs() <= LIMIT));
        assert!((found.values[i] - index(q)).abs() < 1e-9);
        if i > 0 {
            let moved = q
                .iter()
                .zip(&found.q[i - 1])
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(moved <= step + 1e-12, "sample {i}: step {moved}");
        }
    }
    let seed_total: f64 = seed.iter().map(|q| index(q)).sum();
    assert!(found.total >= seed_total, "{} < {seed_total}", found.total);
    // Oracle: the self-motion on a grid of the last link's angle (0.002 rad), both elbows,
    // and the best chain under the step bound by exhaustive dynamic programming.
    let grid = 3200;
    let states: Vec<Vec<[f64; 3]>> = xs
        .iter()
        .map(|&x| {
            (0..grid)
                .flat_map(|k| {
                    let phi =
                        -std::f64::consts::PI + 2.0 * std::f64::consts::PI * k as f64 / grid as f64;
                    closed_form(x, y, phi)
                })
                .collect()
        })
        .collect();
    let mut best: Vec<f64> = states[0].iter().map(|q| index(q)).collect();
    for i in 1..samples {
        best = states[i]
            .iter()
            .map(|q| {
                let before = states[i - 1]
                    .iter()
                    .zip(&best)
                    .filter(|(p, _)| (0..3).all(|j| (p[j] - q[j]).abs() <= step))
                    .map(|(_, b)| *b)
                    .fold(f64::NEG_INFINITY, f64::max);
                before + index(q)
            })
            .collect();
    }
    let oracle = best.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    // The seed is far from the optimum: the test asks for a real improvement.
    assert!(
        oracle > 1.05 * seed_total,
        "oracle {oracle}, seed {seed_total}"
    );
    // 1e-5: ten times finer than the issue's 1e-3, so that the refinement between traced
    // states is what is tested (the best traced state alone is 1e-4 to 1e-3 off).
    assert!(
        (found.total - oracle).abs() <= 1e-5 * oracle,
        "optimiser {} vs brute force {oracle} (seed {seed_total})",
        found.total
    );
    assert!(found.worst_total <= seed_total);
}

#[test]
fn the_null_space_moves_no_kept_row_of_the_tip() {
    use graspath::robot::builtin::{baxter, Arm};
    use graspath::robot::null_space;
    // Baxter's 7-joint arm keeping the pose: one self-motion direction.
    let chain = baxter(Arm::Left);
    let planar = parse_urdf_chain(&planar_3r(), "planar3r.urdf", "base", "tip").unwrap();
    for (chain, rows, expected) in [
        (&chain, KeptRows::Pose, 1),
        (&planar, KeptRows::Position, 1),
    ] {
        let (lower, upper) = (chain.lower(), chain.upper());
        for k in 0..5 {
            let q: Vec<f64> = (0..chain.dof())
                .map(|j| {
                    let t = (0.5 + 0.4 * ((k * 7 + j) as f64 * 1.3).sin()).clamp(0.05, 0.95);
                    lower[j] + t * (upper[j] - lower[j])
                })
                .collect();
            let mut jacobian = Matrix6xX::zeros(chain.dof());
            let pose = chain.pose_and_jacobian_into(&q, &mut jacobian).unwrap();
            let basis = null_space(&jacobian, rows, 1e-9);
            assert_eq!(basis.ncols(), expected);
            // Orthonormal, and a small motion along it moves the kept rows only to second
            // order (finite differences on forward kinematics, not the Jacobian).
            assert!(((basis.transpose() * &basis)[(0, 0)] - 1.0).abs() < 1e-12);
            let eps = 1e-5;
            let moved: Vec<f64> = q
                .iter()
                .zip(basis.column(0).iter())
                .map(|(v, d)| v + eps * d)
                .collect();
            let after = chain.pose(&moved).unwrap();
            let shift = (after.translation.vector - pose.translation.vector).norm();
            assert!(shift < 1e-8, "the tip moved {shift} m along the null space");
            if rows == KeptRows::Pose {
                // From the skew part of the relative rotation, exact for small angles (acos of
                // the trace loses them to rounding).
                let relative = (after.rotation.inverse() * pose.rotation).into_inner();
                let turn = (relative - relative.transpose()).norm() / 2.0_f64.sqrt();
                assert!(
                    turn < 1e-8,
                    "the tip turned {turn} rad along the null space"
                );
            }
            // A joint velocity that is not in it does move the tip.
            let other: Vec<f64> = q
                .iter()
                .enumerate()
                .map(|(j, v)| v + eps * f64::from(j == 0))
                .collect();
            let off =
                (chain.pose(&other).unwrap().translation.vector - pose.translation.vector).norm();
            assert!(off > 1e-7 || basis[(0, 0)].abs() > 0.99);
        }
    }
}
