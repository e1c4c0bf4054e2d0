//! A task file's `robot: {file: PATH}`: the format told by the file's name or root element
//! (`RobotSource::from_path`), the same robot as `urdf:` / `mjcf:`, and a clear error for a file
//! of neither format.

use graspath::task::Task;
use graspath::ErrorKind;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// A task on `robot` (the YAML of the `robot:` mapping), written as `task.yaml` in `dir`.
fn load_task(dir: &Path, robot: &str) -> Result<Task, graspath::task::TaskError> {
    let path = dir.join("task.yaml");
    std::fs::write(
        &path,
        format!(
            "robot: {robot}\narms: arm\nobject: {{ pose: {{ xyz: [0.5, 0, 0.2] }}, shape: {{ box: {{ size: [0.05, 0.05, 0.05] }} }} }}\ncandidates: {{ family: {{ edge: {{ count: 3 }} }} }}\ntrajectory: {{ steps: [ {{ lift: 0.05 }} ] }}\n"
        ),
    )
    .unwrap();
    Task::load(&path)
}

/// The tip poses of the task's one arm at a few configurations spread over its joint ranges.
fn tip_poses(task: &Task) -> Vec<Vec<f64>> {
    let chain = &task.arms()[0].chain;
    let (lower, upper) = (chain.lower(), chain.upper());
    (0..5)
        .map(|k| {
            let q: Vec<f64> = (0..chain.dof())
                .map(|j| {
                    let t = ((k * 7 + j * 3) % 11) as f64 / 10.0;
                    lower[j].max(-3.0) + t * (upper[j].min(3.0) - lower[j].max(-3.0))
                })
                .collect();
            chain.pose(&q).unwrap().to_homogeneous().as_slice().to_vec()
        })
        .collect()
}

#[test]
fn file_loads_the_same_robot_as_urdf_and_mjcf() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // An MJCF file named *.xml and the same file without an extension: told by the root.
    let mjcf = data("mjcf/ur5.xml");
    std::fs::copy(&mjcf, d.join("ur5_model")).unwrap();
    let chains = "chains: { arm: { base: base, tip: tool0 } }";
    let by_key = load_task(d, &format!("{{ mjcf: {}, {chains} }}", mjcf.display())).unwrap();
    for file in [mjcf.display().to_string(), "ur5_model".to_string()] {
        let by_file = load_task(d, &format!("{{ file: {file}, {chains} }}")).unwrap();
        assert_eq!(by_file.arms()[0].chain.dof(), 6);
        assert_eq!(tip_poses(&by_file), tip_poses(&by_key), "{file}");
    }
    // A URDF named *.urdf, *.xml and without an extension (relative to the task file).
    let urdf = data("three_finger_hand.urdf");
    for name in ["hand.urdf", "hand.xml", "hand"] {
        std::fs::copy(&urdf, d.join(name)).unwrap();
    }
    let chains = "chains: { arm: { base: palm, tip: finger_a } }";
    let by_key = load_task(d, &format!("{{ urdf: {}, {chains} }}", urdf.display())).unwrap();
    for file in ["hand.urdf", "hand.xml", "hand"] {
        let by_file = load_task(d, &format!("{{ file: {file}, {chains} }}")).unwrap();
        assert_eq!(by_file.robot_name(), by_key.robot_name());
        assert_eq!(tip_poses(&by_file), tip_poses(&by_key), "{file}");
    }
}

#[test]
fn a_file_of_neither_format_is_refused_at_robot_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("world.model"),
        "<?xml version=\"1.0\"?>\n<sdf version=\"1.9\"/>\n",
    )
    .unwrap();
    let err = load_task(
        d,
        "{ file: world.model, chains: { arm: { base: a, tip: b } } }",
    )
    .unwrap_err();
    assert_eq!(err.field, "robot.file");
    let message = graspath::Chain(&err).to_string();
    assert!(message.contains("field 'robot.file'"), "{message}");
    assert!(
        message.contains("world.model: not a robot description"),
        "{message}"
    );
    assert!(message.contains("its root element is <sdf>"), "{message}");
    let fault = graspath::fault_of(&err).unwrap();
    assert_eq!(fault.kind, ErrorKind::Content);
    // A missing file is a file error at the same field.
    let err = load_task(
        d,
        "{ file: missing.xml, chains: { arm: { base: a, tip: b } } }",
    )
    .unwrap_err();
    assert_eq!(err.field, "robot.file");
    assert_eq!(graspath::fault_of(&err).unwrap().kind, ErrorKind::File);
}

#[test]
fn file_takes_urdf_options_only_for_a_urdf_and_excludes_the_other_keys() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::copy(data("mjcf/ur5.xml"), d.join("ur5.xml")).unwrap();
    let err = load_task(
        d,
        "{ file: ur5.xml, search_paths: [meshes], chains: { arm: { base: base, tip: tool0 } } }",
    )
    .unwrap_err();
    assert_eq!(err.field, "robot.search_paths");
    let message = graspath::Chain(&err).to_string();
    assert!(message.contains("this is an MJCF file"), "{message}");
    let err = load_task(
        d,
        "{ file: ur5.xml, mjcf: ur5.xml, chains: { arm: { base: base, tip: tool0 } } }",
    )
    .unwrap_err();
    assert_eq!(err.field, "robot");
    assert!(err.to_string().contains("not several"), "{err}");
}
