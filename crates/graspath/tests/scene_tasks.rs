//! Tasks in a scene, as a new user writes them: the object on a table, under it, too wide for
//! the gripper; and the errors a scene section can give.

use graspath::failure::{FailureReason, Phase};
use graspath::select::select;
use graspath::task::Task;
use std::path::PathBuf;

/// The paper's pick-and-place (Baxter's left arm, the cuboid's top edge) with `extra` YAML
/// appended and the object at height `z` (its centre, m).
fn task_file(dir: &tempfile::TempDir, z: f64, shape: &str, family: &str, extra: &str) -> PathBuf {
    let text = format!(
        "robot: {{ builtin: baxter }}\n\
         arms: left\n\
         object:\n  pose: {{ xyz: [0.75, 0.0, {z}] }}\n  shape: {shape}\n\
         candidates:\n  family: {family}\n\
         trajectory:\n  samples_per_step: 5\n  steps:\n    - {{ lift: 0.2 }}\n    - {{ move: [0.0, 0.3, 0.0] }}\n    - {{ place: 0.2 }}\n\
         {extra}"
    );
    let path = dir.path().join("task.yaml");
    std::fs::write(&path, text).unwrap();
    path
}

const CUBOID: &str = "{ box: { size: [0.06, 0.40, 0.10] } }";
const EDGE: &str = "{ edge: { count: 11 } }";

#[test]
fn an_object_standing_on_the_table_can_be_picked_and_the_table_is_kept_clear() {
    let dir = tempfile::tempdir().unwrap();
    // The box's bottom (z = −0.15) rests on the table top.
    let path = task_file(
        &dir,
        -0.10,
        CUBOID,
        EDGE,
        "scene: { table: { height: -0.15 } }\n\
         gripper: { builtin: baxter }\n\
         approach: { distance: 0.10, samples: 5 }\n\
         retreat: { distance: 0.10, samples: 5 }\n",
    );
    let task = Task::load(&path).unwrap();
    let selection = select(&task, &|| {}).unwrap();
    let arm = &selection.arms[0];
    assert!(
        arm.feasible_count() > 0,
        "{:?}",
        arm.scores.iter().map(|s| &s.failure).collect::<Vec<_>>()
    );
    for s in arm.scores.iter().filter(|s| s.feasible()) {
        // The approach and retreat were solved, and the robot keeps the margin.
        assert_eq!(s.approach.len(), 5);
        assert_eq!(s.retreat.len(), 5);
        let clearance = s.clearance.expect("a scene gives a clearance");
        assert!(clearance >= 0.01, "clearance {clearance}");
    }
    // The object resting on the table is not a collision at pick or place.
    for s in &arm.scores {
        if let Some(f) = &s.failure {
            if let Some(bodies) = &f.bodies {
                assert!(
                    !(bodies.contains(&"object".to_string())
                        && bodies.contains(&"table".to_string())),
                    "{f}"
                );
            }
        }
    }
}

#[test]
fn a_box_inside_the_table_collides_with_it_for_every_candidate() {
    let dir = tempfile::tempdir().unwrap();
    // The box where the arm reaches it in empty space, the table top 35 cm above its centre.
    let free = select(
        &Task::load(&task_file(&dir, -0.10, CUBOID, EDGE, "")).unwrap(),
        &|| {},
    )
    .unwrap();
    let reachable: Vec<usize> = (0..free.arms[0].scores.len())
        .filter(|&i| free.arms[0].scores[i].feasible())
        .collect();
    assert!(!reachable.is_empty());
    let path = task_file(
        &dir,
        -0.10,
        CUBOID,
        EDGE,
        "scene: { table: { height: 0.25 } }\n",
    );
    let selection = select(&Task::load(&path).unwrap(), &|| {}).unwrap();
    let arm = &selection.arms[0];
    assert_eq!(arm.feasible_count(), 0);
    for i in reachable {
        let f = arm.scores[i].failure.as_ref().unwrap();
        assert_eq!(f.reason, FailureReason::Collision, "{f}");
        let bodies = f.bodies.as_ref().unwrap();
        assert!(bodies.iter().any(|b| b == "table"), "{f}");
    }
}

#[test]
fn a_box_wider_than_the_opening_is_rejected_for_gripper_width() {
    let dir = tempfile::tempdir().unwrap();
    let path = task_file(
        &dir,
        -0.10,
        "{ box: { size: [0.5, 0.5, 0.1] } }",
        "{ faces: { count: 20 } }",
        "gripper: { opening: 0.08 }\n",
    );
    let task = Task::load(&path).unwrap();
    let selection = select(&task, &|| {}).unwrap();
    for s in &selection.arms[0].scores {
        let f = s.failure.as_ref().expect("no grasp fits");
        assert_eq!(f.reason, FailureReason::GripperWidth, "{f}");
        assert_eq!((f.phase, f.sample), (Phase::Path, 0));
    }
    // The same box 6 cm wide across the fingers fits.
    let path = task_file(&dir, -0.10, CUBOID, EDGE, "gripper: { opening: 0.08 }\n");
    let selection = select(&Task::load(&path).unwrap(), &|| {}).unwrap();
    assert!(selection.arms[0].scores.iter().all(|s| s
        .failure
        .as_ref()
        .is_none_or(|f| f.reason != FailureReason::GripperWidth)));
}

#[test]
fn srdf_disabled_pairs_are_not_checked() {
    let dir = tempfile::tempdir().unwrap();
    let pair = ("left_upper_shoulder", "left_wrist");
    std::fs::write(
        dir.path().join("baxter.srdf"),
        format!(
            "<robot name=\"baxter\">\n  <disable_collisions link1=\"{}\" link2=\"{}\" reason=\"Never\"/>\n</robot>\n",
            pair.0, pair.1
        ),
    )
    .unwrap();
    let names = |extra: &str| {
        let task = Task::load(&task_file(&dir, -0.10, CUBOID, EDGE, extra)).unwrap();
        task.arms()[0].bodies.as_ref().unwrap().self_pair_names()
    };
    let touches = |pairs: &[(String, String)]| {
        pairs.iter().any(|(a, b)| {
            let (a, b) = (a.trim_start_matches("link "), b.trim_start_matches("link "));
            (a, b) == pair || (b, a) == pair
        })
    };
    assert!(touches(&names(
        "scene: {}\ncollision: { self_pairs: all }\n"
    )));
    assert!(!touches(&names(
        "scene: {}\ncollision: { self_pairs: all, srdf: baxter.srdf }\n"
    )));
}

#[test]
fn scene_sections_that_cannot_be_used_name_their_field() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("broken.stl"), b"solid nothing\nendsolid\n").unwrap();
    std::fs::write(dir.path().join("hand.urdf"), hand_urdf(FINGER, PALM, 0.04)).unwrap();
    let cases = [
        (
            "scene: { obstacles: [ { name: c, cone: { radius: 0.1 } } ] }\n",
            "cone",
        ),
        (
            "scene: { obstacles: [ { name: m, mesh: broken.stl } ] }\n",
            "scene.obstacles[0].mesh",
        ),
        (
            "scene: { obstacles: [ { name: m, mesh: missing.stl } ] }\n",
            "scene.obstacles[0].mesh",
        ),
        (
            "scene: { obstacles: [ { name: two, sphere: { radius: 0.1 }, capsule: { radius: 0.1, length: 0.2 } } ] }\n",
            "scene.obstacles[0]",
        ),
        (
            "scene: {}\ncollision: { disable: [[left_wrist, no_such_link]] }\n",
            "collision.disable[0]",
        ),
        (
            "scene: { table: { height: 0.0, size: [0.0, 1.0] } }\n",
            "table.size[0]",
        ),
        ("approach: { distance: -0.1 }\n", "approach.distance"),
        (
            "scene: {}\ncollision: { resolution: 1e-12 }\n",
            "collision.resolution",
        ),
        ("gripper: { opening: 0 }\n", "gripper.opening"),
        (
            "gripper: { urdf: hand.urdf, root: no_such_link }\n",
            "gripper.root",
        ),
        ("gripper: { urdf: hand.urdf }\n", "gripper.root"),
        (
            "gripper: { urdf: missing.urdf, root: hand }\n",
            "gripper.urdf",
        ),
        (
            "gripper: { urdf: hand.urdf, root: hand, fingers: [thumb] }\n",
            "gripper.fingers",
        ),
        (
            "gripper: { urdf: hand.urdf, root: hand, open: { left_slide: 0.5 } }\n",
            "gripper.open.left_slide",
        ),
        (
            "gripper: { urdf: hand.urdf, root: hand, open: { elbow: 0.0 } }\n",
            "gripper.open.elbow",
        ),
        (
            "gripper: { urdf: hand.urdf, root: hand, opening: 0.08 }\n",
            "gripper.opening",
        ),
        ("gripper: { opening: 0.08, fingers: [a] }\n", "gripper.fingers"),
        ("collision: { margin: 0.01 }\n", "collision"),
        (
            "scene: { obstacles: [ { name: box, sphere: { radius: 0.1 }, pose: { xyz: [2, 0, 0] } }, { name: box, sphere: { radius: 0.1 }, pose: { xyz: [3, 0, 0] } } ] }\n",
            "scene.obstacles[1].name': 'box' is also the name of scene.obstacles[0]",
        ),
        (
            "scene: {}\ncollision: { srdf: bad.srdf }\n",
            "no_such_link",
        ),
        (
            "scene: {}\ncollision: { srdf: missing.srdf }\n",
            "collision.srdf",
        ),
    ];
    std::fs::write(
        dir.path().join("bad.srdf"),
        "<robot name=\"baxter\">\n  <disable_collisions link1=\"left_wrist\" link2=\"no_such_link\"/>\n</robot>\n",
    )
    .unwrap();
    for (extra, field) in cases {
        let path = task_file(&dir, -0.10, CUBOID, EDGE, extra);
        let error = graspath::Chain(&Task::load(&path).expect_err(extra)).to_string();
        assert!(error.contains(field), "{extra}: {error}");
        assert!(error.contains("task.yaml"), "{extra}: {error}");
    }
}

/// The moving bodies of both arms at one configuration each, in the world (independent of the
/// checker: link frames and the robot's shapes, placed by hand).
fn moving_bodies(
    task: &Task,
    arm: usize,
    q: &[f64],
) -> Vec<(graspath::collision::Body, nalgebra::Isometry3<f64>)> {
    let setup = &task.arms()[arm];
    let chain = &setup.chain;
    let frames = chain.link_frames(q).unwrap();
    let model = graspath::robot::RobotSource::builtin("baxter")
        .load()
        .unwrap();
    let shapes = graspath::task::robot_link_shapes(&model).unwrap();
    let names = chain.link_names();
    shapes
        .iter()
        .filter_map(|s| {
            let k = names.iter().position(|n| *n == s.link)?;
            chain.link_joint(k)?;
            let frame: nalgebra::Isometry3<f64> = nalgebra::convert(frames[k]);
            Some((
                graspath::collision::Body::from_shape(s.link.clone(), &s.shape),
                setup.world_from_base * frame * s.link_from_shape,
            ))
        })
        .collect()
}

#[test]
fn no_selected_two_arm_pair_collides_and_crossing_pairs_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    // Grasps may be as close as the task likes: only the arm-against-arm check keeps the two
    // hands apart.
    let text = "robot: { builtin: baxter }\n\
                arms: both\n\
                object:\n  pose: { xyz: [0.75, 0.0, -0.10] }\n  shape: { box: { size: [0.06, 0.40, 0.10] } }\n\
                candidates:\n  family: { edge: { count: 11 } }\n\
                trajectory:\n  samples_per_step: 4\n  steps:\n    - { lift: 0.2 }\n    - { move: [0.0, 0.3, 0.0] }\n\
                selection: { pairs: 40, min_separation: 0.0 }\n\
                scene: { table: { height: -0.15 } }\n";
    let path = dir.path().join("both.yaml");
    std::fs::write(&path, text).unwrap();
    let task = Task::load(&path).unwrap();
    let selection = select(&task, &|| {}).unwrap();
    assert!(!selection.pairs.is_empty());
    assert!(
        selection.colliding_pairs > 0,
        "with no separation some better pairs put both hands in one place"
    );
    let score_of = |arm: usize, id: usize| {
        selection.arms[arm]
            .scores
            .iter()
            .find(|s| s.candidate.id == id)
            .unwrap()
    };
    // Oracle: every kept pair, at every sample and four points between samples, keeps every
    // moving body of one arm off every moving body of the other.
    for pair in &selection.pairs {
        let (a, b) = (score_of(0, pair.first.id), score_of(1, pair.second.id));
        let qa = &a.joint_trajectory;
        let qb = &b.joint_trajectory;
        for s in 0..qa.len() {
            for t in [0.0, 0.2, 0.4, 0.6, 0.8] {
                if s + 1 == qa.len() && t > 0.0 {
                    continue;
                }
                let lerp = |q: &[Vec<f64>]| -> Vec<f64> {
                    let next = &q[(s + 1).min(q.len() - 1)];
                    q[s].iter()
                        .zip(next)
                        .map(|(x, y)| x + t * (y - x))
                        .collect()
                };
                let bodies_a = moving_bodies(&task, 0, &lerp(qa));
                let bodies_b = moving_bodies(&task, 1, &lerp(qb));
                for (x, px) in &bodies_a {
                    for (y, py) in &bodies_b {
                        let d = graspath::collision::distance(x, px, y, py);
                        assert!(
                            d > 0.0,
                            "pair {} × {}: {} touches {}",
                            pair.first.id,
                            pair.second.id,
                            x.name(),
                            y.name()
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn generated_grasps_that_put_the_hand_into_the_table_are_dropped_before_the_best_are_kept() {
    let dir = tempfile::tempdir().unwrap();
    let examples = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/grasp");
    let model = graspath::grasp::model::train_file(&examples.join("demo_box.json")).unwrap();
    let model_path = dir.path().join("model.json");
    model.write(&model_path).unwrap();
    let cloud = examples.join("cylinder.json");
    // The table cuts the 12 cm cylinder at its middle: grasps from below or low on the side
    // put the hand into it.
    let task = |scene: &str| {
        let text = format!(
            "robot: {{ builtin: baxter }}\n\
             arms: left\n\
             object: {{ pose: {{ xyz: [0.70, 0.25, -0.10] }} }}\n\
             candidates:\n  generate: {{ model: {}, cloud: {}, seed: 3, initial_grasps: 2000, steps: 100, query_kernels: 1500, max_candidates: 15 }}\n\
             trajectory:\n  samples_per_step: 2\n  steps: [ {{ lift: 0.2 }} ]\n{scene}",
            model_path.display(),
            cloud.display()
        );
        let path = dir.path().join("generate.yaml");
        std::fs::write(&path, text).unwrap();
        Task::load(&path).unwrap()
    };
    let table = -0.10;
    // Oracle: the lowest point of every hand shape (its tight bounding box in the world, from
    // the shapes' support functions) at the grasp.
    let world_from_object = nalgebra::Isometry3::translation(0.70, 0.25, -0.10);
    let lowest = |c: &graspath::grasp::Candidate| {
        let links = model.hand.link_poses(&c.hand_joints);
        model
            .hand
            .links
            .iter()
            .zip(&links)
            .flat_map(|(link, wrist_from_link)| {
                link.shapes.iter().map(move |s| {
                    s.shape
                        .aabb_at(
                            &(world_from_object
                                * c.object_from_wrist
                                * wrist_from_link
                                * s.link_from_shape),
                        )
                        .min
                        .z
                })
            })
            .fold(f64::INFINITY, f64::min)
    };
    let free = task("");
    assert!(
        free.candidates()
            .held()
            .expect("held candidates")
            .iter()
            .any(|c| lowest(c) < table),
        "without a scene some of the best grasps reach below the table top"
    );
    let in_scene = task(&format!("scene: {{ table: {{ height: {table} }} }}\n"));
    // Every clear grasp among the best 15 without a scene is still kept (the next best fill
    // the places of the dropped ones, as far as the model generated any).
    for c in free
        .candidates()
        .held()
        .expect("held candidates")
        .iter()
        .filter(|c| lowest(c) > table)
    {
        assert!(
            in_scene
                .candidates()
                .held()
                .expect("held candidates")
                .iter()
                .any(|k| k.object_from_wrist == c.object_from_wrist),
            "{} was clear but not kept",
            c.label
        );
    }
    assert!(in_scene.candidate_count() <= 15);
    for c in in_scene.candidates().held().expect("held candidates") {
        assert!(
            lowest(c) > table - 1e-9,
            "{}: lowest {}",
            c.label,
            lowest(c)
        );
    }
}

#[test]
fn the_scene_examples_select_grasps_that_keep_their_margins() {
    let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scene");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    files.sort();
    assert!(files.len() >= 4);
    for file in files {
        let task = Task::load(&file).unwrap();
        let collisions = task.collisions().expect("a scene example has a scene");
        let required = collisions
            .options
            .margin
            .max(task.selection().min_clearance.unwrap_or(0.0));
        let selection = select(&task, &|| {}).unwrap();
        for arm in &selection.arms {
            let best = arm
                .best()
                .unwrap_or_else(|| panic!("{}: nothing selected", file.display()));
            let clearance = arm.scores[best].clearance.unwrap();
            assert!(
                clearance >= required,
                "{}: clearance {clearance}",
                file.display()
            );
            for s in arm.scores.iter().filter(|s| s.feasible()) {
                assert!(s.clearance.unwrap() >= collisions.options.margin);
            }
        }
        if task.arms().len() == 2 {
            assert!(!selection.pairs.is_empty(), "{}", file.display());
        }
    }
}

/// Finger `[length, width, thickness]` and palm `[x, y, z]` of the URDF hand below (m).
const FINGER: [f64; 3] = [0.09, 0.02, 0.01];
const PALM: [f64; 3] = [0.06, 0.11, 0.04];

/// A parallel-jaw hand written as a URDF: a palm box on the root link `hand` behind the
/// finger roots, and two box fingers on prismatic joints sliding along `±y` up to `travel`
/// (m), their inner faces at the joint value from the tool axis.
fn hand_urdf(finger: [f64; 3], palm: [f64; 3], travel: f64) -> String {
    let [length, width, thickness] = finger;
    let box_ = |size: [f64; 3]| format!("<box size=\"{} {} {}\"/>", size[0], size[1], size[2]);
    let finger_link = |name: &str, side: f64| {
        format!(
            "<link name=\"{name}\"><collision><origin xyz=\"0 {} {}\"/><geometry>{}</geometry></collision></link>",
            side * thickness / 2.0,
            -length / 2.0,
            box_([width, thickness, length])
        )
    };
    let slide = |name: &str, child: &str, side: f64| {
        format!(
            "<joint name=\"{name}\" type=\"prismatic\"><parent link=\"hand\"/><child link=\"{child}\"/>\
             <axis xyz=\"0 {side} 0\"/><limit lower=\"0\" upper=\"{travel}\" effort=\"1\" velocity=\"1\"/></joint>"
        )
    };
    format!(
        "<robot name=\"two_jaw\">\
         <link name=\"hand\"><collision><origin xyz=\"0 0 {}\"/><geometry>{}</geometry></collision></link>\
         {}{}{}{}</robot>",
        -length - palm[2] / 2.0,
        box_(palm),
        finger_link("left_finger", 1.0),
        finger_link("right_finger", -1.0),
        slide("left_slide", "left_finger", 1.0),
        slide("right_slide", "right_finger", -1.0),
    )
}

/// A hand described in a URDF is the gripper its shapes describe. Oracle: the same fingers
/// and palm given by their sizes (`finger`, `palm`, `opening`): the same opening (the fingers'
/// distance), the same bodies in the tool frame, and the same selection, candidate by
/// candidate, in a scene where some grasps collide and some are too wide.
#[test]
fn a_urdf_hand_is_the_gripper_its_shapes_describe() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("hand.urdf"), hand_urdf(FINGER, PALM, 0.035)).unwrap();
    let world = "scene: { table: { height: -0.15 }, obstacles: [ { name: post, cylinder: { radius: 0.03, length: 0.5 }, pose: { xyz: [0.62, 0.1, 0.0] } } ] }\n\
                 approach: { distance: 0.10, samples: 3 }\n";
    let sized = format!(
        "{world}gripper: {{ opening: 0.07, finger: [{}, {}, {}], palm: [{}, {}, {}] }}\n",
        FINGER[0], FINGER[1], FINGER[2], PALM[0], PALM[1], PALM[2]
    );
    let from_urdf = format!("{world}gripper: {{ urdf: hand.urdf, root: hand }}\n");
    let shape = "{ box: { size: [0.06, 0.06, 0.10] } }";
    let family = "{ faces: { count: 40 } }";
    let a = Task::load(&task_file(&dir, -0.10, shape, family, &sized)).unwrap();
    let b = Task::load(&task_file(&dir, -0.10, shape, family, &from_urdf)).unwrap();
    let (ga, gb) = (a.gripper().unwrap(), b.gripper().unwrap());
    assert!((gb.opening - 0.07).abs() < 1e-9, "opening {}", gb.opening);
    let (mut ha, mut hb) = (ga.hand_shapes(), gb.hand_shapes());
    assert_eq!(ha.len(), hb.len());
    let key = |x: &(
        String,
        nalgebra::Isometry3<f64>,
        graspath::geometry::shape::Shape,
    )| {
        let t = x.1.translation.vector;
        (t.y * 1e6).round() as i64 * 1_000_000 + (t.z * 1e6).round() as i64
    };
    ha.sort_by_key(key);
    hb.sort_by_key(key);
    for (x, y) in ha.iter().zip(&hb) {
        assert!((x.1.to_homogeneous() - y.1.to_homogeneous()).abs().max() < 1e-12);
        assert_eq!(x.2, y.2);
    }
    let (sa, sb) = (select(&a, &|| {}).unwrap(), select(&b, &|| {}).unwrap());
    let reasons = |s: &graspath::select::Selection| -> Vec<Option<FailureReason>> {
        s.arms[0]
            .scores
            .iter()
            .map(|c| c.failure.as_ref().map(|f| f.reason))
            .collect()
    };
    assert_eq!(reasons(&sa), reasons(&sb));
    let found = reasons(&sa);
    assert!(found.contains(&None), "{found:?}");
    assert!(found.contains(&Some(FailureReason::Collision)), "{found:?}");
    for (x, y) in sa.arms[0].scores.iter().zip(&sb.arms[0].scores) {
        assert_eq!(x.norms, y.norms);
        assert_eq!(x.clearance, y.clearance);
    }
}

/// An object standing on an obstacle (a shelf board) rests on it as on the table: the same
/// candidates are feasible with the same scores when the table's top is replaced by a board at
/// the same height (oracle: the task on the table), and without the resting rule every grasp
/// would collide with the board at the pick.
#[test]
fn an_object_rests_on_the_obstacle_it_stands_on() {
    let dir = tempfile::tempdir().unwrap();
    let common = "gripper: { builtin: baxter }\napproach: { distance: 0.10, samples: 3 }\n";
    let on_table = task_file(
        &dir,
        -0.10,
        CUBOID,
        EDGE,
        &format!("scene: {{ table: {{ height: -0.15 }} }}\n{common}"),
    );
    let a = select(&Task::load(&on_table).unwrap(), &|| {}).unwrap();
    let on_board = task_file(
        &dir,
        -0.10,
        CUBOID,
        EDGE,
        &format!(
            "scene: {{ obstacles: [ {{ name: board, box: {{ size: [3.0, 3.0, 0.2] }}, pose: {{ xyz: [0.75, 0.0, -0.25] }} }} ] }}\n{common}"
        ),
    );
    let b = select(&Task::load(&on_board).unwrap(), &|| {}).unwrap();
    let (sa, sb) = (&a.arms[0].scores, &b.arms[0].scores);
    assert!(sa.iter().any(graspath::select::CandidateScore::feasible));
    for (x, y) in sa.iter().zip(sb) {
        assert_eq!(
            x.feasible(),
            y.feasible(),
            "{:?} vs {:?}",
            x.failure,
            y.failure
        );
        assert_eq!(x.norms, y.norms);
    }
}

/// A scene task on an MJCF robot whose chain has links without collision geometry (the tool
/// frame `panda_hand_tcp`, `panda_link8`, ... — nearly every real tool-frame chain): the
/// bodies that ride with the object are those of the tip link's rigid group, whatever the
/// number of bodies (this indexed the bodies by the tip's link index and panicked).
#[test]
fn a_scene_task_on_a_robot_with_bare_links_keeps_its_margins() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let example = std::fs::read_to_string(root.join("../../examples/scene/panda_shelf_pick.yaml"))
        .unwrap()
        .replace(
            "robot: { builtin: panda }",
            &format!(
                "robot: {{ mjcf: {}, chains: {{ arm: {{ base: panda_link0, tip: panda_hand_tcp }} }} }}",
                root.join("tests/data/mjcf/panda.xml").display()
            ),
        )
        .replace("count: 200", "count: 40");
    assert!(example.contains("mjcf"));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("task.yaml");
    std::fs::write(&path, example).unwrap();
    let task = Task::load(&path).unwrap();
    let margin = task.collisions().unwrap().options.margin;
    let selection = select(&task, &|| {}).unwrap();
    let scores = &selection.arms[0].scores;
    assert_eq!(scores.len(), 40);
    let feasible = scores.iter().filter(|s| s.feasible()).count();
    assert!(feasible > 0, "nothing feasible to check");
    for s in scores.iter().filter(|s| s.feasible()) {
        assert!(s.clearance.unwrap() >= margin, "{:?}", s.clearance);
    }
}

/// A collision's detail numbers its samples as the failure's `phase` and `sample` do (0 =
/// the phase's first), on the shipped scene examples (collisions on the approach, the
/// object's path and between samples).
#[test]
fn a_collision_detail_names_the_failure_s_own_phase_and_sample() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/scene");
    let mut seen = 0;
    for name in [
        "pick_and_place_left_cluttered.yaml",
        "panda_shelf_pick.yaml",
    ] {
        let selection = select(&Task::load(&root.join(name)).unwrap(), &|| {}).unwrap();
        for score in &selection.arms[0].scores {
            let Some(f) = score.failure.as_ref() else {
                continue;
            };
            if f.reason != FailureReason::Collision {
                continue;
            }
            seen += 1;
            let (phase, k) = (f.phase.as_str(), f.sample);
            let at = format!("at {phase} sample {k};");
            let between = format!("between {phase} samples {k} and {};", k + 1);
            let across = format!("between {phase} sample {k} and ");
            assert!(
                f.detail.contains(&at) || f.detail.contains(&between) || f.detail.contains(&across),
                "{name}: {f}"
            );
        }
    }
    assert!(seen > 0, "no collision to check");
}
