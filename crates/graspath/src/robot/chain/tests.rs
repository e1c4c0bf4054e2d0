//! The kernels against the scalar passes, bit for bit, on random chains (revolute, continuous,
//! prismatic, fixed and mimic joints), and the batch entry points against one call each.

#[cfg(target_arch = "x86_64")]
use super::avx2;
#[cfg(target_arch = "x86_64")]
use super::forward::{forward_scalar, link_frames_scalar};
use super::{Chain, MotionKind};
use crate::robot::error::RobotError;
use crate::robot::spec::{ChainSpec, JointKind, JointSpec, Mimic};
use nalgebra::{Isometry3, IsometryMatrix3, Matrix3, Translation3, UnitQuaternion, Vector3};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

/// A random chain: random joint placements, axes and kinds, some mimic-free prismatic.
fn random_chain(rng: &mut Xoshiro256PlusPlus, joints: usize) -> Chain {
    let mut specs = Vec::new();
    for i in 0..joints {
        let kind = match rng.random_range(0..6) {
            0 => JointKind::Prismatic,
            1 => JointKind::Fixed,
            2 => JointKind::Continuous,
            _ => JointKind::Revolute,
        };
        let axis = Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        specs.push(JointSpec {
            name: format!("j{i}"),
            child_link: format!("l{i}"),
            kind,
            parent_from_joint: Isometry3::from_parts(
                Translation3::new(
                    rng.random_range(-0.4..0.4),
                    rng.random_range(-0.4..0.4),
                    rng.random_range(-0.4..0.4),
                ),
                UnitQuaternion::from_euler_angles(
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-1.5..1.5),
                    rng.random_range(-3.0..3.0),
                ),
            ),
            axis: axis.normalize(),
            lower: -3.0,
            upper: 3.0,
            mimic: None,
            limits: Default::default(),
            child_inertial: None,
        });
    }
    Chain::from_spec(&ChainSpec {
        source_name: "random".into(),
        base_link: "base".into(),
        tip_link: "tip".into(),
        joints: specs,
        tip_from_tool: None,
    })
    .expect("valid random chain")
}

#[cfg(target_arch = "x86_64")]
#[test]
fn bit_identical_to_the_scalar_pass() {
    if !crate::cpu::has_avx2() {
        eprintln!("no AVX2 on this processor: nothing to compare");
        return;
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    for joints in 0..=14 {
        for _ in 0..50 {
            let chain = random_chain(&mut rng, joints);
            let n = chain.segments.len();
            let q: Vec<f64> = (0..n)
                .map(|_| match rng.random_range(0..10) {
                    0 => rng.random_range(-2e5..2e5),
                    1 => 0.0,
                    2 => -0.0,
                    _ => rng.random_range(-7.0..7.0),
                })
                .collect();
            let tail = (&chain.tail_rotation, &chain.tail_translation);
            let (mut scalar, mut vector) = (vec![0.0; 6 * n], vec![1.0; 6 * n]);
            let a = forward_scalar(&chain.segments, |i| q[i], Some(&mut scalar), tail);
            // SAFETY: AVX2 is present (checked above); the storage has 6·n values.
            let b = unsafe { avx2::forward(&chain.segments, |i| q[i], Some(&mut vector), tail) };
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(scalar.as_slice()),
                bits(vector.as_slice()),
                "q = {q:?}"
            );
            assert_eq!(
                bits(a.to_homogeneous().as_slice()),
                bits(b.to_homogeneous().as_slice())
            );
            let c = unsafe { avx2::forward(&chain.segments, |i| q[i], None, tail) };
            assert_eq!(
                bits(a.to_homogeneous().as_slice()),
                bits(c.to_homogeneous().as_slice())
            );
        }
    }
}

#[test]
fn batches_equal_one_call_per_configuration_bit_for_bit() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    for joints in [1, 3, 6, 7, 9] {
        for _ in 0..20 {
            let chain = random_chain(&mut rng, joints);
            let dof = chain.dof();
            if dof == 0 {
                continue;
            }
            for count in 0..=9 {
                let q: Vec<f64> = (0..count * dof)
                    .map(|_| rng.random_range(-7.0..7.0))
                    .collect();
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                let mut seen = Vec::new();
                chain
                    .for_each_pose_and_jacobian(&q, |k, pose, jacobian| {
                        let (one, expected) =
                            chain.pose_and_jacobian(&q[k * dof..(k + 1) * dof]).unwrap();
                        assert_eq!(
                            bits(pose.to_homogeneous().as_slice()),
                            bits(one.to_homogeneous().as_slice())
                        );
                        assert_eq!(bits(jacobian), bits(expected.as_slice()));
                        seen.push(k);
                    })
                    .unwrap();
                assert_eq!(seen, (0..count).collect::<Vec<_>>());
                let mut poses = 0;
                chain
                    .for_each_pose(&q, |k, pose| {
                        let one = chain.pose(&q[k * dof..(k + 1) * dof]).unwrap();
                        assert_eq!(
                            bits(pose.to_homogeneous().as_slice()),
                            bits(one.to_homogeneous().as_slice())
                        );
                        poses += 1;
                    })
                    .unwrap();
                assert_eq!(poses, count);
            }
        }
    }
}

#[test]
fn batches_of_a_chain_with_a_mimic_joint_equal_single_calls() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    let joint = |name: &str, mimic: Option<Mimic>| JointSpec {
        name: name.into(),
        child_link: String::new(),
        kind: JointKind::Revolute,
        parent_from_joint: Isometry3::from_parts(
            Translation3::new(0.1, 0.02, 0.3),
            UnitQuaternion::from_euler_angles(0.3, -0.2, 0.1),
        ),
        axis: Vector3::new(0.0, 1.0, 0.0),
        lower: -3.0,
        upper: 3.0,
        mimic,
        limits: Default::default(),
        child_inertial: None,
    };
    let chain = Chain::from_spec(&ChainSpec {
        source_name: "mimic".into(),
        base_link: "base".into(),
        tip_link: "tip".into(),
        joints: vec![
            joint("a", None),
            joint("b", None),
            joint(
                "c",
                Some(Mimic {
                    leader: "a".into(),
                    multiplier: 2.0,
                    offset: 0.1,
                }),
            ),
        ],
        tip_from_tool: None,
    })
    .expect("valid chain");
    assert_eq!(chain.dof(), 2);
    let q: Vec<f64> = (0..14).map(|_| rng.random_range(-3.0..3.0)).collect();
    let mut count = 0;
    chain
        .for_each_pose_and_jacobian(&q, |k, pose, jacobian| {
            let (one, expected) = chain.pose_and_jacobian(&q[2 * k..2 * k + 2]).unwrap();
            assert_eq!(pose, &one);
            assert_eq!(jacobian, expected.as_slice());
            count += 1;
        })
        .unwrap();
    assert_eq!(count, 7);
}

#[test]
fn batches_refuse_partial_rows_and_non_finite_values() {
    let chain = random_chain(&mut Xoshiro256PlusPlus::seed_from_u64(3), 7);
    let dof = chain.dof();
    assert!(dof > 1);
    let partial = vec![0.0; 2 * dof + 1];
    let err = chain.for_each_pose(&partial, |_, _| {}).unwrap_err();
    assert!(
        err.to_string().contains(&format!("{} values", 2 * dof + 1)),
        "{err}"
    );
    let mut nan = vec![0.0; 3 * dof];
    nan[dof + 1] = f64::NAN;
    let err = chain
        .for_each_pose_and_jacobian(&nan, |_, _, _| panic!("nothing may be emitted"))
        .unwrap_err();
    assert!(
        err.to_string().contains(&format!("q[{}]", dof + 1)),
        "{err}"
    );
}

/// The bits of row-major poses and Jacobians, one configuration after the other, from one
/// call of `pose_and_jacobian` each.
fn row_major_bits_one_by_one(chain: &Chain, q: &[f64]) -> (Vec<u64>, Vec<u64>) {
    let dof = chain.dof();
    let (mut poses, mut jacobians) = (Vec::new(), Vec::new());
    for row in q.chunks(dof) {
        let (pose, jacobian) = chain.pose_and_jacobian(row).unwrap();
        let matrix = pose.to_homogeneous();
        poses.extend((0..16).map(|k| matrix[(k / 4, k % 4)].to_bits()));
        jacobians.extend((0..6 * dof).map(|k| jacobian[(k / dof, k % dof)].to_bits()));
    }
    (poses, jacobians)
}

#[test]
fn parallel_row_major_batches_equal_one_call_each_at_any_thread_count() {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let mut checked = 0;
    for seed in 0..40 {
        let (chain, _) = chain_and_configurations(seed);
        let dof = chain.dof();
        if dof == 0 {
            continue;
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed + 1000);
        // Several parallel tasks, the last one short and not a whole lane group.
        let count = 2 * super::batch::BATCH_CHUNK + 7;
        let q: Vec<f64> = (0..count * dof)
            .map(|_| rng.random_range(-3.0..3.0))
            .collect();
        let (poses, jacobians) = row_major_bits_one_by_one(&chain, &q);
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let (p, j) = chain.batch_poses_and_jacobians(&q).unwrap();
                assert_eq!(bits(&p), poses, "seed {seed}, {threads} threads");
                assert_eq!(bits(&j), jacobians, "seed {seed}, {threads} threads");
                assert_eq!(bits(&chain.batch_poses(&q).unwrap()), poses);
                assert_eq!(bits(&chain.batch_jacobians(&q).unwrap()), jacobians);
                let mut p = vec![f64::NAN; 16 * count];
                let mut j = vec![f64::NAN; 6 * dof * count];
                chain.batch_into(&q, Some(&mut p), Some(&mut j)).unwrap();
                assert_eq!((bits(&p), bits(&j)), (poses.clone(), jacobians.clone()));
            });
        }
        checked += 1;
    }
    assert!(checked > 30);
}

#[test]
fn parallel_batches_check_their_buffers_and_name_the_first_non_finite_value() {
    let chain = random_chain(&mut Xoshiro256PlusPlus::seed_from_u64(3), 7);
    let dof = chain.dof();
    let count = 3 * super::batch::BATCH_CHUNK;
    let mut q = vec![0.1; count * dof];
    let mut poses = vec![0.0; 16 * count];
    let mut jacobians = vec![0.0; 6 * dof * count];
    let err = chain
        .batch_into(&q[..q.len() - 1], Some(&mut poses), None)
        .unwrap_err();
    assert!(matches!(err, RobotError::WrongDof { .. }), "{err}");
    let err = chain
        .batch_into(&q, Some(&mut poses[..16]), None)
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "the pose buffer has 16 values but {} are needed",
            16 * count
        )
    );
    let err = chain
        .batch_into(&q, None, Some(&mut jacobians[1..]))
        .unwrap_err();
    assert!(
        matches!(
            err,
            RobotError::WrongBufferLength {
                what: "Jacobian",
                ..
            }
        ),
        "{err}"
    );
    // Non-finite values in two parallel tasks: the first one is named, whichever task
    // meets its value first.
    let (first, second) = (
        super::batch::BATCH_CHUNK * dof + 5,
        2 * super::batch::BATCH_CHUNK * dof + 1,
    );
    q[second] = f64::NAN;
    q[first] = f64::INFINITY;
    for threads in [1, 3] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let err = pool
            .install(|| chain.batch_into(&q, Some(&mut poses), Some(&mut jacobians)))
            .unwrap_err();
        assert!(
            matches!(err, RobotError::NonFiniteJoint { index } if index == first),
            "{err}"
        );
        assert!(chain.batch_poses(&q).is_err() && chain.batch_jacobians(&q).is_err());
    }
}

#[test]
fn a_chain_without_joints_gives_its_fixed_tip_pose_to_every_configuration() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    let chain = (0..1000)
        .map(|_| random_chain(&mut rng, 2))
        .find(|c| c.dof() == 0)
        .expect("two fixed joints among 1000 random chains");
    let tip = chain.pose(&[]).unwrap().to_homogeneous();
    let mut poses = vec![f64::NAN; 16 * 600];
    chain
        .batch_into(&[], Some(&mut poses), Some(&mut []))
        .unwrap();
    for pose in poses.chunks(16) {
        assert!((0..16).all(|k| pose[k].to_bits() == tip[(k / 4, k % 4)].to_bits()));
    }
    assert!(chain.batch_into(&[0.0], Some(&mut poses), None).is_err());
    assert!(chain.batch_poses(&[]).unwrap().is_empty());
}

/// A random chain with every kind of joint, mimic followers among them (each follows an
/// earlier independent joint with a random multiplier and offset), and a random tool offset.
fn random_chain_with_mimics(rng: &mut Xoshiro256PlusPlus, joints: usize) -> Chain {
    let mut specs: Vec<JointSpec> = Vec::new();
    let mut leaders: Vec<String> = Vec::new();
    let placement = |rng: &mut Xoshiro256PlusPlus| {
        Isometry3::from_parts(
            Translation3::new(
                rng.random_range(-0.4..0.4),
                rng.random_range(-0.4..0.4),
                rng.random_range(-0.4..0.4),
            ),
            UnitQuaternion::from_euler_angles(
                rng.random_range(-3.0..3.0),
                rng.random_range(-1.5..1.5),
                rng.random_range(-3.0..3.0),
            ),
        )
    };
    for i in 0..joints {
        let kind = match rng.random_range(0..6) {
            0 => JointKind::Prismatic,
            1 => JointKind::Fixed,
            2 => JointKind::Continuous,
            _ => JointKind::Revolute,
        };
        // Some axes exactly along ±z, so that some link offsets are exactly the identity.
        let axis = match rng.random_range(0..4) {
            0 => Vector3::z(),
            1 => -Vector3::z(),
            _ => Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
            .normalize(),
        };
        let follows =
            kind != JointKind::Fixed && !leaders.is_empty() && rng.random_range(0..3) == 0;
        let mimic = follows.then(|| Mimic {
            leader: leaders[rng.random_range(0..leaders.len())].clone(),
            multiplier: rng.random_range(-2.0..2.0),
            offset: rng.random_range(-0.5..0.5),
        });
        let name = format!("j{i}");
        if kind != JointKind::Fixed && mimic.is_none() {
            leaders.push(name.clone());
        }
        let parent_from_joint = if rng.random_range(0..4) == 0 {
            Isometry3::identity()
        } else {
            placement(rng)
        };
        specs.push(JointSpec {
            name,
            child_link: format!("l{i}"),
            kind,
            parent_from_joint,
            axis,
            lower: -3.0,
            upper: 3.0,
            mimic,
            limits: Default::default(),
            child_inertial: None,
        });
    }
    Chain::from_spec(&ChainSpec {
        source_name: "random".into(),
        base_link: "base".into(),
        tip_link: "tip".into(),
        joints: specs,
        tip_from_tool: Some(placement(rng)),
    })
    .expect("valid random chain")
}

/// A configuration mixing ordinary values, signed zeros and values beyond the fast `sin_cos`
/// range.
fn random_configuration(rng: &mut Xoshiro256PlusPlus, dof: usize) -> Vec<f64> {
    (0..dof)
        .map(|_| match rng.random_range(0..10) {
            0 => rng.random_range(-2e5..2e5),
            1 => 0.0,
            2 => -0.0,
            _ => rng.random_range(-7.0..7.0),
        })
        .collect()
}

fn frame_bits(frames: &[IsometryMatrix3<f64>]) -> Vec<u64> {
    frames
        .iter()
        .flat_map(|f| f.to_homogeneous().as_slice().to_vec())
        .map(f64::to_bits)
        .collect()
}

#[cfg(target_arch = "x86_64")]
#[test]
fn link_frame_kernel_is_bit_identical_to_the_scalar_pass() {
    if !crate::cpu::has_avx2() {
        eprintln!("no AVX2 on this processor: nothing to compare");
        return;
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(13);
    let (mut mimics, mut prismatic, mut identities) = (0, 0, 0);
    for joints in 0..=16 {
        for _ in 0..60 {
            let chain = random_chain_with_mimics(&mut rng, joints);
            let q = random_configuration(&mut rng, chain.dof());
            let value = |i: usize| match &chain.drives {
                None => q[i],
                Some(d) => d[i].multiplier * q[d[i].source] + d[i].offset,
            };
            mimics += usize::from(chain.drives.is_some());
            prismatic += chain
                .segments
                .iter()
                .filter(|s| s.kind == MotionKind::Prismatic)
                .count();
            identities += chain.link_slots.iter().filter(|s| s.identity).count();
            let links = chain.link_names().len();
            let identity = IsometryMatrix3::identity();
            let (mut scalar, mut vector) = (vec![identity; links], vec![identity; links]);
            link_frames_scalar(&chain.segments, &chain.link_slots, value, &mut scalar);
            // SAFETY: AVX2 is present (checked above); `vector` has one entry per link.
            unsafe { avx2::link_frames(&chain.segments, &chain.link_slots, value, &mut vector) };
            assert_eq!(frame_bits(&scalar), frame_bits(&vector), "q = {q:?}");
            // The public entry point (which picks the kernel) gives the same bits.
            let mut public = vec![IsometryMatrix3::translation(1.0, 2.0, 3.0); links];
            chain.link_frames_into(&q, &mut public).unwrap();
            assert_eq!(frame_bits(&scalar), frame_bits(&public), "q = {q:?}");
        }
    }
    // The generator did exercise what the test claims to cover.
    assert!(mimics > 100 && prismatic > 100 && identities > 100);
}

/// Four configurations in lane layout give, lane by lane, what one call per configuration
/// gives, bit for bit: on plain chains (one vector pass on AVX2 processors) and on chains with
/// mimic joints (one configuration after the other).
#[test]
fn four_lanes_equal_one_call_per_configuration_bit_for_bit() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(23);
    for joints in [1, 4, 7, 9] {
        for round in 0..16 {
            let chain = if round % 2 == 0 {
                random_chain(&mut rng, joints)
            } else {
                random_chain_with_mimics(&mut rng, joints)
            };
            let dof = chain.dof();
            if dof == 0 {
                continue;
            }
            let configurations: Vec<Vec<f64>> = (0..4)
                .map(|_| random_configuration(&mut rng, dof))
                .collect();
            let lanes: Vec<[f64; 4]> = (0..dof)
                .map(|j| std::array::from_fn(|lane| configurations[lane][j]))
                .collect();
            let mut jacobian = vec![[f64::NAN; 4]; 6 * dof];
            let poses = chain.four_poses_and_jacobians(&lanes, &mut jacobian);
            for (lane, q) in configurations.iter().enumerate() {
                let (pose, expected) = chain.pose_and_jacobian(q).unwrap();
                assert_eq!(
                    frame_bits(&[poses[lane]]),
                    frame_bits(&[pose]),
                    "pose, lane {lane}"
                );
                let got: Vec<u64> = jacobian.iter().map(|v| v[lane].to_bits()).collect();
                let want: Vec<u64> = expected.as_slice().iter().map(|v| v.to_bits()).collect();
                assert_eq!(got, want, "Jacobian, lane {lane}");
            }
        }
    }
}

/// A random chain of either generator, and a configuration inside its limits (every joint's
/// limits are ±3; a revolute joint may turn any amount, which only widens what is reachable).
fn chain_and_configurations(seed: u64) -> (Chain, Vec<Vec<f64>>) {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let joints = rng.random_range(1..10);
    let chain = if seed.is_multiple_of(2) {
        random_chain(&mut rng, joints)
    } else {
        random_chain_with_mimics(&mut rng, joints)
    };
    let configurations = (0..20)
        .map(|_| {
            (0..chain.dof())
                .map(|_| rng.random_range(-3.0..=3.0))
                .collect()
        })
        .collect();
    (chain, configurations)
}

#[test]
fn no_reachable_pose_is_proven_out_of_reach() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(17);
    let mut chains: Vec<(Chain, Vec<Vec<f64>>)> = (0..400).map(chain_and_configurations).collect();
    for robot in crate::robot::builtin::BuiltinRobot::ALL {
        for spec in robot.chain_specs() {
            let chain = Chain::from_spec(&spec).unwrap();
            let configurations = (0..200)
                .map(|_| {
                    (0..chain.dof())
                        .map(|j| {
                            let (lo, hi) = (chain.lower()[j], chain.upper()[j]);
                            if lo.is_finite() && hi.is_finite() {
                                rng.random_range(lo..=hi)
                            } else {
                                rng.random_range(-7.0..7.0)
                            }
                        })
                        .collect()
                })
                .collect();
            chains.push((chain, configurations));
        }
    }
    let (position_tolerance, rotation_tolerance) = (1e-3, 1e-2);
    for (chain, configurations) in &chains {
        for q in configurations {
            let pose = chain.pose(q).unwrap();
            let (p, r) = (pose.translation.vector, *pose.rotation.matrix());
            let proof = chain.out_of_reach(&p, &r, 0.0, 0.0);
            assert!(
                proof.is_none(),
                "{} at {q:?}: {}",
                chain.name(),
                proof.unwrap()
            );
            // A pose just within the tolerances of a reachable one is not out of reach either.
            let shift = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
            .normalize();
            let turn = nalgebra::Rotation3::from_scaled_axis(
                Vector3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                )
                .normalize()
                    * (0.999 * rotation_tolerance),
            );
            let near = chain.out_of_reach(
                &(p + 0.999 * position_tolerance * shift),
                &(turn.matrix() * r),
                position_tolerance,
                rotation_tolerance,
            );
            assert!(
                near.is_none(),
                "{} near {q:?}: {}",
                chain.name(),
                near.unwrap()
            );
        }
    }
}

#[test]
fn the_reach_anchors_are_where_forward_kinematics_puts_the_joints() {
    for seed in 0..400 {
        let (chain, configurations) = chain_and_configurations(seed);
        let n = chain.segments.len();
        for q in &configurations {
            let pose = chain.pose(q).unwrap();
            // [base, b₀, …, bₙ₋₁, tip]: every joint's origin before its own motion.
            let origins: Vec<Vector3<f64>> = chain
                .joint_origins(q)
                .unwrap()
                .iter()
                .map(|p| p.coords)
                .collect();
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()));
            for anchor in chain.base_anchors() {
                let joint = anchor.index / 2;
                let gap = anchor.distance(&origins[1 + joint]);
                assert!(
                    close(gap, 0.0),
                    "seed {seed}: b{joint} is {gap} m off its anchor"
                );
            }
            for anchor in chain.tip_anchors() {
                let point = pose.translation.vector + pose.rotation * anchor.offset;
                if anchor.index == 2 * n {
                    assert!(
                        close((point - origins[n + 1]).norm(), 0.0),
                        "seed {seed}: tip"
                    );
                    continue;
                }
                // aᵢ: bᵢ, moved along the axis by a prismatic joint; only revolute joints are
                // compared here (the after-motion frame of a prismatic one is not listed).
                let joint = (anchor.index - 1) / 2;
                if chain.segments[joint].kind == MotionKind::Revolute {
                    let off = (point - origins[1 + joint]).norm();
                    assert!(
                        close(off, anchor.slack),
                        "seed {seed}: a{joint} is {off} m from its anchor, not {}",
                        anchor.slack
                    );
                }
            }
        }
    }
}

#[test]
fn baxter_grasping_towards_its_shoulder_at_arm_s_length_is_out_of_reach() {
    use crate::robot::builtin::{baxter_spec, Arm};
    let chain = Chain::from_spec(&baxter_spec(Arm::Left)).unwrap();
    // The wrist centre (joint w1's origin) in the tip frame, from forward kinematics.
    let q = chain.mid_configuration();
    let pose = chain.pose(&q).unwrap();
    let origins = chain.joint_origins(&q).unwrap();
    let wrist_in_tip = pose.inverse_transform_point(&origins[6]).coords;
    // A tip 0.55 m out from the shoulder, pointing back at it: the wrist centre lies beyond.
    let s0 = origins[1].coords;
    let out = Vector3::new(1.0, 0.3, -0.2).normalize();
    let position = s0 + 0.55 * out;
    let approach = -out;
    let side = approach.cross(&Vector3::z()).normalize();
    let rotation = Matrix3::from_columns(&[side, approach.cross(&side), approach]);
    let wrist = position + rotation * wrist_in_tip;
    // Brute force: the nearest the shoulder's second joint (s1) comes to the wrist centre as
    // the first joint turns, and the longest the links from s1 to w1 can be end to end.
    let nearest = (0..36_000)
        .map(|k| {
            let mut q = chain.mid_configuration();
            q[0] = k as f64 * std::f64::consts::TAU / 36_000.0;
            (chain.joint_origins(&q).unwrap()[2].coords - wrist).norm()
        })
        .fold(f64::INFINITY, f64::min);
    let links: f64 = (2..6)
        .map(|i| (origins[i + 1].coords - origins[i].coords).norm())
        .sum();
    assert!(
        nearest > links + 0.05,
        "the pose is chosen well out of reach"
    );
    // The tip itself is well within the sphere about the first joint.
    let all_links: f64 = (1..origins.len() - 1)
        .map(|i| (origins[i + 1].coords - origins[i].coords).norm())
        .sum();
    assert!((position - s0).norm() < all_links - 0.3);
    let proof = chain
        .out_of_reach(&position, &rotation, 1e-5, 1e-4)
        .expect("proven out of reach");
    assert!((proof.distance - nearest).abs() < 1e-6, "{proof}");
    assert!((proof.span - links).abs() < 1e-9, "{proof}");
    let text = proof.to_string();
    assert!(
        text.contains("'left_w1'") && text.contains("'left_s1'"),
        "{text}"
    );
}
