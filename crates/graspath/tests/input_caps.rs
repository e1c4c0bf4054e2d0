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
use std::path::{Path, PathBuf};

/// A sparse file `name` in `dir` of `len` bytes.
fn sparse(dir: &Path, name: &str, len: u64) -> PathBuf {
    let path = dir.join(name);
    File::create(&path).unwrap().set_len(len).unwrap();
    path
}

/// The error names the file and says it is too large for the cap.
fn refused(error: impl std::fmt::Display, path: &Path, cap: u64) {
    let message = error.to_string();
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
    let over = MAX_ROBOT_FILE_BYTES + 1;
    let urdf = sparse(dir.path(), "robot.urdf", over);
    refused(
        UrdfRobot::from_file(&urdf).unwrap_err(),
        &urdf,
        MAX_ROBOT_FILE_BYTES,
    );
    let mjcf = sparse(dir.path(), "robot.xml", over);
    refused(
        MjcfRobot::from_file(&mjcf).unwrap_err(),
        &mjcf,
        MAX_ROBOT_FILE_BYTES,
    );
    let srdf = sparse(dir.path(), "robot.srdf", over);
    refused(Srdf::read(&srdf).unwrap_err(), &srdf, MAX_ROBOT_FILE_BYTES);
}

#[test]
fn a_task_file_over_the_cap_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let task = sparse(dir.path(), "task.yaml", MAX_TASK_FILE_BYTES + 1);
    refused(
        TaskFile::load(&task).unwrap_err(),
        &task,
        MAX_TASK_FILE_BYTES,
    );
}

#[test]
fn model_and_demonstration_files_over_the_cap_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let model = sparse(dir.path(), "model.json", MAX_MODEL_FILE_BYTES + 1);
    refused(
        GraspModel::read(&model).unwrap_err(),
        &model,
        MAX_MODEL_FILE_BYTES,
    );
    let demo = sparse(dir.path(), "demo.json", MAX_MODEL_FILE_BYTES + 1);
    refused(
        Demonstration::read(&demo).unwrap_err(),
        &demo,
        MAX_MODEL_FILE_BYTES,
    );
}

#[test]
fn clouds_and_meshes_over_the_cap_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let over = MAX_CLOUD_FILE_BYTES + 1;
    let ply = sparse(dir.path(), "scan.ply", over);
    refused(read_ply(&ply).unwrap_err(), &ply, MAX_CLOUD_FILE_BYTES);
    refused(read_cloud(&ply).unwrap_err(), &ply, MAX_CLOUD_FILE_BYTES);
    let pcd = sparse(dir.path(), "scan.pcd", over);
    refused(read_pcd(&pcd).unwrap_err(), &pcd, MAX_CLOUD_FILE_BYTES);
    let source = sparse(dir.path(), "scan.json", over);
    refused(
        load_cloud_argument(&source).unwrap_err(),
        &source,
        MAX_CLOUD_FILE_BYTES,
    );
    let mesh = sparse(dir.path(), "bin.stl", over);
    refused(read_mesh(&mesh).unwrap_err(), &mesh, MAX_CLOUD_FILE_BYTES);
}
