//! Every reader of a whole input file refuses one larger than its cap with an error that names
//! the file, before reading it: each file here is sparse (no disk blocks), one byte over the
//! cap, so a reader that read it whole would take the cap's worth of memory (up to 4 GiB) and
//! time instead of failing at once.

use graspath::cloud::{load_cloud_argument, read_cloud, read_mesh, read_pcd, read_ply};
use graspath::grasp::model::{Demonstration, GraspModel};
use graspath::input::{
    MAX_CLOUD_FILE_BYTES, MAX_MODEL_FILE_BYTES, MAX_ROBOT_FILE_BYTES, MAX_TASK_FILE_BYTES,
};
use graspath::robot::{MjcfRobot, Srdf, UrdfRobot};
use graspath::task::TaskFile;
use std::fs::File;
use std::path::Path;

/// Makes `name` in `dir` a sparse file one byte over `cap`, reads it with `read`, and checks
/// that the error (with its sources) names the file and gives the cap, and that it is
/// classified as a resource limit.
fn refused_over_cap<T, E: std::error::Error + 'static>(
    dir: &Path,
    name: &str,
    cap: u64,
    read: impl FnOnce(&Path) -> Result<T, E>,
) {
    let path = dir.join(name);
    File::create(&path).unwrap().set_len(cap + 1).unwrap();
    let Err(error) = read(&path) else {
        panic!("{name}: a file over the cap was read");
    };
    let message = graspath::Chain(&error).to_string();
    assert_eq!(
        graspath::fault_of(&error).map(|fault| fault.kind),
        Some(graspath::ErrorKind::Limit),
        "{message}"
    );
    assert!(
        message.contains(&path.display().to_string()),
        "the file is not named: {message}"
    );
    assert!(
        message.contains(&format!("larger than {cap} bytes")),
        "the cap is not given: {message}"
    );
}

#[test]
fn robot_descriptions_over_the_cap_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    refused_over_cap(d, "robot.urdf", MAX_ROBOT_FILE_BYTES, UrdfRobot::from_file);
    refused_over_cap(d, "robot.xml", MAX_ROBOT_FILE_BYTES, MjcfRobot::from_file);
    refused_over_cap(d, "robot.srdf", MAX_ROBOT_FILE_BYTES, Srdf::read);
}

#[test]
fn a_task_file_over_the_cap_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    refused_over_cap(dir.path(), "task.yaml", MAX_TASK_FILE_BYTES, TaskFile::load);
}

#[test]
fn model_and_demonstration_files_over_the_cap_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    refused_over_cap(d, "model.json", MAX_MODEL_FILE_BYTES, GraspModel::read);
    refused_over_cap(d, "demo.json", MAX_MODEL_FILE_BYTES, Demonstration::read);
}

#[test]
fn clouds_and_meshes_over_the_cap_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    refused_over_cap(d, "scan.ply", MAX_CLOUD_FILE_BYTES, read_ply);
    refused_over_cap(d, "any.ply", MAX_CLOUD_FILE_BYTES, read_cloud);
    refused_over_cap(d, "scan.pcd", MAX_CLOUD_FILE_BYTES, read_pcd);
    refused_over_cap(d, "scan.json", MAX_CLOUD_FILE_BYTES, load_cloud_argument);
    refused_over_cap(d, "bin.stl", MAX_CLOUD_FILE_BYTES, read_mesh);
}
