//! Collision checks against oracles that do not share their code: closed-form distances,
//! brute force over sampled surfaces, and a fine subdivision of motions.

use graspath::collision::{
    distance, ArmBodies, ArmInScene, Body, CollisionOptions, ObjectAlong, Scene, SelfPairs,
    WholeMotion,
};
use graspath::geometry::shape::Shape;
use graspath::robot::builtin::{baxter, Arm};
use graspath::robot::RobotSource;
use graspath::task::robot_link_shapes;
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

fn at(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}

#[test]
fn sphere_sphere_is_the_centre_distance_less_the_radii() {
    let a = Body::from_shape("a", &Shape::sphere(0.1).unwrap());
    let b = Body::from_shape("b", &Shape::sphere(0.25).unwrap());
    for (pa, pb) in [
        (
            at(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            at(1.0, 0.0, 0.0, 0.3, 0.2, 0.1),
        ),
        (
            at(0.3, -0.2, 0.5, 1.0, 0.0, 0.0),
            at(-0.4, 0.9, 0.1, 0.0, 2.0, 0.0),
        ),
    ] {
        let expected = (pa.translation.vector - pb.translation.vector).norm() - 0.35;
        assert!((distance(&a, &pa, &b, &pb) - expected).abs() < 1e-12);
    }
}

/// The closest distance between segments `p0 p1` and `q0 q1`, by a fine scan of one parameter
/// and the closed-form projection for the other.
fn segment_distance(p0: Vector3<f64>, p1: Vector3<f64>, q0: Vector3<f64>, q1: Vector3<f64>) -> f64 {
    let mut best = f64::INFINITY;
    let d = q1 - q0;
    for i in 0..=20_000 {
        let p = p0 + (p1 - p0) * (i as f64 / 20_000.0);
        let t = ((p - q0).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
        best = best.min((p - (q0 + d * t)).norm());
    }
    best
}

#[test]
fn capsule_capsule_is_the_segment_distance_less_the_radii() {
    let a = Body::from_shape("a", &Shape::capsule(0.03, 0.4).unwrap());
    let b = Body::from_shape("b", &Shape::capsule(0.05, 0.2).unwrap());
    let poses = [
        (
            at(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            at(0.3, 0.0, 0.0, 0.0, 0.0, 0.0),
        ),
        (
            at(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            at(0.2, 0.1, 0.5, std::f64::consts::FRAC_PI_2, 0.0, 0.0),
        ),
        (
            at(0.1, 0.2, 0.3, 0.4, 0.5, 0.6),
            at(-0.2, 0.1, 0.0, 1.0, -0.3, 2.0),
        ),
    ];
    for (pa, pb) in poses {
        let ends = |p: &Isometry3<f64>, half: f64| {
            (
                (p * Point3::new(0.0, 0.0, -half)).coords,
                (p * Point3::new(0.0, 0.0, half)).coords,
            )
        };
        let (p0, p1) = ends(&pa, 0.2);
        let (q0, q1) = ends(&pb, 0.1);
        let expected = (segment_distance(p0, p1, q0, q1) - 0.08).max(0.0);
        let got = distance(&a, &pa, &b, &pb);
        assert!((got - expected).abs() < 1e-6, "{got} vs {expected}");
    }
}

#[test]
fn box_point_is_the_clamped_distance() {
    // A sphere of radius r about a point: its distance to a box is the point's distance to
    // the box (clamp the point into the box in the box frame) less r.
    let size = [0.2, 0.4, 0.1];
    let b = Body::from_shape("box", &Shape::cuboid(size).unwrap());
    let s = Body::from_shape("ball", &Shape::sphere(0.01).unwrap());
    let pose = at(0.1, -0.2, 0.3, 0.3, -0.4, 0.9);
    for i in 0..100 {
        let t = i as f64 * 0.61;
        let p = Point3::new(0.5 * t.sin(), 0.5 * (0.7 * t).cos(), 0.5 * (1.3 * t).sin());
        let local = pose.inverse() * p;
        let clamped = Point3::new(
            local.x.clamp(-0.1, 0.1),
            local.y.clamp(-0.2, 0.2),
            local.z.clamp(-0.05, 0.05),
        );
        let expected = ((local - clamped).norm() - 0.01).max(0.0);
        let got = distance(&b, &pose, &s, &Isometry3::translation(p.x, p.y, p.z));
        assert!((got - expected).abs() < 1e-9, "{got} vs {expected}");
    }
}

/// Points on the surface of a capsule (radius r, segment length l along z) and a box.
fn capsule_surface(r: f64, l: f64, pose: &Isometry3<f64>) -> Vec<Point3<f64>> {
    let mut out = Vec::new();
    for i in 0..200 {
        let a = i as f64 / 200.0 * std::f64::consts::TAU;
        for j in 0..=60 {
            let z = -l / 2.0 + l * j as f64 / 60.0;
            out.push(pose * Point3::new(r * a.cos(), r * a.sin(), z));
        }
        for j in 0..=30 {
            let polar = j as f64 / 30.0 * std::f64::consts::FRAC_PI_2;
            for sign in [-1.0, 1.0] {
                out.push(
                    pose * Point3::new(
                        r * polar.cos() * a.cos(),
                        r * polar.cos() * a.sin(),
                        sign * (l / 2.0 + r * polar.sin()),
                    ),
                );
            }
        }
    }
    out
}

#[test]
fn capsule_box_matches_brute_force_over_sampled_surfaces() {
    let capsule = Body::from_shape("capsule", &Shape::capsule(0.04, 0.3).unwrap());
    let size = [0.3, 0.2, 0.1];
    let cuboid = Body::from_shape("box", &Shape::cuboid(size).unwrap());
    let box_pose = at(0.0, 0.0, 0.0, 0.2, 0.1, -0.3);
    for capsule_pose in [
        at(0.0, 0.0, 0.4, 0.0, 0.0, 0.0),
        at(0.35, 0.1, 0.0, 0.4, 1.2, 0.0),
        at(-0.1, 0.3, 0.2, 1.0, 0.3, 0.7),
    ] {
        // Brute force: the distance from each capsule surface point to the box (clamped in
        // the box frame), minimised.
        let expected = capsule_surface(0.04, 0.3, &capsule_pose)
            .iter()
            .map(|p| {
                let local = box_pose.inverse() * p;
                let h = [size[0] / 2.0, size[1] / 2.0, size[2] / 2.0];
                let clamped = Point3::new(
                    local.x.clamp(-h[0], h[0]),
                    local.y.clamp(-h[1], h[1]),
                    local.z.clamp(-h[2], h[2]),
                );
                (local - clamped).norm()
            })
            .fold(f64::INFINITY, f64::min);
        let got = distance(&capsule, &capsule_pose, &cuboid, &box_pose);
        // The sampled surface is within ~1 mm of the true one.
        assert!(
            got <= expected + 1e-9 && expected - got < 2e-3,
            "parry {got} vs sampled {expected}"
        );
    }
}

/// A motion of `arm` (base at the world origin, no object) checked against `scene`.
fn check_motion(
    arm: &ArmBodies,
    scene: &Scene,
    options: &CollisionOptions,
    motion: &[Vec<f64>],
) -> graspath::collision::MotionCheck {
    let identity = Isometry3::identity();
    ArmInScene {
        arm,
        world_from_base: &identity,
        scene,
        object: None,
        options,
    }
    .check(&WholeMotion {
        q: motion,
        object: ObjectAlong {
            path: 0..motion.len(),
            world_from_object_start: &identity,
            world_from_object_end: &identity,
            object_from_wrist: &identity,
        },
    })
}

fn baxter_left_bodies() -> ArmBodies {
    let model = RobotSource::builtin("baxter").load().unwrap();
    let shapes = robot_link_shapes(&model).unwrap();
    ArmBodies::new(&baxter(Arm::Left), &shapes, &[], &[], SelfPairs::None).unwrap()
}

/// The continuous check never misses a collision that a subdivision of the motion into steps
/// of at most 1 mm of any body's displacement finds (160 seeded random motions of Baxter's left
/// arm, each with a 1 cm ball placed near the motion so that many, not all, collide).
#[test]
fn the_continuous_check_never_misses_what_a_fine_subdivision_finds() {
    use rand::{rngs::StdRng, RngExt, SeedableRng};
    let arm = baxter_left_bodies();
    let chain = arm.chain().clone();
    let model = RobotSource::builtin("baxter").load().unwrap();
    let shapes = robot_link_shapes(&model).unwrap();
    let names = chain.link_names();
    let ball = Shape::sphere(0.005).unwrap();
    let ball_body = Body::from_shape("ball", &ball);
    let options = CollisionOptions {
        margin: 0.0,
        self_collision: false,
        ..CollisionOptions::default()
    };
    let mut rng = StdRng::seed_from_u64(2026);
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..160 {
        let n = chain.dof();
        let qa: Vec<f64> = (0..n)
            .map(|j| rng.random_range(chain.lower()[j]..chain.upper()[j]))
            .collect();
        let qb: Vec<f64> = qa
            .iter()
            .enumerate()
            .map(|(j, v)| {
                (v + rng.random_range(-0.5..0.5)).clamp(chain.lower()[j], chain.upper()[j])
            })
            .collect();
        // Near the origin of a moving link frame at a random instant of the motion.
        let instant: f64 = rng.random_range(0.0..1.0);
        let q_at: Vec<f64> = qa
            .iter()
            .zip(&qb)
            .map(|(a, b)| a + instant * (b - a))
            .collect();
        let frames_at = chain.link_frames(&q_at).unwrap();
        let link = rng.random_range(3..frames_at.len());
        let near = frames_at[link].translation.vector;
        let offset = [0; 3].map(|_| rng.random_range(-0.12..0.12));
        let ball_pose =
            Isometry3::translation(near.x + offset[0], near.y + offset[1], near.z + offset[2]);
        let scene = Scene::new().with_shape("ball", &ball, ball_pose);
        let check = check_motion(&arm, &scene, &options, &[qa.clone(), qb.clone()]);
        // Oracle: the moving links' shapes along the line, in steps in which no point of them
        // moves more than 1 mm (no Baxter link point is 2 m from a joint).
        let travel: f64 = qa.iter().zip(&qb).map(|(a, b)| (a - b).abs()).sum::<f64>() * 2.0;
        let steps = ((travel / 1e-3).ceil() as usize).max(1);
        let mut oracle_hit = false;
        'outer: for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let q: Vec<f64> = qa.iter().zip(&qb).map(|(a, b)| a + t * (b - a)).collect();
            let frames = chain.link_frames(&q).unwrap();
            for shape in &shapes {
                let Some(k) = names.iter().position(|n| *n == shape.link) else {
                    continue;
                };
                if chain.link_joint(k).is_none() {
                    continue; // fixed links are not checked against the scene
                }
                let frame: Isometry3<f64> = nalgebra::convert(frames[k]);
                let body = Body::from_shape("link", &shape.shape);
                if distance(
                    &body,
                    &(frame * shape.link_from_shape),
                    &ball_body,
                    &ball_pose,
                ) <= 0.0
                {
                    oracle_hit = true;
                    break 'outer;
                }
            }
        }
        if oracle_hit {
            hits += 1;
            assert!(
                check.hit.is_some(),
                "the subdivision found a collision the check missed"
            );
        } else {
            misses += 1;
        }
        if let Some(hit) = &check.hit {
            assert!(hit.distance < hit.required || hit.distance <= 0.0);
        }
    }
    assert!(
        hits >= 10 && misses >= 10,
        "{hits} colliding and {misses} free motions"
    );
}

#[test]
fn a_floor_below_the_motion_is_clear_by_its_gap_and_one_above_collides() {
    // A small shoulder motion over an infinite floor. Oracle: the lowest point of every moving
    // link shape at both samples (their tight bounding boxes).
    let arm = baxter_left_bodies();
    let chain = arm.chain().clone();
    let q0 = chain.mid_configuration();
    let mut q1 = q0.clone();
    q1[0] += 0.05;
    let frames = [
        chain.link_frames(&q0).unwrap(),
        chain.link_frames(&q1).unwrap(),
    ];

    let names = chain.link_names();
    let model = RobotSource::builtin("baxter").load().unwrap();
    let shapes = robot_link_shapes(&model).unwrap();
    let mut lowest: f64 = f64::INFINITY;
    for f in &frames {
        for shape in shapes.iter().filter(|s| names.contains(&s.link)) {
            let k = names.iter().position(|n| *n == shape.link).unwrap();
            if chain.link_joint(k).is_none() {
                // Fixed links (the pedestal) are not checked against the scene.
                continue;
            }
            let frame: Isometry3<f64> = nalgebra::convert(f[k]);
            let aabb = shape.shape.aabb_at(&(frame * shape.link_from_shape));
            lowest = lowest.min(aabb.min.z);
        }
    }
    let options = CollisionOptions {
        self_collision: false,
        ..CollisionOptions::default()
    };
    let motion = [q0, q1];
    let run = |floor: f64| {
        let scene = Scene::new().with_table(floor, None, None).unwrap();
        check_motion(&arm, &scene, &options, &motion)
    };
    // A floor 5 cm below the lowest point: clear, and the clearance is that gap (±0.1 mm).
    let clear = run(lowest - 0.05);
    assert!(clear.hit.is_none());
    let clearance = clear.clearance.unwrap();
    assert!(
        clearance <= 0.05 + 1e-9 && clearance > 0.05 - 1e-3,
        "{clearance}"
    );
    // A floor 5 mm below it breaks the 1 cm margin; one above it is a collision.
    assert!(run(lowest - 0.005).hit.is_some());
    let hit = run(lowest + 0.01).hit.unwrap();
    assert!(hit.bodies.iter().any(|b| b == "table"));
}

#[test]
fn a_urdf_link_with_a_mesh_collides_where_its_mesh_is() {
    // A planar two-link arm about z whose second link carries a 10 cm cube as an OBJ mesh
    // (a surface) centred 0.5 m out along x. Oracle: the geometry — turning the first joint
    // by θ puts the cube's centre at (0.3 + 0.5·cos θ', ...) where a ball is waiting.
    let dir = tempfile::tempdir().unwrap();
    let cube = "v -0.05 -0.05 -0.05\nv 0.05 -0.05 -0.05\nv 0.05 0.05 -0.05\nv -0.05 0.05 -0.05\n\
                v -0.05 -0.05 0.05\nv 0.05 -0.05 0.05\nv 0.05 0.05 0.05\nv -0.05 0.05 0.05\n\
                f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\n\
                f 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
    std::fs::write(dir.path().join("cube.obj"), cube).unwrap();
    let urdf = r#"<robot name="planar">
  <link name="base"/>
  <link name="one"/>
  <link name="two">
    <collision><origin xyz="0.5 0 0"/><geometry><mesh filename="cube.obj"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="one"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="one"/><child link="two"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>"#;
    let path = dir.path().join("planar.urdf");
    std::fs::write(&path, urdf).unwrap();
    let model = RobotSource::urdf(&path).load().unwrap();
    let chain = model.chain("base", "two", None).unwrap();
    let shapes = robot_link_shapes(&model).unwrap();
    assert_eq!(shapes.len(), 1);
    let arm = ArmBodies::new(&chain, &shapes, &[], &[], SelfPairs::None).unwrap();
    // At q = 0 the cube is centred at (0.8, 0, 0). A 1 cm ball at (0, 0.8, 0) is reached when
    // the first joint has turned by 90°, halfway along a motion from 0 to 180°: only the
    // continuous check sees it (both ends are far from the ball).
    let ball_pose = Isometry3::translation(0.0, 0.8, 0.0);
    let scene = Scene::new().with_shape("ball", &Shape::sphere(0.01).unwrap(), ball_pose);
    let options = CollisionOptions {
        self_collision: false,
        ..CollisionOptions::default()
    };
    let check = |motion: &[Vec<f64>]| check_motion(&arm, &scene, &options, motion);
    let sweep = [vec![0.0, 0.0], vec![3.0, 0.0]];
    let hit = check(&sweep).hit.expect("the cube sweeps through the ball");
    assert!(hit.between);
    assert_eq!(
        hit.bodies,
        ["link two".to_string(), "obstacle ball".to_string()]
    );
    // Folding the second joint back keeps the cube 0.3 − 0.5 = −0.2 m out: it passes at
    // 0.2 m from the axis, far from the ball.
    let folded = [vec![0.0, 3.0], vec![3.0, 3.0]];
    let clear = check(&folded);
    assert!(clear.hit.is_none());
    // Clearance at the samples: the cube's nearest corner to the ball (brute force over the
    // eight corners and the faces is not needed: at both samples the ball is far outside).
    assert!(clear.clearance.unwrap() > 0.3);
}

/// The check of the tool's commanded poses finds exactly the collisions of the bodies rigid
/// with the tool (Baxter's wrist, hand and gripper links: no moving joint after them) that
/// brute force finds at the same poses, and never one of a body that moves with the arm.
/// Oracle: each such body placed from the link frames at a configuration whose forward
/// kinematics gives the tool pose, against the scene by the exact distance.
#[test]
fn the_tool_pose_check_sees_exactly_the_bodies_rigid_with_the_tool() {
    use graspath::collision::ToolMotion;
    use rand::{rngs::StdRng, RngExt, SeedableRng};
    let arm = baxter_left_bodies();
    let chain = arm.chain().clone();
    let last_joint = chain.dof() - 1;
    let ball = Shape::sphere(0.02).unwrap();
    let ball_body = Body::from_shape("ball", &ball);
    let options = CollisionOptions {
        margin: 0.01,
        self_collision: false,
        ..CollisionOptions::default()
    };
    let identity = Isometry3::identity();
    let mut rng = StdRng::seed_from_u64(11);
    let (mut hits, mut clear) = (0, 0);
    for _ in 0..200 {
        let q: Vec<f64> = (0..chain.dof())
            .map(|j| rng.random_range(chain.lower()[j]..chain.upper()[j]))
            .collect();
        let frames = chain.link_frames(&q).unwrap();
        // A ball near a random link origin: sometimes a wrist or hand link, sometimes not.
        let near = frames[rng.random_range(3..frames.len())].translation.vector;
        let offset = [0; 3].map(|_| rng.random_range(-0.1..0.1));
        let ball_pose =
            Isometry3::translation(near.x + offset[0], near.y + offset[1], near.z + offset[2]);
        let scene = Scene::new().with_shape("ball", &ball, ball_pose);
        let base_from_tool: Isometry3<f64> = nalgebra::convert(chain.pose(&q).unwrap());
        let checker = ArmInScene {
            arm: &arm,
            world_from_base: &identity,
            scene: &scene,
            object: None,
            options: &options,
        };
        let hit = checker.check_tool_poses(&ToolMotion {
            base_from_tool: &[base_from_tool],
            object: ObjectAlong {
                path: 0..1,
                world_from_object_start: &identity,
                world_from_object_end: &identity,
                object_from_wrist: &identity,
            },
        });
        let colliding: Vec<String> = arm
            .bodies()
            .filter(|(link, _, _)| chain.link_joint(*link) == Some(last_joint))
            .filter(|(link, link_from_body, body)| {
                let world_from_body: Isometry3<f64> =
                    nalgebra::convert(frames[*link] * **link_from_body);
                distance(body, &world_from_body, &ball_body, &ball_pose) < options.margin
            })
            .map(|(_, _, body)| body.name().to_string())
            .collect();
        match &hit {
            Some(h) => {
                hits += 1;
                assert!(colliding.contains(&h.bodies[0]), "{h:?} vs {colliding:?}");
                assert_eq!(h.bodies[1], "obstacle ball");
            }
            None => {
                clear += 1;
                assert!(colliding.is_empty(), "missed {colliding:?}");
            }
        }
    }
    assert!(hits >= 10 && clear >= 10, "{hits} hits, {clear} clear");
}
