//! The built-in arms against oracles that do not share their code: forward kinematics by
//! plain 4 × 4 products of each manufacturer's published Denavit–Hartenberg table (typed here
//! from the datasheets, not from the library's tables), the geometric Jacobian from those DH
//! frames (`[zᵢ × (p − oᵢ); zᵢ]`), and invariants of the collision primitives.

use graspath::geometry::shape::Shape;
use graspath::robot::builtin::{BuiltinRobot, ARM_CHAIN, BUILTIN_NAMES};
use graspath::robot::{Chain, CollisionGeometry, JointKind, RobotSource};
use nalgebra::{Matrix4, Matrix6xX, Point3, Vector3};
use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

const TOL: f64 = 1e-9;

fn rot_z(t: f64) -> Matrix4<f64> {
    let (s, c) = t.sin_cos();
    Matrix4::new(
        c, -s, 0.0, 0.0, s, c, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    )
}

fn rot_x(t: f64) -> Matrix4<f64> {
    let (s, c) = t.sin_cos();
    Matrix4::new(
        1.0, 0.0, 0.0, 0.0, 0.0, c, -s, 0.0, 0.0, s, c, 0.0, 0.0, 0.0, 0.0, 1.0,
    )
}

fn trans(x: f64, y: f64, z: f64) -> Matrix4<f64> {
    Matrix4::new(
        1.0, 0.0, 0.0, x, 0.0, 1.0, 0.0, y, 0.0, 0.0, 1.0, z, 0.0, 0.0, 0.0, 1.0,
    )
}

/// A DH table: per joint `(d, a, α, θ offset)`; `modified` = Craig's convention.
struct Dh {
    rows: Vec<(f64, f64, f64, f64)>,
    modified: bool,
    /// A constant before the first row (base to DH frame 0).
    base: Matrix4<f64>,
    /// A constant after the last frame (to the tool frame).
    tool: Matrix4<f64>,
}

impl Dh {
    /// The tool pose and the frames `(origin, z)` of every joint axis, in the base frame.
    fn frames(&self, q: &[f64]) -> (Matrix4<f64>, Vec<Axis>) {
        let mut t = self.base;
        let mut axes = Vec::new();
        for (&(d, a, alpha, offset), &qi) in self.rows.iter().zip(q) {
            let theta = qi + offset;
            if self.modified {
                // Craig: Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i); joint i turns about the new z.
                t = t * rot_x(alpha) * trans(a, 0.0, 0.0);
                axes.push(axis_of(&t));
                t = t * rot_z(theta) * trans(0.0, 0.0, d);
            } else {
                // Standard: Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i); joint i turns about the old z.
                axes.push(axis_of(&t));
                t = t * rot_z(theta) * trans(0.0, 0.0, d) * trans(a, 0.0, 0.0) * rot_x(alpha);
            }
        }
        (t * self.tool, axes)
    }

    fn pose_and_jacobian(&self, q: &[f64]) -> (Matrix4<f64>, Matrix6xX<f64>) {
        let (pose, axes) = self.frames(q);
        let p = Vector3::new(pose[(0, 3)], pose[(1, 3)], pose[(2, 3)]);
        let mut j = Matrix6xX::zeros(q.len());
        for (k, (o, z)) in axes.iter().enumerate() {
            let v = z.cross(&(p - o));
            for r in 0..3 {
                j[(r, k)] = v[r];
                j[(r + 3, k)] = z[r];
            }
        }
        (pose, j)
    }
}

/// A joint axis: a point on it (its frame's origin) and its direction, base frame.
type Axis = (Vector3<f64>, Vector3<f64>);

fn axis_of(t: &Matrix4<f64>) -> Axis {
    (
        Vector3::new(t[(0, 3)], t[(1, 3)], t[(2, 3)]),
        Vector3::new(t[(0, 2)], t[(1, 2)], t[(2, 2)]),
    )
}

fn load(name: &str) -> Chain {
    RobotSource::builtin(name)
        .load()
        .unwrap()
        .named_chain(ARM_CHAIN, None)
        .unwrap()
}

/// Seeded configurations within the limits (continuous joints in [−π, π]).
fn configurations(chain: &Chain, count: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            (0..chain.dof())
                .map(|j| {
                    let (lo, hi) = (chain.lower()[j], chain.upper()[j]);
                    if lo.is_finite() {
                        rng.random_range(lo..hi)
                    } else {
                        rng.random_range(-PI..PI)
                    }
                })
                .collect()
        })
        .collect()
}

fn check_against_dh(name: &str, dh: &Dh) {
    let chain = load(name);
    assert_eq!(chain.dof(), dh.rows.len(), "{name}: joints");
    for q in configurations(&chain, 200, 17) {
        let (pose, jacobian) = chain.pose_and_jacobian(&q).unwrap();
        let (expected, expected_j) = dh.pose_and_jacobian(&q);
        let error = (pose.to_homogeneous() - expected).abs().max();
        assert!(error <= TOL, "{name} at {q:?}: pose differs by {error:e}");
        let error = (jacobian - expected_j).abs().max();
        assert!(
            error <= TOL,
            "{name} at {q:?}: Jacobian differs by {error:e}"
        );
    }
}

/// Universal Robots' DH tables ("DH parameters for calculations of kinematics and dynamics").
fn ur_dh(d1: f64, a2: f64, a3: f64, d4: f64, d5: f64, d6: f64) -> Dh {
    Dh {
        rows: vec![
            (d1, 0.0, FRAC_PI_2, 0.0),
            (0.0, a2, 0.0, 0.0),
            (0.0, a3, 0.0, 0.0),
            (d4, 0.0, FRAC_PI_2, 0.0),
            (d5, 0.0, -FRAC_PI_2, 0.0),
            (d6, 0.0, 0.0, 0.0),
        ],
        modified: false,
        base: Matrix4::identity(),
        tool: Matrix4::identity(),
    }
}

#[test]
fn universal_robots_equal_their_published_dh_tables() {
    check_against_dh(
        "ur5",
        &ur_dh(0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823),
    );
    check_against_dh(
        "ur10",
        &ur_dh(0.1273, -0.612, -0.5723, 0.163941, 0.1157, 0.0922),
    );
    check_against_dh(
        "ur5e",
        &ur_dh(0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996),
    );
    check_against_dh(
        "ur10e",
        &ur_dh(0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655),
    );
}

/// Franka's modified DH table, and the hand's TCP: −π/4 about z, then 0.1034 m along z.
fn franka_dh() -> Dh {
    Dh {
        rows: vec![
            (0.333, 0.0, 0.0, 0.0),
            (0.0, 0.0, -FRAC_PI_2, 0.0),
            (0.316, 0.0, FRAC_PI_2, 0.0),
            (0.0, 0.0825, FRAC_PI_2, 0.0),
            (0.384, -0.0825, -FRAC_PI_2, 0.0),
            (0.0, 0.0, FRAC_PI_2, 0.0),
            (0.0, 0.088, FRAC_PI_2, 0.0),
        ],
        modified: true,
        base: Matrix4::identity(),
        tool: trans(0.0, 0.0, 0.107) * rot_z(-FRAC_PI_4) * trans(0.0, 0.0, 0.1034),
    }
}

#[test]
fn franka_arms_equal_the_published_dh_table_with_the_hand_tcp() {
    check_against_dh("panda", &franka_dh());
    check_against_dh("fr3", &franka_dh());
    // The FR3 differs in its limits only.
    let (panda, fr3) = (load("panda"), load("fr3"));
    assert_ne!(panda.lower(), fr3.lower());
    assert_eq!(fr3.tip_link(), "fr3_hand_tcp");
}

/// KUKA LBR iiwa 14 R820: standard DH from KUKA's dimensions (0.36, 0.42, 0.4, 0.126 m).
#[test]
fn iiwa14_equals_the_dh_table_from_kukas_dimensions() {
    let dh = Dh {
        rows: vec![
            (0.36, 0.0, -FRAC_PI_2, 0.0),
            (0.0, 0.0, FRAC_PI_2, 0.0),
            (0.42, 0.0, FRAC_PI_2, 0.0),
            (0.0, 0.0, -FRAC_PI_2, 0.0),
            (0.4, 0.0, -FRAC_PI_2, 0.0),
            (0.0, 0.0, FRAC_PI_2, 0.0),
            (0.126, 0.0, 0.0, 0.0),
        ],
        modified: false,
        base: Matrix4::identity(),
        tool: Matrix4::identity(),
    };
    check_against_dh("iiwa14", &dh);
}

/// Kinova Gen3 7-DOF: the classical DH table of Kinova's user guide (base frame turned by π
/// about x, θᵢ = qᵢ + π for i ≥ 2), with the lengths at ros_kortex's precision.
#[test]
fn gen3_equals_kinovas_classical_dh_table() {
    let dh = Dh {
        rows: vec![
            (-(0.15643 + 0.12838), 0.0, FRAC_PI_2, 0.0),
            (-(0.005375 + 0.006375), 0.0, FRAC_PI_2, PI),
            (-(0.21038 + 0.21038), 0.0, FRAC_PI_2, PI),
            (-(0.006375 + 0.006375), 0.0, FRAC_PI_2, PI),
            (-(0.20843 + 0.10593), 0.0, FRAC_PI_2, PI),
            (-(0.00017505 + 0.00017505), 0.0, FRAC_PI_2, PI),
            (-(0.10593 + 0.061525), 0.0, PI, PI),
        ],
        modified: false,
        base: rot_x(PI),
        tool: Matrix4::identity(),
    };
    check_against_dh("gen3", &dh);
}

#[test]
fn every_builtin_robot_loads_with_its_chains_and_limits() {
    for name in BUILTIN_NAMES {
        let model = RobotSource::builtin(name).load().unwrap();
        assert_eq!(model.name(), name);
        assert!(model.is_builtin());
        let robot = BuiltinRobot::from_name(name).unwrap();
        assert_eq!(model.builtin(), Some(robot));
        for chain_name in model.chain_names() {
            let chain = model.named_chain(&chain_name, None).unwrap();
            let dof = chain.dof();
            assert!(dof == 6 || dof == 7, "{name}: {dof} joints");
            for j in 0..dof {
                assert!(chain.lower()[j] < chain.upper()[j], "{name} joint {j}");
                if chain.joint_kinds()[j] == JointKind::Continuous {
                    assert!(!chain.lower()[j].is_finite());
                }
            }
            // The whole chain again by its links, through the sub-chain route.
            let again = model
                .chain(chain.base_link(), chain.tip_link(), None)
                .unwrap();
            let q = chain.mid_configuration();
            assert_eq!(chain.pose(&q).unwrap(), again.pose(&q).unwrap());
        }
        // Every link named in the collision list is a link of the model.
        let links = model.link_names();
        for link in model.collisions().unwrap() {
            assert!(links.contains(&link.link), "{name}: {}", link.link);
            assert!(!link.shapes.is_empty());
        }
    }
    let err = RobotSource::builtin("ur5e")
        .load()
        .unwrap()
        .named_chain("left", None)
        .unwrap_err();
    assert!(err.to_string().contains("arm"), "{err}");
    let err = RobotSource::builtin("pand").load().unwrap_err();
    assert!(err.to_string().contains("did you mean: panda?"), "{err}");
}

/// The capsule or cylinder axis ends (or a sphere's centre) of a primitive, in its frame,
/// and its radius.
fn axis_ends(shape: &Shape) -> (Vec<Point3<f64>>, f64) {
    match shape {
        Shape::Capsule(c) => {
            let h = c.length() / 2.0;
            (
                vec![Point3::new(0.0, 0.0, -h), Point3::new(0.0, 0.0, h)],
                c.radius(),
            )
        }
        Shape::Cylinder(c) => {
            let h = c.length() / 2.0;
            (
                vec![Point3::new(0.0, 0.0, -h), Point3::new(0.0, 0.0, h)],
                0.0,
            )
        }
        Shape::Sphere(s) => (vec![Point3::origin()], s.radius()),
        other => panic!("unexpected primitive {}", other.kind()),
    }
}

/// The collision primitives cover each arm as one connected body: at seeded configurations,
/// the primitives of consecutive links overlap, the base and first link reach nowhere below
/// the mounting plane, and (for arms whose links follow the joint origins) every joint origin lies inside
/// a primitive.
#[test]
fn collision_primitives_form_a_connected_arm_above_the_base_plane() {
    for name in BUILTIN_NAMES.into_iter().filter(|n| *n != "baxter") {
        let model = RobotSource::builtin(name).load().unwrap();
        let chain = model.named_chain(ARM_CHAIN, None).unwrap();
        let collisions = model.collisions().unwrap();
        for q in configurations(&chain, 20, 5) {
            let frames = chain.link_frames(&q).unwrap();
            let placed: Vec<Vec<_>> = collisions
                .iter()
                .map(|lc| {
                    let k = chain.link_index(&lc.link).unwrap();
                    lc.shapes
                        .iter()
                        .map(|s| {
                            let CollisionGeometry::Shape(shape) = &s.geometry else {
                                panic!("{name}: built-in primitives only")
                            };
                            let world = nalgebra::Isometry3::from_parts(
                                frames[k].translation,
                                nalgebra::UnitQuaternion::from_rotation_matrix(&frames[k].rotation),
                            ) * s.link_from_collision;
                            (world, shape.clone())
                        })
                        .collect()
                })
                .collect();
            let inside =
                |p: &Point3<f64>, slack: f64, shapes: &[(nalgebra::Isometry3<f64>, Shape)]| {
                    shapes.iter().any(|(w, s)| {
                        s.signed_distance(&w.inverse_transform_point(p)) <= slack + 1e-9
                    })
                };
            for pair in placed.windows(2) {
                let touches = pair[0].iter().any(|(w, s)| {
                    let (ends, r) = axis_ends(s);
                    ends.iter().any(|e| inside(&(w * e), r, &pair[1]))
                });
                assert!(touches, "{name}: consecutive links apart at {q:?}");
            }
            // The base and the first link (turning about the base's vertical axis).
            for (w, s) in placed.iter().take(2).flatten() {
                let lowest = s.aabb_at(w).min.z;
                assert!(lowest >= -1e-9, "{name}: a primitive reaches z = {lowest}");
            }
            if !name.starts_with("ur") {
                let all: Vec<_> = placed.iter().flatten().cloned().collect();
                let origins = chain.joint_origins(&q).unwrap();
                // The last point is the tool frame, which may lie in free space (Panda's TCP).
                for p in &origins[..origins.len() - 1] {
                    assert!(inside(p, 0.0, &all), "{name}: joint origin {p} uncovered");
                }
            }
        }
    }
}

/// `robot: {builtin: NAME}` in a task file: the single chain is found by default, by
/// `arms: arm` and by `arms: all`, and a scene builds the arm's bodies from the primitives.
#[test]
fn task_files_name_single_arm_builtin_robots() {
    let dir = tempfile::tempdir().unwrap();
    // Gen3's continuous joints are sampled over one revolution by the collision set-up.
    let table = "scene: { table: { height: 0.0 } }\n";
    for (robot, arms, scene) in [
        ("panda", "", table),
        ("ur5e", "arms: arm\n", table),
        ("gen3", "arms: all\n", table),
        ("iiwa14", "", ""),
    ] {
        let text = format!(
            "robot: {{ builtin: {robot} }}\n{arms}\
             object:\n  pose: {{ xyz: [0.45, 0.0, 0.2] }}\n  shape: {{ box: {{ size: [0.05, 0.05, 0.1] }} }}\n\
             candidates:\n  family: {{ edge: {{ count: 3 }} }}\n\
             trajectory:\n  samples_per_step: 3\n  steps:\n    - {{ lift: 0.1 }}\n{scene}"
        );
        let path = dir.path().join(format!("{robot}.yaml"));
        std::fs::write(&path, text).unwrap();
        let task = graspath::task::Task::load(&path).unwrap_or_else(|e| panic!("{robot}: {e}"));
        assert_eq!(task.robot_name(), robot);
        assert_eq!(task.arms().len(), 1);
        assert_eq!(task.arms()[0].name, ARM_CHAIN);
        assert_eq!(
            task.arms()[0].bodies.is_some(),
            !scene.is_empty(),
            "{robot}"
        );
    }
}

/// The makers' published total weights (kg), base included; Baxter's arms have none of their
/// own and are checked against a range.
fn published_weight(robot: BuiltinRobot) -> Option<f64> {
    match robot {
        BuiltinRobot::Panda => Some(18.0),
        BuiltinRobot::Fr3 => Some(17.8),
        BuiltinRobot::Ur5 => Some(18.4),
        BuiltinRobot::Ur10 => Some(28.9),
        BuiltinRobot::Ur5e => Some(20.6),
        BuiltinRobot::Ur10e => Some(33.5),
        BuiltinRobot::Iiwa14 => Some(29.9),
        BuiltinRobot::Xarm7 => Some(13.7),
        BuiltinRobot::Gen3 => Some(8.2),
        BuiltinRobot::Baxter => None,
    }
}

/// Every built-in arm has a dynamics model and a velocity and effort limit on every joint;
/// its moving links weigh between 60 % and 100 % of the maker's total weight (the rest is the
/// base); and its gravity torques over 200 seeded configurations stay within its effort
/// limits: the arm holds itself everywhere. Baxter's `s1` is the exception, and the test
/// checks that it is one: it needs up to 1.12 times its 50 N·m, which the arm's shoulder
/// spring provides and `baxter_description` (hence the built-in model) does not model.
#[test]
fn every_builtin_arm_has_dynamics_and_limits() {
    for robot in BuiltinRobot::ALL {
        let model = RobotSource::builtin(robot.name()).load().unwrap();
        for chain_name in robot.chain_names() {
            let chain = model.named_chain(chain_name, None).unwrap();
            let what = format!("{} {chain_name}", robot.name());
            let dynamics = chain.dynamics().unwrap_or_else(|e| panic!("{what}: {e}"));
            for (j, limits) in chain.motion_limits().iter().enumerate() {
                let (v, e) = (limits.velocity.unwrap(), limits.effort.unwrap());
                assert!(
                    v > 0.0 && v < 10.0 && e > 0.0 && e < 1000.0,
                    "{what} joint {j}"
                );
            }
            let moving = dynamics.moving_mass();
            match published_weight(robot) {
                Some(total) => assert!(
                    moving > 0.6 * total && moving < total,
                    "{what}: moving mass {moving} kg of {total} kg"
                ),
                None => assert!(moving > 15.0 && moving < 25.0, "{what}: {moving} kg"),
            }
            let mut load = vec![0.0f64; chain.dof()];
            for q in configurations(&chain, 200, 5) {
                let g = dynamics.gravity_torques(&q).unwrap();
                for (j, (t, limits)) in g.iter().zip(chain.motion_limits()).enumerate() {
                    load[j] = load[j].max(t.abs() / limits.effort.unwrap());
                }
            }
            eprintln!("{what}: moving mass {moving:.2} kg, largest gravity load / effort limit per joint {load:.2?}");
            for (j, l) in load.iter().enumerate() {
                let spring = robot == BuiltinRobot::Baxter && j == 1;
                assert_eq!(
                    *l > 1.0,
                    spring,
                    "{what}: joint {j} load {l:.2} of its limit"
                );
            }
        }
    }
}

/// The Python stub's `Robot.builtin(name: Literal[...])` lists exactly the built-in names, in
/// their order, so type checkers accept every built-in robot and no other.
#[test]
fn the_python_stub_lists_the_built_in_names() {
    let stub = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../graspath-py/python/graspath/_graspath.pyi");
    let text = std::fs::read_to_string(&stub).unwrap();
    let after = text
        .split_once("def builtin(")
        .expect("the stub declares Robot.builtin")
        .1;
    let literal = after
        .split_once("name: Literal[")
        .expect("Robot.builtin's name is a Literal")
        .1
        .split_once(']')
        .unwrap()
        .0;
    let names: Vec<&str> = literal
        .split(',')
        .map(|n| n.trim().trim_matches('"'))
        .filter(|n| !n.is_empty())
        .collect();
    assert_eq!(names, BUILTIN_NAMES);
}
