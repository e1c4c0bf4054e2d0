//! The collision kernel on the scene workload's link/obstacle pairs
//! (`examples/workload_1000_faces_scene.yaml`): every moving link and hand body of Baxter's
//! left arm against each of the three obstacles (wall, post, crate), at every 20th
//! configuration of the feasible candidates' whole motions (approach → path → retreat).
//!
//! * `graspath_distance`: [`graspath::collision::distance`], the exact distance through our
//!   conversion boundary (poses converted on every call);
//! * `graspath_keeps_apart`: [`graspath::collision::keeps_apart`] at the workload's 1 cm margin,
//!   the decision the motion check takes for every pair at every sample (bounding spheres,
//!   then sphere covers, the exact distance only when neither settles it);
//! * `parry_distance`: `parry3d_f64::query::distance` on the same shapes and poses, converted
//!   once beforehand.
//!
//! The pairs are written to `$CARGO_TARGET_TMPDIR/collision_pairs.json`; with
//! `COAL_PYTHON=<python with the pin wheel>` set, `examples/peers/coal_distance.py` then times
//! coal (Pinocchio's collision library) on the same pairs in the same run.
//!
//! `COAL_PYTHON=target/pyenv/bin/python cargo bench -p graspath --bench collision`

use criterion::{criterion_group, criterion_main, Criterion};
use graspath::collision::{distance, keeps_apart, Body, BodyKind};
use graspath::geometry::shape::Shape;
use graspath::select::select;
use graspath::task::Task;
use nalgebra::{Isometry3, UnitQuaternion};
use parry3d_f64::math::{Pose, Rot3, Vector};
use parry3d_f64::shape::SharedShape;
use std::hint::black_box;
use std::path::PathBuf;

/// Every how many samples of a motion a configuration is taken.
const STRIDE: usize = 20;

/// The workload's margin (m).
const MARGIN: f64 = 0.01;

/// One pair: two bodies and their world poses.
struct Pair<'a> {
    a: &'a Body,
    world_from_a: Isometry3<f64>,
    b: &'a Body,
    world_from_b: Isometry3<f64>,
}

fn shape_of(body: &Body) -> Option<&Shape> {
    match body.kind() {
        BodyKind::Solid(s @ (Shape::Box(_) | Shape::Cylinder(_) | Shape::Sphere(_))) => Some(s),
        _ => None,
    }
}

/// The shape in parry's types, converted here (independently of the library's boundary):
/// parry's cylinders are along `y`, ours along `z`.
fn parry_shape(shape: &Shape) -> (Pose, SharedShape) {
    match shape {
        Shape::Box(b) => {
            let h = b.half_extents();
            (Pose::identity(), SharedShape::cuboid(h.x, h.y, h.z))
        }
        Shape::Cylinder(c) => (
            Pose::from_rotation(Rot3::from_rotation_x(std::f64::consts::FRAC_PI_2)),
            SharedShape::cylinder(c.length() / 2.0, c.radius()),
        ),
        Shape::Sphere(s) => (Pose::identity(), SharedShape::ball(s.radius())),
        _ => unreachable!("only boxes, cylinders and spheres are kept"),
    }
}

fn parry_pose(p: &Isometry3<f64>) -> Pose {
    let q = p.rotation.coords;
    let t = p.translation.vector;
    Pose::from_parts(
        Vector::new(t.x, t.y, t.z),
        Rot3::from_xyzw(q.x, q.y, q.z, q.w),
    )
}

/// `{"box": [x, y, z]}` (full sizes), `{"cylinder": [radius, length]}` (along `z`) or
/// `{"sphere": radius}`, all in metres.
fn shape_json(shape: &Shape) -> serde_json::Value {
    match shape {
        Shape::Box(b) => {
            let h = b.half_extents() * 2.0;
            serde_json::json!({ "box": [h.x, h.y, h.z] })
        }
        Shape::Cylinder(c) => serde_json::json!({ "cylinder": [c.radius(), c.length()] }),
        Shape::Sphere(s) => serde_json::json!({ "sphere": s.radius() }),
        _ => unreachable!("only boxes, cylinders and spheres are kept"),
    }
}

/// `[x, y, z, qx, qy, qz, qw]` (m, unit quaternion).
fn pose_json(p: &Isometry3<f64>) -> serde_json::Value {
    let q: &UnitQuaternion<f64> = &p.rotation;
    let t = p.translation.vector;
    serde_json::json!([t.x, t.y, t.z, q.i, q.j, q.k, q.w])
}

fn kernel(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/workload_1000_faces_scene.yaml");
    let task = Task::load(&path).expect("the scene workload loads");
    let arm = &task.arms()[0];
    let bodies = arm.bodies.as_ref().expect("the workload checks collisions");
    let scene = &task
        .collisions()
        .as_ref()
        .expect("the workload has a scene")
        .scene;
    let selection = select(&task, &|| {}).unwrap();
    let mut configurations = Vec::new();
    for score in selection.arms[0].scores.iter().filter(|s| s.feasible()) {
        let whole = score
            .approach
            .iter()
            .chain(&score.joint_trajectory)
            .chain(&score.retreat);
        configurations.extend(whole.step_by(STRIDE).cloned());
    }
    let world_from_base = arm.world_from_base;
    let mut pairs = Vec::new();
    for q in &configurations {
        let frames = arm
            .chain
            .link_frames(q)
            .expect("IK solutions are in the limits");
        for (i, (link, link_from_body, body)) in bodies.bodies().enumerate() {
            if !bodies.moves(i) || shape_of(body).is_none() {
                continue;
            }
            let world_from_a = world_from_base
                * nalgebra::convert::<_, Isometry3<f64>>(frames[link] * link_from_body);
            for obstacle in scene.obstacles() {
                if shape_of(&obstacle.body).is_some() {
                    pairs.push(Pair {
                        a: body,
                        world_from_a,
                        b: &obstacle.body,
                        world_from_b: obstacle.world_from_body,
                    });
                }
            }
        }
    }
    // The same pairs in parry's types, converted once; and their distances both ways.
    let converted: Vec<_> = pairs
        .iter()
        .map(|p| {
            let (a_at, a) = parry_shape(shape_of(p.a).expect("kept"));
            let (b_at, b) = parry_shape(shape_of(p.b).expect("kept"));
            (
                parry_pose(&p.world_from_a) * a_at,
                a,
                parry_pose(&p.world_from_b) * b_at,
                b,
            )
        })
        .collect();
    let ours: Vec<f64> = pairs
        .iter()
        .map(|p| distance(p.a, &p.world_from_a, p.b, &p.world_from_b))
        .collect();
    let mut worst: f64 = 0.0;
    for ((pa, a, pb, b), d) in converted.iter().zip(&ours) {
        let theirs = parry3d_f64::query::distance(pa, a.as_ref(), pb, b.as_ref())
            .expect("convex pairs have a distance")
            .distance;
        worst = worst.max((theirs - d).abs());
    }
    let close = ours.iter().filter(|&&d| d < MARGIN).count();
    let mut sorted = ours.clone();
    sorted.sort_by(f64::total_cmp);
    let within = |limit: f64| sorted.partition_point(|&d| d < limit);
    let decided: usize = pairs
        .iter()
        .filter(|p| keeps_apart(p.a, &p.world_from_a, p.b, &p.world_from_b, MARGIN))
        .count();
    eprintln!(
        "collision kernel: {} pairs from {} configurations; {close} closer than {MARGIN} m \
         ({decided} kept apart); distances: min {:.4} m, median {:.4} m, {} within 5 cm, {} \
         within 10 cm; graspath vs parry-only distances differ by at most {worst:.1e} m",
        pairs.len(),
        configurations.len(),
        sorted[0],
        sorted[sorted.len() / 2],
        within(0.05),
        within(0.10),
    );
    assert_eq!(
        decided,
        pairs.len() - close,
        "the decision agrees with the distance"
    );

    let file = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("collision_pairs.json");
    let json = serde_json::json!({
        "source": "crates/graspath/benches/collision.rs on examples/workload_1000_faces_scene.yaml",
        "margin": MARGIN,
        "pairs": pairs.iter().zip(&ours).map(|(p, d)| serde_json::json!({
            "a": shape_json(shape_of(p.a).expect("kept")),
            "pose_a": pose_json(&p.world_from_a),
            "b": shape_json(shape_of(p.b).expect("kept")),
            "pose_b": pose_json(&p.world_from_b),
            "distance": d,
        })).collect::<Vec<_>>(),
    });
    std::fs::write(&file, serde_json::to_string(&json).expect("JSON"))
        .expect("the pairs file is written");

    let mut group = c.benchmark_group("collision_kernel");
    group.bench_function("graspath_distance", |b| {
        b.iter(|| {
            for p in &pairs {
                black_box(distance(p.a, &p.world_from_a, p.b, &p.world_from_b));
            }
        });
    });
    group.bench_function("graspath_keeps_apart", |b| {
        b.iter(|| {
            for p in &pairs {
                black_box(keeps_apart(
                    p.a,
                    &p.world_from_a,
                    p.b,
                    &p.world_from_b,
                    MARGIN,
                ));
            }
        });
    });
    group.bench_function("parry_distance", |b| {
        b.iter(|| {
            for (pa, a, pb, b) in &converted {
                black_box(parry3d_f64::query::distance(pa, a.as_ref(), pb, b.as_ref()).ok());
            }
        });
    });
    group.finish();

    // The peer, in the same run.
    if let Ok(python) = std::env::var("COAL_PYTHON") {
        // Relative to the workspace root (benches run in the package directory).
        let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
        let python = root.join(python);
        let script = root.join("examples/peers/coal_distance.py");
        let status = std::process::Command::new(python)
            .arg(&script)
            .arg(&file)
            .status();
        match status {
            Ok(s) if s.success() => {}
            other => eprintln!("coal peer did not run: {other:?}"),
        }
    } else {
        eprintln!(
            "coal peer skipped (set COAL_PYTHON); pairs written to {}",
            file.display()
        );
    }
}

criterion_group!(benches, kernel);
criterion_main!(benches);
