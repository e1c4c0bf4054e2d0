//! The kernels against closed forms (a planar 2R arm of point masses), finite differences of
//! `M(q)` and of a potential energy computed from link frames, and mimic joints against the
//! same chain with the follower made independent. The comparison with Pinocchio is in
//! `tests/dynamics.rs`.

use crate::robot::spec::{ChainSpec, JointKind, JointSpec, Mimic, MotionLimits, RigidBody};
use crate::robot::{Chain, RobotError};
use nalgebra::{DMatrix, DVector, Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

const G: f64 = 9.81;

fn joint(name: &str, kind: JointKind, origin: Isometry3<f64>, axis: Vector3<f64>) -> JointSpec {
    JointSpec {
        name: name.into(),
        child_link: format!("{name}_link"),
        kind,
        parent_from_joint: origin,
        axis,
        lower: -3.0,
        upper: 3.0,
        mimic: None,
        limits: MotionLimits::default(),
        child_inertial: None,
    }
}

fn spec(joints: Vec<JointSpec>, tip_from_tool: Option<Isometry3<f64>>) -> ChainSpec {
    ChainSpec {
        source_name: "test".into(),
        base_link: "base".into(),
        tip_link: "tip".into(),
        joints,
        tip_from_tool,
    }
}

/// A planar 2R arm in the base's x–z plane: both joints turn about `y`, link lengths `l1`,
/// `l2`, point masses `m1`, `m2` at the link ends.
fn planar_2r(l1: f64, l2: f64, m1: f64, m2: f64) -> ChainSpec {
    let mut a = joint(
        "j1",
        JointKind::Revolute,
        Isometry3::identity(),
        Vector3::y(),
    );
    a.child_inertial = Some(RigidBody::point(m1, Vector3::new(l1, 0.0, 0.0)));
    let mut b = joint(
        "j2",
        JointKind::Revolute,
        Isometry3::translation(l1, 0.0, 0.0),
        Vector3::y(),
    );
    b.child_inertial = Some(RigidBody::point(m2, Vector3::new(l2, 0.0, 0.0)));
    spec(vec![a, b], None)
}

fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!(
        (a - b).abs() <= tol * b.abs().max(1.0),
        "{what}: {a} vs {b} (difference {:e})",
        (a - b).abs()
    );
}

/// Rotation about `y` by `q` takes `x` to `(cos q, 0, −sin q)`: the heights of the masses are
/// `−l1 sin q1` and `−l1 sin q1 − l2 sin(q1 + q2)`.
#[test]
fn planar_2r_gravity_and_mass_matrix_equal_the_closed_forms() {
    let (l1, l2, m1, m2) = (0.7, 0.45, 2.3, 1.1);
    let dynamics = Chain::from_spec(&planar_2r(l1, l2, m1, m2))
        .unwrap()
        .dynamics()
        .unwrap();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    for _ in 0..50 {
        let q = [rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0)];
        let g = dynamics.gravity_torques(&q).unwrap();
        let (c1, c12) = (q[0].cos(), (q[0] + q[1]).cos());
        close(
            g[0],
            -m1 * G * l1 * c1 - m2 * G * (l1 * c1 + l2 * c12),
            1e-12,
            "g1",
        );
        close(g[1], -m2 * G * l2 * c12, 1e-12, "g2");
        let m = dynamics.mass_matrix(&q).unwrap();
        let c2 = q[1].cos();
        close(
            m[(0, 0)],
            m1 * l1 * l1 + m2 * (l1 * l1 + l2 * l2 + 2.0 * l1 * l2 * c2),
            1e-12,
            "M11",
        );
        close(m[(0, 1)], m2 * (l2 * l2 + l1 * l2 * c2), 1e-12, "M12");
        close(m[(1, 0)], m[(0, 1)], 0.0, "M21");
        close(m[(1, 1)], m2 * l2 * l2, 1e-12, "M22");
        // The Coriolis and centrifugal torques of the 2R arm (no gravity).
        let qd = [rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0)];
        let tau = dynamics.inverse_dynamics(&q, &qd, &[0.0, 0.0]).unwrap();
        let h = m2 * l1 * l2 * q[1].sin();
        close(
            tau[0] - g[0],
            -h * (2.0 * qd[0] * qd[1] + qd[1] * qd[1]),
            1e-11,
            "C1",
        );
        close(tau[1] - g[1], h * qd[0] * qd[0], 1e-11, "C2");
    }
}

/// A payload at the tool adds exactly what the same point mass on the last link adds, and a
/// chain without inertial data is refused by name.
#[test]
fn payload_at_the_tool_equals_the_same_mass_on_the_last_link() {
    let (l1, l2, m1, m2, mp) = (0.6, 0.4, 1.5, 0.8, 0.9);
    // Tool turned and shifted: the payload's centre is 0.1 m along the tool's z, which the
    // turn maps onto the link's x.
    let tip_from_tool = Isometry3::from_parts(
        Translation3::new(l2 - 0.1, 0.0, 0.0),
        UnitQuaternion::from_euler_angles(0.0, std::f64::consts::FRAC_PI_2, 0.0),
    );
    let mut with_tool = planar_2r(l1, l2, m1, m2);
    with_tool.tip_from_tool = Some(tip_from_tool);
    let dynamics = Chain::from_spec(&with_tool).unwrap().dynamics().unwrap();
    let heavier = Chain::from_spec(&planar_2r(l1, l2, m1, m2 + mp))
        .unwrap()
        .dynamics()
        .unwrap();
    let mut data = dynamics.data();
    let payload = RigidBody::point(mp, Vector3::new(0.0, 0.0, 0.1));
    assert!(
        (tip_from_tool * nalgebra::Point3::from(payload.com) - nalgebra::Point3::new(l2, 0.0, 0.0))
            .norm()
            < 1e-12
    );
    data.set_payload(Some(payload)).unwrap();
    let mut tau = [0.0; 2];
    let q = [0.4, -1.1];
    dynamics
        .gravity_torques_into(&mut data, &q, &mut tau)
        .unwrap();
    let expected = heavier.gravity_torques(&q).unwrap();
    for j in 0..2 {
        close(tau[j], expected[j], 1e-12, "payload gravity");
    }
    let mut m = DMatrix::zeros(0, 0);
    dynamics.mass_matrix_into(&mut data, &q, &mut m).unwrap();
    assert!((m - heavier.mass_matrix(&q).unwrap()).amax() < 1e-12);
    let bad = RigidBody::point(-1.0, Vector3::zeros());
    assert!(matches!(
        data.set_payload(Some(bad)),
        Err(RobotError::BadInertia { .. })
    ));

    let mut bare = planar_2r(l1, l2, m1, m2);
    bare.joints[1].child_inertial = None;
    let err = Chain::from_spec(&bare).unwrap().dynamics().unwrap_err();
    assert!(matches!(&err, RobotError::NoInertia { joint, .. } if joint == "j2"));
    assert!(err.to_string().contains("j2_link"), "{err}");
}

/// A random chain with bodies on every segment: revolute, continuous, prismatic and fixed
/// joints with random axes, placements and inertias.
/// A rotation drawn over all orientations (roll and yaw in ±3 rad, pitch in ±1.5 rad).
fn random_turn(rng: &mut Xoshiro256PlusPlus) -> UnitQuaternion<f64> {
    UnitQuaternion::from_euler_angles(
        rng.random_range(-3.0..3.0),
        rng.random_range(-1.5..1.5),
        rng.random_range(-3.0..3.0),
    )
}

fn random_chain(rng: &mut Xoshiro256PlusPlus, joints: usize, mimic: bool) -> ChainSpec {
    let mut specs = Vec::new();
    let mut moving = Vec::new();
    for i in 0..joints {
        let kind = match rng.random_range(0..6) {
            0 => JointKind::Prismatic,
            1 if i > 0 => JointKind::Fixed,
            2 => JointKind::Continuous,
            _ => JointKind::Revolute,
        };
        let axis = Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let origin = Isometry3::from_parts(
            Translation3::new(
                rng.random_range(-0.4..0.4),
                rng.random_range(-0.4..0.4),
                rng.random_range(-0.4..0.4),
            ),
            random_turn(rng),
        );
        let mut j = joint(&format!("j{i}"), kind, origin, axis.normalize());
        let principal = Matrix3::from_diagonal(&Vector3::new(
            rng.random_range(0.001..0.05),
            rng.random_range(0.001..0.05),
            rng.random_range(0.001..0.05),
        ));
        let turn = random_turn(rng).to_rotation_matrix().into_inner();
        j.child_inertial = Some(RigidBody::new(
            rng.random_range(0.2..3.0),
            Vector3::new(
                rng.random_range(-0.2..0.2),
                rng.random_range(-0.2..0.2),
                rng.random_range(-0.2..0.2),
            ),
            turn * principal * turn.transpose(),
        ));
        if mimic && kind != JointKind::Fixed && !moving.is_empty() && rng.random_range(0..3) == 0 {
            let leader: &String = &moving[rng.random_range(0..moving.len())];
            j.mimic = Some(Mimic {
                leader: leader.clone(),
                multiplier: rng.random_range(-1.5..1.5),
                offset: rng.random_range(-0.3..0.3),
            });
        } else if kind != JointKind::Fixed {
            moving.push(j.name.clone());
        }
        specs.push(j);
    }
    spec(specs, Some(Isometry3::translation(0.05, -0.02, 0.12)))
}

fn random_vector(rng: &mut Xoshiro256PlusPlus, n: usize, range: f64) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-range..range)).collect()
}

/// `M q̈ = τ(q, 0, q̈) − τ(q, 0, 0)`, `g = τ(q, 0, 0)`, and the velocity terms equal
/// `Ṁ q̇ − ½ ∂(q̇ᵀ M q̇)/∂q` with both derivatives of `M` by central differences.
#[test]
fn inverse_dynamics_agrees_with_the_mass_matrix_and_its_derivatives() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    for trial in 0..40 {
        let chain = Chain::from_spec(&random_chain(&mut rng, 2 + trial % 8, false)).unwrap();
        let dynamics = chain.dynamics().unwrap();
        let n = dynamics.dof();
        let q = random_vector(&mut rng, n, 2.0);
        let qd = random_vector(&mut rng, n, 1.5);
        let qdd = random_vector(&mut rng, n, 3.0);
        let zero = vec![0.0; n];
        let g = dynamics.gravity_torques(&q).unwrap();
        let bias = dynamics.inverse_dynamics(&q, &zero, &zero).unwrap();
        let tau_a = dynamics.inverse_dynamics(&q, &zero, &qdd).unwrap();
        let m = dynamics.mass_matrix(&q).unwrap();
        let mq = &m * DVector::from_column_slice(&qdd);
        for j in 0..n {
            close(g[j], bias[j], 1e-12, "g vs rnea(q, 0, 0)");
            close(tau_a[j] - bias[j], mq[j], 1e-11, "M q̈");
        }
        assert!((&m - m.transpose()).amax() == 0.0, "M is symmetric");
        // Velocity terms by finite differences of M.
        let step = 1e-6;
        let at = |x: &[f64]| dynamics.mass_matrix(x).unwrap();
        let along =
            |d: &[f64], h: f64| -> Vec<f64> { q.iter().zip(d).map(|(a, b)| a + h * b).collect() };
        let m_dot = (at(&along(&qd, step)) - at(&along(&qd, -step))) / (2.0 * step);
        let qd_v = DVector::from_column_slice(&qd);
        let tau_v = dynamics.inverse_dynamics(&q, &qd, &zero).unwrap();
        for j in 0..n {
            let mut e = vec![0.0; n];
            e[j] = 1.0;
            let dm = (at(&along(&e, step)) - at(&along(&e, -step))) / (2.0 * step);
            let expected = (&m_dot * &qd_v)[j] - 0.5 * qd_v.dot(&(&dm * &qd_v));
            close(tau_v[j] - g[j], expected, 1e-6, "velocity terms");
        }
    }
}

/// `g(q)` is the gradient of the potential energy `−Σ mᵢ g·cᵢ`, with every centre of mass
/// placed by the FK kernel's link frames (not by the dynamics pass).
#[test]
fn gravity_is_the_gradient_of_the_potential_energy() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(17);
    for trial in 0..30 {
        let spec = random_chain(&mut rng, 2 + trial % 7, trial % 2 == 1);
        let chain = Chain::from_spec(&spec).unwrap();
        let gravity = Vector3::new(0.3, -2.0, -9.5);
        let dynamics = chain.dynamics().unwrap().with_gravity(gravity).unwrap();
        // The links' bodies in their link frames, in chain order (the base carries none).
        let bodies: Vec<Option<RigidBody>> = std::iter::once(None)
            .chain(spec.joints.iter().map(|j| j.child_inertial))
            .collect();
        let potential = |q: &[f64]| -> f64 {
            let frames = chain.link_frames(q).unwrap();
            frames
                .iter()
                .zip(&bodies)
                .filter_map(|(frame, body)| body.map(|b| (frame, b)))
                .map(|(frame, b)| {
                    -b.mass * gravity.dot(&(frame * nalgebra::Point3::from(b.com)).coords)
                })
                .sum()
        };
        // Links before the first moving joint do not move: their energy is constant.
        let n = dynamics.dof();
        let q = random_vector(&mut rng, n, 2.0);
        let g = dynamics.gravity_torques(&q).unwrap();
        let step = 1e-6;
        for j in 0..n {
            let mut plus = q.clone();
            let mut minus = q.clone();
            plus[j] += step;
            minus[j] -= step;
            let derivative = (potential(&plus) - potential(&minus)) / (2.0 * step);
            close(g[j], derivative, 1e-6, "dV/dq");
        }
    }
}

/// A mimic follower's torque reaches its leader times the multiplier: the chain with mimic
/// joints equals the chain with the followers made independent, mapped by `J` (`q_f = m q_l
/// + offset`): `τ = Jᵀ τ_full`, `M = Jᵀ M_full J`.
#[test]
fn mimic_joints_equal_the_independent_chain_mapped() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(23);
    let mut seen_mimic = 0;
    for trial in 0..40 {
        let spec = random_chain(&mut rng, 3 + trial % 7, true);
        let mut free = spec.clone();
        for j in &mut free.joints {
            j.mimic = None;
        }
        let chain = Chain::from_spec(&spec).unwrap();
        let full_chain = Chain::from_spec(&free).unwrap();
        let dynamics = chain.dynamics().unwrap();
        let full = full_chain.dynamics().unwrap();
        let (n, nf) = (dynamics.dof(), full.dof());
        if n == nf {
            continue;
        }
        seen_mimic += 1;
        // J (nf × n) and the offsets, in the full chain's joint order.
        let mut jac = DMatrix::<f64>::zeros(nf, n);
        let mut offset = vec![0.0; nf];
        for (k, name) in full_chain.joint_names().iter().enumerate() {
            let joint = spec.joints.iter().find(|j| &j.name == name).unwrap();
            match &joint.mimic {
                None => {
                    let i = chain.joint_names().iter().position(|x| x == name).unwrap();
                    jac[(k, i)] = 1.0;
                }
                Some(m) => {
                    let i = chain
                        .joint_names()
                        .iter()
                        .position(|x| *x == m.leader)
                        .unwrap();
                    jac[(k, i)] = m.multiplier;
                    offset[k] = m.offset;
                }
            }
        }
        let q = DVector::from_vec(random_vector(&mut rng, n, 2.0));
        let qd = DVector::from_vec(random_vector(&mut rng, n, 1.5));
        let qdd = DVector::from_vec(random_vector(&mut rng, n, 3.0));
        let q_full = &jac * &q + DVector::from_vec(offset);
        let tau = dynamics
            .inverse_dynamics(q.as_slice(), qd.as_slice(), qdd.as_slice())
            .unwrap();
        let tau_full = full
            .inverse_dynamics(
                q_full.as_slice(),
                (&jac * &qd).as_slice(),
                (&jac * &qdd).as_slice(),
            )
            .unwrap();
        let mapped = jac.transpose() * DVector::from_vec(tau_full);
        for j in 0..n {
            close(tau[j], mapped[j], 1e-11, "mimic τ");
        }
        let m = dynamics.mass_matrix(q.as_slice()).unwrap();
        let m_full = full.mass_matrix(q_full.as_slice()).unwrap();
        let expected = jac.transpose() * m_full * &jac;
        assert!((m - &expected).amax() <= 1e-11 * expected.amax().max(1.0));
        let g = dynamics.gravity_torques(q.as_slice()).unwrap();
        let g_full =
            jac.transpose() * DVector::from_vec(full.gravity_torques(q_full.as_slice()).unwrap());
        for j in 0..n {
            close(g[j], g_full[j], 1e-11, "mimic g");
        }
    }
    assert!(
        seen_mimic >= 10,
        "only {seen_mimic} chains had mimic joints"
    );
}

/// Wrong lengths, non-finite inputs and a workspace of another model are errors, never panics.
#[test]
fn bad_inputs_are_errors() {
    let dynamics = Chain::from_spec(&planar_2r(0.5, 0.5, 1.0, 1.0))
        .unwrap()
        .dynamics()
        .unwrap();
    let mut data = dynamics.data();
    let mut tau = [0.0; 2];
    assert!(matches!(
        dynamics.gravity_torques_into(&mut data, &[0.0], &mut tau),
        Err(RobotError::WrongDof { .. })
    ));
    assert!(matches!(
        dynamics.gravity_torques_into(&mut data, &[0.0, f64::NAN], &mut tau),
        Err(RobotError::NonFiniteJoint { index: 1 })
    ));
    assert!(matches!(
        dynamics.inverse_dynamics_into(&mut data, &[0.0; 2], &[0.0; 3], &[0.0; 2], &mut tau),
        Err(RobotError::BadDynamicsInput { what: "qd", .. })
    ));
    assert!(matches!(
        dynamics.inverse_dynamics_into(
            &mut data,
            &[0.0; 2],
            &[0.0; 2],
            &[f64::INFINITY, 0.0],
            &mut tau
        ),
        Err(RobotError::BadDynamicsInput { what: "qdd", .. })
    ));
    assert!(matches!(
        dynamics.gravity_torques_into(&mut data, &[0.0; 2], &mut [0.0; 3]),
        Err(RobotError::BadDynamicsInput { what: "tau", .. })
    ));
    let other = Chain::from_spec(&random_chain(
        &mut Xoshiro256PlusPlus::seed_from_u64(1),
        5,
        false,
    ))
    .unwrap()
    .dynamics()
    .unwrap();
    let mut foreign = other.data();
    if other.dof() != 2 {
        assert!(matches!(
            dynamics.gravity_torques_into(&mut foreign, &[0.0; 2], &mut tau),
            Err(RobotError::BadDynamicsInput { what: "data", .. })
        ));
    }
    assert!(dynamics
        .clone()
        .with_gravity(Vector3::new(0.0, f64::NAN, 0.0))
        .is_err());
    // A negative mass in the model is refused when the model is built.
    let mut negative = planar_2r(0.5, 0.5, 1.0, 1.0);
    negative.joints[0].child_inertial = Some(RigidBody::point(-2.0, Vector3::zeros()));
    assert!(matches!(
        Chain::from_spec(&negative).unwrap().dynamics(),
        Err(RobotError::BadInertia { .. })
    ));
}

/// Oracle: `gravity_torques_into` and the FK kernel's `pose_and_jacobian_into`, called apart,
/// on random chains with prismatic and mimic joints and a tool offset, with a payload.
#[test]
fn the_fused_gravity_and_jacobian_equal_the_two_kernels_apart() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(23);
    for trial in 0..40 {
        let spec = random_chain(&mut rng, 2 + trial % 8, trial % 2 == 1);
        let chain = Chain::from_spec(&spec).unwrap();
        let dynamics = chain.dynamics().unwrap();
        let n = dynamics.dof();
        let mut data = dynamics.data();
        data.set_payload(Some(RigidBody::point(0.7, Vector3::new(0.01, 0.02, 0.05))))
            .unwrap();
        let q = random_vector(&mut rng, n, 2.0);
        let (mut apart, mut fused) = (vec![0.0; n], vec![0.0; n]);
        dynamics
            .gravity_torques_into(&mut data, &q, &mut apart)
            .unwrap();
        let mut expected = nalgebra::Matrix6xX::zeros(n);
        chain.pose_and_jacobian_into(&q, &mut expected).unwrap();
        // A wrong-sized Jacobian is resized.
        let mut jacobian = nalgebra::Matrix6xX::zeros(0);
        dynamics
            .gravity_torques_and_jacobian_into(&mut data, &q, &mut fused, &mut jacobian)
            .unwrap();
        assert_eq!(apart, fused, "trial {trial}: the same gravity torques");
        let scale = expected.amax().max(1.0);
        assert!(
            (&jacobian - &expected).amax() <= 1e-12 * scale,
            "trial {trial}: {jacobian} vs {expected}"
        );
    }
}

/// Oracle: three inverse dynamics calls, `g = τ(q, 0, 0)`, `M q' = τ(q, 0, q') − g` and
/// `M q'' + C(q, q') q' = τ(q, q', q'') − g`, on random chains with a payload.
#[test]
fn path_torques_equal_three_inverse_dynamics_calls() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(29);
    for trial in 0..40 {
        let chain =
            Chain::from_spec(&random_chain(&mut rng, 2 + trial % 8, trial % 2 == 1)).unwrap();
        let dynamics = chain.dynamics().unwrap();
        let n = dynamics.dof();
        let mut data = dynamics.data();
        data.set_payload(Some(RigidBody::new(
            1.3,
            Vector3::new(0.02, -0.01, 0.04),
            Matrix3::from_diagonal(&Vector3::new(0.01, 0.02, 0.015)),
        )))
        .unwrap();
        let q = random_vector(&mut rng, n, 2.0);
        let dq = random_vector(&mut rng, n, 1.5);
        let ddq = random_vector(&mut rng, n, 3.0);
        let zero = vec![0.0; n];
        let [mut g, mut a, mut b, mut rest, mut tau_a, mut tau_b] =
            std::array::from_fn(|_| vec![0.0; n]);
        dynamics
            .path_torques_into(&mut data, &q, &dq, &ddq, &mut g, &mut a, &mut b)
            .unwrap();
        dynamics
            .inverse_dynamics_into(&mut data, &q, &zero, &zero, &mut rest)
            .unwrap();
        dynamics
            .inverse_dynamics_into(&mut data, &q, &zero, &dq, &mut tau_a)
            .unwrap();
        dynamics
            .inverse_dynamics_into(&mut data, &q, &dq, &ddq, &mut tau_b)
            .unwrap();
        let scale = rest
            .iter()
            .chain(&tau_a)
            .chain(&tau_b)
            .fold(1.0_f64, |m, v| m.max(v.abs()));
        for j in 0..n {
            close(g[j], rest[j], 1e-12 * scale, "g");
            close(a[j], tau_a[j] - rest[j], 1e-11 * scale, "M q'");
            close(b[j], tau_b[j] - rest[j], 1e-11 * scale, "M q'' + C q'");
        }
    }
}

/// The mass matrix compiled for AVX2 (where the processor has it) equals the portable build
/// bit for bit: the same operations, no fused multiply–add.
#[test]
fn the_mass_matrix_is_the_same_bits_with_and_without_avx2() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(31);
    for trial in 0..40 {
        let chain =
            Chain::from_spec(&random_chain(&mut rng, 2 + trial % 8, trial % 2 == 1)).unwrap();
        let dynamics = chain.dynamics().unwrap();
        let n = dynamics.dof();
        let mut data = dynamics.data();
        data.set_payload(Some(RigidBody::point(0.4, Vector3::new(0.0, 0.03, 0.02))))
            .unwrap();
        let q = random_vector(&mut rng, n, 2.0);
        let (mut dispatched, mut portable) = (vec![0.0; n * n], vec![0.0; n * n]);
        dynamics.crba_unchecked(&mut data, &q, &mut dispatched);
        dynamics.crba_portable(&mut data, &q, &mut portable);
        let bits = |m: &[f64]| m.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&dispatched), bits(&portable), "trial {trial}");
    }
}

/// The torques per kilogram at a tool point equal the gravity torques with that mass attached
/// as a payload (joined to the last body) minus those without, and scale with the mass, on
/// random chains with prismatic, fixed and mimic joints and a tilted gravity.
#[test]
fn point_load_torques_are_the_payload_difference_per_kilogram() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(41);
    for trial in 0..40 {
        let chain =
            Chain::from_spec(&random_chain(&mut rng, 1 + trial % 8, trial % 3 == 1)).unwrap();
        let gravity = Vector3::new(0.8, -1.1, -9.7);
        let dynamics = chain.dynamics().unwrap().with_gravity(gravity).unwrap();
        let n = dynamics.dof();
        let q = random_vector(&mut rng, n, 2.0);
        let point = Vector3::from_vec(random_vector(&mut rng, 3, 0.3));
        let mut data = dynamics.data();
        let (mut tau, mut per_kg) = (vec![0.0; n], vec![0.0; n]);
        dynamics
            .gravity_torques_and_point_load_into(&mut data, &q, &point, &mut tau, &mut per_kg)
            .unwrap();
        let empty = dynamics.gravity_torques(&q).unwrap();
        for mass in [1.0, 2.5] {
            let mut loaded_data = dynamics.data();
            loaded_data
                .set_payload(Some(RigidBody::point(mass, point)))
                .unwrap();
            let mut loaded = vec![0.0; n];
            dynamics
                .gravity_torques_into(&mut loaded_data, &q, &mut loaded)
                .unwrap();
            let scale = loaded
                .iter()
                .chain(&empty)
                .fold(1.0_f64, |m, v| m.max(v.abs()));
            for j in 0..n {
                assert_eq!(tau[j], empty[j], "g(q), trial {trial}");
                close(
                    empty[j] + mass * per_kg[j],
                    loaded[j],
                    1e-12 * scale,
                    "τ + m · per_kg",
                );
            }
        }
    }
    let dynamics = Chain::from_spec(&random_chain(&mut rng, 3, false))
        .unwrap()
        .dynamics()
        .unwrap();
    let n = dynamics.dof();
    let (mut tau, mut per_kg) = (vec![0.0; n], vec![0.0; n]);
    let error = dynamics
        .gravity_torques_and_point_load_into(
            &mut dynamics.data(),
            &vec![0.0; n],
            &Vector3::new(0.0, f64::NAN, 0.0),
            &mut tau,
            &mut per_kg,
        )
        .unwrap_err();
    assert!(error.to_string().contains("point"), "{error}");
}

/// The mass matrix sees a payload as the inverse dynamics do (`M q̈ = τ(q, 0, q̈) − g(q)`
/// with the payload), and removing the payload gives back the workspace's own mass matrix
/// bit for bit, on chains of 1 to 12 joints (one to three groups of four bodies).
#[test]
fn the_mass_matrix_follows_the_payload_on_and_off() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(47);
    for joints in 1..=12 {
        let chain = Chain::from_spec(&random_chain(&mut rng, joints, joints % 3 == 0)).unwrap();
        let dynamics = chain.dynamics().unwrap();
        let n = dynamics.dof();
        let q = random_vector(&mut rng, n, 2.0);
        let qdd = random_vector(&mut rng, n, 3.0);
        let zero = vec![0.0; n];
        let mut data = dynamics.data();
        let mut bare = DMatrix::zeros(n, n);
        dynamics.mass_matrix_into(&mut data, &q, &mut bare).unwrap();
        let mut payload = RigidBody::point(1.3, Vector3::new(0.02, -0.05, 0.11));
        payload.inertia = Matrix3::new(0.02, 0.001, 0.0, 0.001, 0.03, -0.002, 0.0, -0.002, 0.01);
        data.set_payload(Some(payload)).unwrap();
        let mut loaded = DMatrix::zeros(n, n);
        dynamics
            .mass_matrix_into(&mut data, &q, &mut loaded)
            .unwrap();
        let (mut g, mut tau) = (vec![0.0; n], vec![0.0; n]);
        dynamics
            .inverse_dynamics_into(&mut data, &q, &zero, &zero, &mut g)
            .unwrap();
        dynamics
            .inverse_dynamics_into(&mut data, &q, &zero, &qdd, &mut tau)
            .unwrap();
        let mq = &loaded * DVector::from_column_slice(&qdd);
        let scale = mq.amax().max(1.0);
        for j in 0..n {
            close(tau[j] - g[j], mq[j], 1e-11 * scale, "M q̈ with the payload");
        }
        assert!(
            (&loaded - &bare).amax() > 1e-6,
            "{joints} joints: the payload is seen"
        );
        data.set_payload(None).unwrap();
        let mut again = DMatrix::zeros(n, n);
        dynamics
            .mass_matrix_into(&mut data, &q, &mut again)
            .unwrap();
        let bits = |m: &DMatrix<f64>| m.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&again),
            bits(&bare),
            "{joints} joints: payload removed"
        );
    }
}

/// A body's principal spread gives back its inertia, `λ 1 − a aᵀ − b bᵀ = I`, with `λ` the
/// largest principal moment, for random symmetric inertias (rods, discs, near-isotropic and
/// zero ones included).
#[test]
fn the_principal_spread_recomposes_the_inertia() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(53);
    let mut inertias = vec![Matrix3::zeros(), Matrix3::identity() * 0.2];
    for _ in 0..200 {
        let axes = random_turn(&mut rng).to_rotation_matrix().into_inner();
        let scale = 10f64.powf(rng.random_range(-6.0..1.0));
        let moments = Vector3::new(
            rng.random_range(0.0..1.0),
            rng.random_range(0.0..1.0),
            rng.random_range(0.0..1e-3),
        ) * scale;
        inertias.push(axes * Matrix3::from_diagonal(&moments) * axes.transpose());
    }
    for inertia in inertias {
        let inertia = (inertia + inertia.transpose()) / 2.0;
        let spread = super::PrincipalSpread::of(&inertia).expect("a symmetric 3 × 3 converges");
        let [a, b] = spread.axes;
        let back = Matrix3::identity() * spread.peak - a * a.transpose() - b * b.transpose();
        let largest = inertia.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(
            (back - inertia).amax() <= 1e-14 * largest,
            "{inertia} came back as {back}"
        );
        let eigen_max = inertia.symmetric_eigenvalues().max();
        assert!((spread.peak - eigen_max).abs() <= 1e-14 * largest.max(f64::MIN_POSITIVE));
    }
}
