//! The geometric Jacobian against finite differences of forward kinematics (Baxter built in
//! and from URDF, Panda, UR5), a planar 2R arm's closed form, and property tests.

mod common;

use graspath::geometry::so3_log;
use graspath::manipulability::{task_relevant, yoshikawa, Direction, JacobianPart};
use graspath::robot::builtin::{baxter, Arm};
use graspath::robot::{load_urdf_chain, parse_urdf_chain, Chain};
use nalgebra::{Matrix6xX, Vector3, Vector6};
use proptest::prelude::*;
use rand::{RngExt, SeedableRng};

/// Central differences of FK: linear rows from the tip position, angular rows from
/// `log(R(q+h) R(q−h)ᵀ) / 2h`.
fn finite_difference_jacobian(chain: &Chain, q: &[f64]) -> Matrix6xX<f64> {
    let h = 1e-6;
    let mut jac = Matrix6xX::zeros(chain.dof());
    for j in 0..chain.dof() {
        let mut plus = q.to_vec();
        let mut minus = q.to_vec();
        plus[j] += h;
        minus[j] -= h;
        let a = chain.pose(&plus).unwrap();
        let b = chain.pose(&minus).unwrap();
        let dv = (a.translation.vector - b.translation.vector) / (2.0 * h);
        let dw = so3_log(&(a.rotation * b.rotation.inverse())) / (2.0 * h);
        jac.set_column(j, &Vector6::new(dv.x, dv.y, dv.z, dw.x, dw.y, dw.z));
    }
    jac
}

fn random_configurations(chain: &Chain, count: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            chain
                .lower()
                .iter()
                .zip(chain.upper())
                .map(|(&lo, &hi)| {
                    let (lo, hi) = (lo.max(-std::f64::consts::PI), hi.min(std::f64::consts::PI));
                    rng.random_range(lo..=hi)
                })
                .collect()
        })
        .collect()
}

fn check_against_finite_differences(chain: &Chain, seed: u64) {
    for q in random_configurations(chain, 50, seed) {
        let (_, jac) = chain.pose_and_jacobian(&q).unwrap();
        let fd = finite_difference_jacobian(chain, &q);
        let error = (jac - &fd).abs().max();
        assert!(
            error < 1e-7,
            "{}: |J − J_fd| = {error} at {q:?}",
            chain.name()
        );
    }
}

#[test]
fn baxter_builtin_jacobian_matches_finite_differences() {
    check_against_finite_differences(&baxter(Arm::Left), 1);
    check_against_finite_differences(&baxter(Arm::Right), 2);
}

#[test]
fn shared_robots_jacobians_match_finite_differences() {
    let Some(dir) = common::shared_dir() else {
        eprintln!("skipped: ../shared is not present");
        return;
    };
    for (file, base, tip) in [
        ("baxter.urdf", "base", "right_gripper"),
        ("panda.urdf", "panda_link0", "panda_hand_tcp"),
        ("ur5_robot.urdf", "base_link", "tool0"),
    ] {
        let chain = load_urdf_chain(&dir.join("robots").join(file), base, tip, None).unwrap();
        check_against_finite_differences(&chain, 3);
    }
}

#[test]
fn builtin_baxter_equals_the_published_urdf() {
    let Some(path) = common::shared_file("robots/baxter.urdf") else {
        return;
    };
    for arm in [Arm::Left, Arm::Right] {
        let builtin = baxter(arm);
        let loaded = load_urdf_chain(&path, "base", &format!("{arm}_gripper"), None).unwrap();
        assert_eq!(builtin.joint_names(), loaded.joint_names());
        assert_eq!(builtin.lower(), loaded.lower());
        assert_eq!(builtin.upper(), loaded.upper());
        for q in random_configurations(&builtin, 100, 4) {
            let (pa, ja) = builtin.pose_and_jacobian(&q).unwrap();
            let (pb, jb) = loaded.pose_and_jacobian(&q).unwrap();
            assert!((pa.to_homogeneous() - pb.to_homogeneous()).abs().max() < 1e-14);
            assert!((ja - jb).abs().max() < 1e-14);
        }
    }
}

const PLANAR_2R: &str = r#"<robot name="planar">
  <link name="base"/><link name="upper"/><link name="lower"/><link name="tip"/>
  <joint name="q1" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="q2" type="revolute"><parent link="upper"/><child link="lower"/>
    <origin xyz="0.7 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="end" type="fixed"><parent link="lower"/><child link="tip"/><origin xyz="0.4 0 0"/></joint>
</robot>"#;

proptest! {
    #[test]
    fn planar_2r_matches_closed_forms(q1 in -3.0..3.0f64, q2 in -3.0..3.0f64, angle in 0.0..6.3f64) {
        let (l1, l2) = (0.7, 0.4);
        let chain = parse_urdf_chain(PLANAR_2R, "planar", "base", "tip").unwrap();
        let (pose, jac) = chain.pose_and_jacobian(&[q1, q2]).unwrap();
        // Closed-form position.
        let x = l1 * q1.cos() + l2 * (q1 + q2).cos();
        let y = l1 * q1.sin() + l2 * (q1 + q2).sin();
        prop_assert!((pose.translation.vector - Vector3::new(x, y, 0.0)).norm() < 1e-12);
        // Closed-form planar manipulability l1·l2·|sin q2| of the x–y rows.
        let planar = nalgebra::Matrix2::new(jac[(0, 0)], jac[(0, 1)], jac[(1, 0)], jac[(1, 1)]);
        let expected = l1 * l2 * q2.sin().abs();
        prop_assert!((planar.determinant().abs() - expected).abs() < 1e-12);
        // Translational Yoshikawa of a planar arm: √det(Jv Jvᵀ) is 0 (z row is zero) ...
        prop_assert!(yoshikawa(&jac, JacobianPart::Translation) < 1e-12);
        // ... and M_T along an in-plane unit u equals ‖Jᵀu‖² computed by hand.
        let u = Vector3::new(angle.cos(), angle.sin(), 0.0);
        let by_hand: f64 = (0..2)
            .map(|c| (jac[(0, c)] * u.x + jac[(1, c)] * u.y).powi(2))
            .sum();
        let m_t = task_relevant(&jac, &Direction::Translation(u));
        prop_assert!((m_t - by_hand).abs() < 1e-12);
    }

    #[test]
    fn eigen_form_of_task_relevant_index_equals_the_norm_form(
        q in prop::array::uniform7(-1.0..1.0f64),
        u in prop::array::uniform6(-1.0..1.0f64),
    ) {
        let chain = baxter(Arm::Left);
        let (_, jac) = chain.pose_and_jacobian(&q).unwrap();
        let u = Vector6::from_column_slice(&u);
        prop_assume!(u.norm() > 1e-3);
        let u = u.normalize();
        // Σ_j λ_j (v_j·u)², eigenpairs of J Jᵀ — the paper's eq. 13.
        let eigen = (&jac * jac.transpose()).symmetric_eigen();
        let eigen_form: f64 = (0..6)
            .map(|k| eigen.eigenvalues[k] * eigen.eigenvectors.column(k).dot(&u).powi(2))
            .sum();
        let m_t = task_relevant(&jac, &Direction::Full(u));
        prop_assert!((m_t - eigen_form).abs() < 1e-12 * eigen_form.max(1.0));
    }

    #[test]
    fn fixed_size_chain_equals_dynamic_chain(q in prop::array::uniform7(-1.5..1.5f64)) {
        let chain = baxter(Arm::Right);
        let fixed = chain.fixed::<7>().unwrap();
        let (pa, ja) = chain.pose_and_jacobian(&q).unwrap();
        let (pb, jb) = fixed.pose_and_jacobian(&q);
        prop_assert_eq!(pa, pb);
        prop_assert_eq!(ja.as_slice(), jb.as_slice());
        prop_assert_eq!(fixed.pose(&q), pa);
    }

    #[test]
    fn yoshikawa_is_invariant_to_rotating_the_base(q in prop::array::uniform7(-1.5..1.5f64), yaw in -3.0..3.0f64) {
        // Rotating the base frame rotates J's rows blockwise; √det(JJᵀ) cannot change.
        let chain = baxter(Arm::Left);
        let (_, jac) = chain.pose_and_jacobian(&q).unwrap();
        let r = nalgebra::Rotation3::from_euler_angles(0.3, -0.2, yaw).into_inner();
        let mut rotated = jac.clone();
        let top = r * jac.rows(0, 3);
        let bottom = r * jac.rows(3, 3);
        rotated.rows_mut(0, 3).copy_from(&top);
        rotated.rows_mut(3, 3).copy_from(&bottom);
        let a = yoshikawa(&jac, JacobianPart::Full);
        let b = yoshikawa(&rotated, JacobianPart::Full);
        prop_assert!((a - b).abs() < 1e-12 * a.max(1e-3));
    }
}

#[test]
fn prismatic_and_mimic_joints() {
    // A slider, a revolute joint and a mimic joint that turns twice as far as its leader.
    let urdf = r#"<robot name="mix">
      <link name="a"/><link name="b"/><link name="c"/><link name="d"/>
      <joint name="slide" type="prismatic"><parent link="a"/><child link="b"/>
        <axis xyz="0 1 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="turn" type="continuous"><parent link="b"/><child link="c"/>
        <origin xyz="0.3 0 0" rpy="0.1 0.2 0.3"/><axis xyz="1 0 0"/></joint>
      <joint name="follow" type="revolute"><parent link="c"/><child link="d"/>
        <origin xyz="0.2 0.1 0"/><axis xyz="0 0 -1"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
        <mimic joint="turn" multiplier="2" offset="0.1"/></joint>
    </robot>"#;
    let chain = parse_urdf_chain(urdf, "mix", "a", "d").unwrap();
    assert_eq!(chain.dof(), 2);
    assert!(chain.lower()[1].is_infinite());
    for q in [[0.1, 0.4], [-0.5, 2.0], [0.9, -1.2]] {
        let (_, jac) = chain.pose_and_jacobian(&q).unwrap();
        let fd = finite_difference_jacobian(&chain, &q);
        assert!((jac - fd).abs().max() < 1e-7);
    }
    assert!(
        chain.fixed::<2>().is_err(),
        "mimic chains have no fixed-size form"
    );
}

#[test]
fn joint_origins_end_at_the_tip_and_keep_link_lengths() {
    let chain = baxter(Arm::Left);
    for q in random_configurations(&chain, 20, 9) {
        let points = chain.joint_origins(&q).unwrap();
        assert_eq!(points.len(), chain.dof() + 2);
        let tip = chain.pose(&q).unwrap().translation.vector;
        assert!((points.last().unwrap().coords - tip).norm() < 1e-12);
        // The distance between consecutive joint origins does not depend on q (rigid links).
        let reference = chain.joint_origins(&[0.0; 7]).unwrap();
        for k in 1..points.len() {
            let a = (points[k] - points[k - 1]).norm();
            let b = (reference[k] - reference[k - 1]).norm();
            assert!((a - b).abs() < 1e-12);
        }
    }
}
