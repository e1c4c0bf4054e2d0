//! End to end: train on a demonstrated pinch of a box, then generate on the training cloud,
//! on other boxes, a cylinder and a T-shape; determinism; a three-finger URDF hand.

use graspath::cloud::{CloudShape, LegacyTShape, PointCloud, SampleOptions};
use graspath::geometry::pose_from_rows;
use graspath::geometry::shape::Shape;
use graspath::grasp::hand::Hand;
use graspath::grasp::model::{
    candidates_json, generate, train_file, Candidate, GenerateOptions, GraspModel,
};
use nalgebra::{Isometry3, Vector3};
use std::path::PathBuf;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn box_model() -> GraspModel {
    train_file(&repo().join("examples/grasp/demo_box.json")).expect("train")
}

fn small_budget(seed: u64) -> GenerateOptions {
    GenerateOptions {
        initial_grasps: 4000,
        steps: 200,
        first_stage_steps: 30,
        query_kernels: 2000,
        seed,
        ..GenerateOptions::default()
    }
}

fn cloud(shape: CloudShape, seed: u64) -> PointCloud {
    shape
        .sample(&SampleOptions {
            points: 4000,
            seed,
            ..Default::default()
        })
        .expect("cloud")
}

fn run(model: &GraspModel, cloud: &PointCloud, seed: u64) -> Vec<Candidate> {
    generate(model, cloud, &small_budget(seed), "test cloud", &|_| {}).expect("generate")
}

/// Position (m) and angle (rad) between a wrist pose and the demonstrated one, up to the
/// symmetries that make grasps indistinguishable: the box's (half turns about its axes) and the
/// parallel gripper's own (half a turn about the approach axis swaps the fingers).
fn distance_to_demo(a: &Isometry3<f64>, demo: &Isometry3<f64>) -> (f64, f64) {
    let half = std::f64::consts::PI;
    let flip = Isometry3::rotation(Vector3::z() * half);
    let mut best = (f64::INFINITY, f64::INFINITY);
    for axis in [Vector3::zeros(), Vector3::x(), Vector3::y(), Vector3::z()] {
        for gripper in [Isometry3::identity(), flip] {
            let target = Isometry3::rotation(axis * half) * demo * gripper;
            let d = (a.translation.vector - target.translation.vector).norm();
            let angle = a.rotation.angle_to(&target.rotation);
            if d + 0.05 * angle < best.0 + 0.05 * best.1 {
                best = (d, angle);
            }
        }
    }
    best
}

/// Deepest penetration (m) of any cloud point into any link shape at the grasp.
fn deepest(hand: &Hand, c: &Candidate, cloud: &PointCloud) -> f64 {
    let poses = hand.link_poses(&c.hand_joints);
    let wrist_from_object = c.object_from_wrist.inverse();
    let mut worst: f64 = 0.0;
    for p in &cloud.points {
        let p = wrist_from_object * p;
        for (i, pose) in poses.iter().enumerate() {
            if let Some(prox) = hand.link_proximity(i, pose, &p) {
                worst = worst.max(-prox.signed_distance);
            }
        }
    }
    worst
}

/// Checks that a Baxter candidate is an antipodal pinch: object surface within 10 mm of both
/// finger pads, the surfaces facing the pads (normals along ±y of the wrist), the opening in
/// the gripper range and wider than the object between the pads, and no point deeper than 4 mm
/// in any link.
fn assert_antipodal_pinch(model: &GraspModel, c: &Candidate, cloud: &PointCloud, what: &str) {
    let hand = &model.hand;
    let w = c.hand_joints[0];
    assert!((0.01..=0.07).contains(&w), "{what}: opening {w}");
    let poses = hand.link_poses(&c.hand_joints);
    let wrist_from_object = c.object_from_wrist.inverse();
    let normals = cloud.normals.as_ref().expect("normals");
    let mut facing = [Vector3::zeros(), Vector3::zeros()];
    let mut near = [0usize; 2];
    let mut span: (f64, f64) = (f64::INFINITY, f64::NEG_INFINITY);
    for (p, n) in cloud.points.iter().zip(normals) {
        let p = wrist_from_object * p;
        let n = wrist_from_object * n;
        if p.x.abs() < 0.01 && p.z > -0.09 && p.z < 0.0 && p.y.abs() < w / 2.0 + 0.01 {
            span = (span.0.min(p.y), span.1.max(p.y));
        }
        for (k, link) in [1usize, 2].into_iter().enumerate() {
            let prox = hand
                .link_proximity(link, &poses[link], &p)
                .expect("finger shape");
            if prox.signed_distance < 0.01 {
                near[k] += 1;
                facing[k] += n;
            }
        }
    }
    assert!(
        near[0] > 5 && near[1] > 5,
        "{what}: points near the fingers {near:?}"
    );
    let l = facing[0].normalize();
    let r = facing[1].normalize();
    assert!(
        l.y > 0.7 && r.y < -0.7,
        "{what}: surface normals at the pads {l} {r}"
    );
    assert!(
        span.1 - span.0 <= w + 0.004,
        "{what}: object {:.1} mm wide between pads {:.1} mm apart",
        (span.1 - span.0) * 1e3,
        w * 1e3
    );
    let depth = deepest(hand, c, cloud);
    assert!(depth < 0.004, "{what}: penetration {depth}");
}

#[test]
fn the_demonstrated_grasp_is_found_again_on_the_training_cloud() {
    let model = box_model();
    assert_eq!(
        model.contact_links().count(),
        2,
        "both fingers touch, the palm does not"
    );
    let demo = pose_from_rows(&model.demonstration.object_from_wrist).expect("pose");
    let training = cloud(Shape::cuboid([0.05, 0.04, 0.14]).unwrap().into(), 1);
    let candidates = run(&model, &training, 3);
    assert!(!candidates.is_empty());
    let top = &candidates[..candidates.len().min(20)];
    let best = top
        .iter()
        .map(|c| distance_to_demo(&c.object_from_wrist, &demo))
        .min_by(|a, b| (a.0 + a.1 * 0.05).total_cmp(&(b.0 + b.1 * 0.05)))
        .expect("some");
    assert!(
        best.0 < 0.005 && best.1.to_degrees() < 10.0,
        "closest of the top 20: {:.1} mm, {:.1}°",
        best.0 * 1e3,
        best.1.to_degrees()
    );
    for (k, c) in candidates.iter().take(5).enumerate() {
        assert_antipodal_pinch(&model, c, &training, &format!("training box #{k}"));
    }
}

#[test]
fn novel_objects_get_antipodal_pinches_that_fit_and_do_not_penetrate() {
    let model = box_model();
    let objects = [
        (
            "box 40×100×120",
            Shape::cuboid([0.04, 0.1, 0.12]).unwrap().into(),
        ),
        (
            "box 56×70×90",
            Shape::cuboid([0.056, 0.07, 0.09]).unwrap().into(),
        ),
        (
            "cylinder r 22",
            Shape::cylinder(0.022, 0.12).unwrap().into(),
        ),
        (
            "T-shape",
            CloudShape::LegacyT(
                LegacyTShape::new([0.04, 0.045, 0.1], [0.16, 0.045, 0.04]).unwrap(),
            ),
        ),
    ];
    for (k, (name, shape)) in objects.into_iter().enumerate() {
        let c = cloud(shape, 20 + k as u64);
        let candidates = run(&model, &c, 7);
        assert!(candidates.len() >= 3, "{name}");
        for (rank, cand) in candidates.iter().take(3).enumerate() {
            assert_antipodal_pinch(&model, cand, &c, &format!("{name} #{rank}"));
        }
    }
}

#[test]
fn same_seed_same_bytes_at_any_thread_count() {
    let model = box_model();
    let c = cloud(Shape::cylinder(0.025, 0.1).unwrap().into(), 9);
    let bytes = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| candidates_json(&run(&model, &c, 42), &model.label).expect("json"))
    };
    let one = bytes(1);
    assert_eq!(one, bytes(2));
    assert_eq!(one, bytes(3));
    let other = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("pool")
        .install(|| candidates_json(&run(&model, &c, 43), &model.label).expect("json"));
    assert_ne!(one, other, "another seed gives other candidates");
}

#[test]
fn three_finger_urdf_hand_learns_and_grasps_a_new_cylinder() {
    let model = train_file(&repo().join("crates/graspath/tests/data/three_finger_demo.json"))
        .expect("train");
    assert_eq!(model.hand.dof(), 2);
    let fingers: Vec<&str> = model.contact_links().map(|(link, _)| link).collect();
    assert!(
        fingers.len() >= 2 && fingers.iter().all(|f| f.starts_with("finger_")),
        "{fingers:?}"
    );
    let c = cloud(Shape::cylinder(0.027, 0.12).unwrap().into(), 31);
    let candidates = run(&model, &c, 5);
    let best = candidates.first().expect("a candidate");
    let poses = model.hand.link_poses(&best.hand_joints);
    let wrist_from_object = best.object_from_wrist.inverse();
    for link in &fingers {
        let link_index = model.hand.link_index(link).expect("a hand link");
        let closest = c
            .points
            .iter()
            .filter_map(|p| {
                model
                    .hand
                    .link_proximity(link_index, &poses[link_index], &(wrist_from_object * p))
            })
            .map(|prox| prox.signed_distance)
            .fold(f64::INFINITY, f64::min);
        assert!(
            closest < 0.01,
            "{} is {:.1} mm from the object",
            link,
            closest * 1e3
        );
    }
    assert!(deepest(&model.hand, best, &c) < 0.004);
    assert!(best.log_likelihood > -100.0, "{}", best.log_likelihood);
}
