//! Stock grippers on every built-in arm: each arm standing on a table at its mounting plane,
//! with a stock gripper, picks a box from the table, carries and places it; the gripper mounts
//! itself at a flange (the tool frame is its TCP, checked against the bare chain and the
//! maker's flange-to-TCP distance); the mistakes a user makes with grippers are named.

use graspath::grasp::hand::StockGripper;
use graspath::robot::RobotSource;
use graspath::select::{select, Scored};
use graspath::spelling::Spelled;
use graspath::task::{Task, TaskFile};
use nalgebra::Vector3;
use std::path::Path;

/// A pick-and-place on a table at the arm's mounting plane (`z = 0`): a 5 × 5 × 12 cm box
/// standing on it at `(x, y)`, grasped from its top and sides, lifted 15 cm, carried 20 cm
/// along `y` and put down, with an 8 cm approach and retreat; `extra` adds task-file lines.
fn task_text(robot: &str, gripper: &str, (x, y): (f64, f64), extra: &str) -> String {
    format!(
        r#"
robot: {{ builtin: {robot} }}
object:
  pose: {{ xyz: [{x}, {y}, 0.06] }}
  shape: {{ box: {{ size: [0.05, 0.05, 0.12] }} }}
candidates:
  family: {{ faces: {{ count: 40, exclude: [bottom], depth: 0.02 }} }}
trajectory:
  samples_per_step: 5
  steps:
    - {{ lift: 0.15 }}
    - {{ move: [0.0, 0.2, 0.0] }}
    - {{ place: 0.15 }}
scene: {{ table: {{ height: 0.0 }} }}
gripper: {{ builtin: {gripper} }}
approach: {{ distance: 0.08, samples: 4 }}
retreat: {{ distance: 0.08, samples: 4 }}
{extra}
"#
    )
}

fn load(text: &str) -> Result<Task, graspath::task::TaskError> {
    let file = TaskFile::parse(text, "stock.yaml", "yaml")?;
    Task::from_file(&file, "stock.yaml", Path::new("."))
}

/// Every built-in arm, with its stock gripper and where its box stands (within its reach).
const ARMS: [(&str, &str, (f64, f64)); 10] = [
    ("baxter", "baxter", (0.75, 0.0)),
    ("panda", "franka_hand", (0.5, -0.1)),
    ("fr3", "franka_hand", (0.5, -0.1)),
    ("ur5", "robotiq_2f_85", (0.45, -0.1)),
    ("ur10", "robotiq_2f_140", (0.6, -0.1)),
    ("ur5e", "robotiq_2f_85", (0.45, -0.1)),
    ("ur10e", "robotiq_2f_140", (0.6, -0.1)),
    ("iiwa14", "robotiq_2f_85", (0.5, -0.1)),
    ("xarm7", "franka_hand", (0.4, -0.1)),
    ("gen3", "robotiq_2f_85", (0.45, -0.1)),
];

#[test]
fn every_built_in_arm_with_a_stock_gripper_picks_from_a_table_at_its_base() {
    for (robot, gripper, at) in ARMS {
        let task = load(&task_text(robot, gripper, at, "")).unwrap();
        assert!(task.warnings().is_empty(), "{robot}: {:?}", task.warnings());
        let selection = select(&task, &|| {}).unwrap();
        let arm = &selection.arms[0];
        assert!(
            arm.feasible_count() > 0,
            "{robot} + {gripper}: nothing feasible"
        );
        let best = &arm.scores[arm.best().expect("a selected grasp")];
        // Standing on the table, the arm keeps clear of it: the fixed base is left out of
        // the checks, and the moving links above it keep at least 2 cm.
        let clearance = best.clearance().expect("a scene task measures clearance");
        assert!(
            clearance >= 0.02,
            "{robot} + {gripper}: clearance {clearance}"
        );
        // No candidate fails on the table with the shoulder or upper arm: only the hand or
        // the lower links may meet it (a grasp too low).
        for s in &arm.scores {
            if let Some([a, b]) = s.colliding_bodies() {
                let shoulder = |n: &str| n.contains("shoulder") || n.contains("link1");
                assert!(
                    !((a == "table" && shoulder(b)) || (b == "table" && shoulder(a))),
                    "{robot}: {a} – {b}"
                );
            }
        }
    }
}

#[test]
fn a_stock_gripper_bolted_to_a_flange_puts_the_tool_frame_at_its_tcp() {
    for (robot, gripper) in [
        ("ur5e", StockGripper::Robotiq2F85),
        ("ur10", StockGripper::Robotiq2F140),
        ("iiwa14", StockGripper::FrankaHand),
        ("gen3", StockGripper::Baxter),
    ] {
        let task = load(&task_text(robot, gripper.as_str(), (0.45, -0.1), "")).unwrap();
        let chain = &task.arms()[0].chain;
        // Oracle: the bare chain (no tool) from the robot source, and the maker's distance.
        let bare = RobotSource::builtin(robot)
            .load()
            .unwrap()
            .named_chain("arm", None)
            .unwrap();
        let q = chain.mid_configuration();
        let (flange, tcp) = (bare.pose(&q).unwrap(), chain.pose(&q).unwrap());
        let offset = flange.inverse() * tcp;
        let expected = Vector3::new(0.0, 0.0, gripper.flange_to_tcp());
        assert!(
            (offset.translation.vector - expected).norm() < 1e-12,
            "{robot}"
        );
        assert!(offset.rotation.angle() < 1e-12, "{robot}");
        // A tool offset given by the task wins.
        let given = "robot: { builtin: ROBOT, tool: { xyz: [0, 0, 0.3] } }".replace("ROBOT", robot);
        let text = task_text(robot, gripper.as_str(), (0.45, -0.1), "")
            .replace(&format!("robot: {{ builtin: {robot} }}"), &given);
        let task = load(&text).unwrap();
        let offset = bare.pose(&q).unwrap().inverse() * task.arms()[0].chain.pose(&q).unwrap();
        assert!((offset.translation.vector.z - 0.3).abs() < 1e-12, "{robot}");
    }
}

#[test]
fn gripper_mistakes_are_named() {
    // Another gripper on an arm whose chain ends at its own gripper's TCP.
    let e = load(&task_text("panda", "robotiq_2f_85", (0.5, -0.1), ""))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("gripper.builtin") && e.contains("franka_hand"),
        "{e}"
    );
    let e = load(&task_text("ur5", "robotiq", (0.5, -0.1), ""))
        .unwrap_err()
        .to_string();
    assert!(e.contains("robotiq_2f_85, robotiq_2f_140"), "{e}");
    let e = load(&task_text("ur5", "robotiq_2f_85", (0.5, -0.1), "").replace(
        "builtin: robotiq_2f_85 }",
        "builtin: robotiq_2f_85, opening: 0.1 }",
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("gripper.opening") && e.contains("0.085"), "{e}");
    // A gripper given by its size on a flange, without a tool offset: a warning naming the
    // flange; none with a tool offset.
    let sized = task_text("ur5e", "X", (0.45, -0.1), "")
        .replace("gripper: { builtin: X }", "gripper: { opening: 0.08 }");
    let task = load(&sized).unwrap();
    assert_eq!(task.warnings().len(), 1, "{:?}", task.warnings());
    assert_eq!(task.warnings()[0].field, "gripper");
    assert!(
        task.warnings()[0].message.contains("'tool0'"),
        "{}",
        task.warnings()[0]
    );
    let with_tool = sized.replace(
        "robot: { builtin: ur5e }",
        "robot: { builtin: ur5e, tool: { xyz: [0, 0, 0.15] } }",
    );
    assert!(load(&with_tool).unwrap().warnings().is_empty());
    // The Panda's chain ends at its hand's TCP: a sized gripper there is not at a flange.
    let panda = task_text("panda", "X", (0.5, -0.1), "")
        .replace("gripper: { builtin: X }", "gripper: { opening: 0.08 }");
    assert!(load(&panda).unwrap().warnings().is_empty());
}
