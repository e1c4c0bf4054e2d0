//! Candidate files: both formats agree, and every bad value is refused at its place.

use super::*;
use crate::geometry::QUATERNION_NORM_TOLERANCE;
use std::io::Write;

#[test]
fn the_grasp_point_is_the_contact_else_the_wrist_origin() {
    let mut candidate = Candidate {
        id: 0,
        label: String::new(),
        object_from_wrist: Isometry3::translation(0.1, -0.2, 0.3),
        log_likelihood: 0.0,
        contact: None,
        hand_joints: Vec::new(),
        width: None,
    };
    assert_eq!(candidate.grasp_point(), Point3::new(0.1, -0.2, 0.3));
    candidate.contact = Some(Point3::new(0.0, 0.01, 0.02));
    assert_eq!(candidate.grasp_point(), Point3::new(0.0, 0.01, 0.02));
}

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.path().join(name);
    std::fs::File::create(&path)
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    path
}

#[test]
fn json_and_csv_give_the_same_candidates() {
    let dir = tempfile::tempdir().unwrap();
    let json = write(
        &dir,
        "c.json",
        r#"{"format":"graspath-candidates","version":1,"frame":"object","candidates":[
            {"id":3,"label":"top","xyz":[0.0,0.1,0.05],"quaternion":[1,0,0,0],"likelihood":0.5,"contact":[0,0.1,0.03]},
            {"id":4,"object_from_wrist":[[1,0,0,0.01],[0,1,0,0],[0,0,1,0],[0,0,0,1]],"log_likelihood":-2}]}"#,
    );
    let csv = write(
        &dir,
        "c.csv",
        "id,label,x,y,z,qx,qy,qz,qw,log_likelihood,contact_x,contact_y,contact_z\n\
         3,top,0.0,0.1,0.05,1,0,0,0,-0.6931471805599453,0,0.1,0.03\n\
         4,,0.01,0,0,0,0,0,1,-2,,,\n",
    );
    let a = read_candidates(&json).unwrap();
    let b = read_candidates(&csv).unwrap();
    assert_eq!(a.len(), 2);
    assert_eq!(a[0].id, b[0].id);
    assert!((a[0].log_likelihood - b[0].log_likelihood).abs() < 1e-15);
    assert_eq!(a[0].object_from_wrist, b[0].object_from_wrist);
    assert_eq!(a[1].object_from_wrist, b[1].object_from_wrist);
    assert_eq!(a[0].contact, Some(Point3::new(0.0, 0.1, 0.03)));
    assert_eq!(b[1].contact, None);
    assert_eq!(b[1].label, "candidate 4");
}

#[test]
fn bad_files_name_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let empty = write(&dir, "e.json", r#"{"candidates":[]}"#);
    assert!(read_candidates(&empty)
        .unwrap_err()
        .to_string()
        .contains("contains no candidates"));
    let nan = write(
        &dir,
        "n.json",
        r#"[{"xyz":[0,0,0],"quaternion":[0,0,0,0]}]"#,
    );
    let err = read_candidates(&nan).unwrap_err();
    assert_eq!(err.location, "candidates[0].quaternion");
    let unknown = write(
        &dir,
        "u.json",
        r#"[{"xyz":[0,0,0],"quaternion":[0,0,0,1],"score":1}]"#,
    );
    assert!(read_candidates(&unknown)
        .unwrap_err()
        .message
        .contains("unknown field `score`"));
    let bad_number = write(&dir, "b.csv", "x,y,z,qx,qy,qz,qw\n0,zero,0,0,0,0,1\n");
    let err = read_candidates(&bad_number).unwrap_err();
    assert_eq!(err.location, "line 2");
    let dup = write(
        &dir,
        "d.json",
        r#"[{"id":1,"xyz":[0,0,0],"quaternion":[0,0,0,1]},{"id":1,"xyz":[0,0,0],"quaternion":[0,0,0,1]}]"#,
    );
    let err = read_candidates(&dup).unwrap_err();
    assert_eq!(err.location, "candidates[1]");
    assert!(err
        .message
        .contains("id 1 is used twice (also by candidates[0])"));
    let skew = write(
        &dir,
        "s.json",
        r#"[{"object_from_wrist":[[1,0.5,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]"#,
    );
    assert!(read_candidates(&skew)
        .unwrap_err()
        .message
        .contains("not orthonormal"));
}

#[test]
fn a_quaternion_must_be_unit_within_the_stated_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    // Half a tolerance off: accepted, and the rotation is the normalised quaternion's.
    let (x, w) = (0.6_f64, 0.8_f64);
    let scale = 1.0 + QUATERNION_NORM_TOLERANCE / 2.0;
    let near = write(
        &dir,
        "near.json",
        &format!(
            r#"[{{"xyz":[0,0,0],"quaternion":[{},0,0,{}]}}]"#,
            x * scale,
            w * scale
        ),
    );
    let c = read_candidates(&near).unwrap();
    let angle = c[0].object_from_wrist.rotation.angle();
    assert!((angle - 2.0 * x.atan2(w)).abs() < 1e-12, "{angle}");
    // Twice the tolerance off, in JSON and in CSV: an error naming the candidate and field.
    let scale = 1.0 + 2.0 * QUATERNION_NORM_TOLERANCE;
    let far = write(
        &dir,
        "far.json",
        &format!(
            r#"[{{"xyz":[0,0,0],"quaternion":[0,0,0,1]}},{{"xyz":[0,0,0],"quaternion":[0,0,0,{scale}]}}]"#
        ),
    );
    let err = read_candidates(&far).unwrap_err();
    assert_eq!(err.location, "candidates[1].quaternion");
    assert!(err.message.contains("must be a unit quaternion"), "{err}");
    let csv = write(
        &dir,
        "far.csv",
        "x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\n0,0,0,0,0,0,2\n",
    );
    let err = read_candidates(&csv).unwrap_err();
    assert_eq!(err.location, "line 3");
    assert!(
        err.message
            .contains("quaternion: must be a unit quaternion [x, y, z, w] (its norm is 2.000000"),
        "{err}"
    );
}

#[test]
fn absurd_or_non_finite_values_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "far.json",
            r#"[{"xyz":[1e300,0,0],"quaternion":[0,0,0,1]}]"#,
            "candidates[0].xyz",
        ),
        (
            "mm.json",
            r#"[{"object_from_wrist":[[1,0,0,150],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]"#,
            "candidates[0].object_from_wrist",
        ),
        (
            "contact.json",
            r#"[{"xyz":[0,0,0],"quaternion":[0,0,0,1],"contact":[0,-11,0]}]"#,
            "candidates[0].contact",
        ),
        (
            "nan.csv",
            "x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\nNaN,0,0,0,0,0,1\n",
            "line 3",
        ),
        (
            "joints.csv",
            "x,y,z,qx,qy,qz,qw,hand_joints\n0,0,0,0,0,0,1,0.01 inf\n",
            "line 2",
        ),
        ("wrapped.json", r#"{"candidates":[],"units":"mm"}"#, "file"),
        ("scalar.json", "42", "file"),
    ];
    for (name, text, location) in cases {
        let err = read_candidates(&write(&dir, name, text)).unwrap_err();
        assert_eq!(err.location, location, "{name}: {err}");
        assert!(err.file.ends_with(name));
    }
    let err = read_candidates(&dir.path().join("far.json")).unwrap_err();
    assert!(err.message.contains("are the units metres?"), "{err}");
    let err = read_candidates(&dir.path().join("wrapped.json")).unwrap_err();
    assert!(err.message.contains("unknown field `units`"), "{err}");
}

#[test]
fn csv_hand_joints_are_read_and_line_numbers_count_quoted_newlines() {
    let dir = tempfile::tempdir().unwrap();
    let csv = write(
        &dir,
        "h.csv",
        "label,x,y,z,qx,qy,qz,qw,hand_joints\n\"two\nlines\",0,0,0,0,0,0,1,0.01 0.02;0.03\nb,0,0,0,0,0,0,oops,\n",
    );
    let err = read_candidates(&csv).unwrap_err();
    assert_eq!(err.location, "line 4", "{err}");
    let ok = write(
        &dir,
        "ok.csv",
        "x,y,z,qx,qy,qz,qw,hand_joints\n0,0,0,0,0,0,1,0.01 0.02;0.03\n",
    );
    assert_eq!(
        read_candidates(&ok).unwrap()[0].hand_joints,
        [0.01, 0.02, 0.03]
    );
}

#[test]
fn a_file_over_the_size_limit_is_refused_before_it_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.json");
    // A sparse file: no disk space is used and nothing is read.
    std::fs::File::create(&path)
        .unwrap()
        .set_len(MAX_FILE_BYTES + 1)
        .unwrap();
    for err in every_reader(&path) {
        assert_eq!(err.location, "file");
        // A resource limit, as every input file over its cap is: the size cap's error is the
        // source, of the operating system's kind for it.
        let fault = crate::fault_of(&err).unwrap();
        assert_eq!(fault.kind, crate::ErrorKind::Limit, "{err}");
        assert_eq!(fault.io, Some(io::ErrorKind::FileTooLarge), "{err}");
        assert_eq!(fault.file, Some(path.display().to_string().as_str()));
        let chain = crate::Chain(&err).to_string();
        assert!(
            chain.contains(&format!("is larger than {MAX_FILE_BYTES} bytes")),
            "{chain}"
        );
    }
}

#[test]
fn a_missing_file_is_a_file_error_that_keeps_the_operating_systems() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["missing.json", "missing.csv", "missing.npz"] {
        let path = dir.path().join(name);
        for err in every_reader(&path) {
            let fault = crate::fault_of(&err).unwrap();
            assert_eq!(fault.kind, crate::ErrorKind::File, "{err}");
            assert_eq!(fault.io, Some(io::ErrorKind::NotFound), "{err}");
            assert_eq!(fault.file, Some(path.display().to_string().as_str()));
            assert_eq!(fault.field, Some("file"));
            let source = std::error::Error::source(&err).unwrap();
            assert_eq!(
                source.downcast_ref::<io::Error>().map(io::Error::kind),
                Some(io::ErrorKind::NotFound)
            );
            assert_eq!(
                crate::Chain(&err).to_string(),
                format!("{}: file: cannot read: {source}", path.display())
            );
        }
    }
    // A folder is a file error too, not bad content.
    for err in every_reader(dir.path()) {
        assert_eq!(
            crate::fault_of(&err).unwrap().kind,
            crate::ErrorKind::File,
            "{err}"
        );
    }
}

/// The error of every reader of candidate and grasp files for `path`: the whole-file reader,
/// the indexer, the grasp-file readers and the format guess.
fn every_reader(path: &Path) -> Vec<CandidateError> {
    let options = crate::grasp::GraspFileOptions::default();
    vec![
        read_candidates(path).unwrap_err(),
        CandidateFile::index(path).unwrap_err(),
        crate::grasp::read_grasp_file(path, &options).unwrap_err(),
        crate::grasp::open_grasp_file(path, &options).unwrap_err(),
        crate::grasp::guess_format(path).unwrap_err(),
    ]
}

#[test]
fn every_pose_form_is_read_by_the_one_parser_alike() {
    // Oracle: the same rotation written three ways (rpy_deg, its quaternion, its matrix)
    // gives the same pose to rounding.
    let q = nalgebra::UnitQuaternion::from_euler_angles(
        10f64.to_radians(),
        -20f64.to_radians(),
        30f64.to_radians(),
    );
    let m =
        Isometry3::from_parts(nalgebra::Translation3::new(0.01, 0.02, 0.03), q).to_homogeneous();
    let rows: Vec<Vec<f64>> = (0..4)
        .map(|r| (0..4).map(|c| m[(r, c)]).collect())
        .collect();
    let c = q.coords;
    let text = format!(
        r#"[{{"pose": {{"xyz": [0.01, 0.02, 0.03], "rpy_deg": [10, -20, 30]}}}},
            {{"xyz": [0.01, 0.02, 0.03], "quaternion": [{}, {}, {}, {}]}},
            {{"object_from_wrist": {rows:?}}},
            {{"pose": {{"matrix": {rows:?}}}}}]"#,
        c.x, c.y, c.z, c.w
    );
    let dir = tempfile::tempdir().unwrap();
    let list = read_candidates(&write(&dir, "poses.json", &text)).unwrap();
    assert_eq!(list.len(), 4);
    for other in &list[1..] {
        let d = list[0].object_from_wrist.inverse() * other.object_from_wrist;
        assert!(d.translation.vector.norm() < 1e-12 && d.rotation.angle() < 1e-12);
    }
    let both = r#"[{"pose": {"xyz": [0, 0, 0]}, "xyz": [0, 0, 0], "quaternion": [0, 0, 0, 1]}]"#;
    let error = read_candidates(&write(&dir, "both.json", both))
        .unwrap_err()
        .to_string();
    assert!(error.contains("candidates[0].pose"), "{error}");
    let two_rotations =
        r#"[{"pose": {"xyz": [0, 0, 0], "rpy": [0, 0, 0], "quaternion": [0, 0, 0, 1]}}]"#;
    let error = read_candidates(&write(&dir, "two.json", two_rotations))
        .unwrap_err()
        .to_string();
    assert!(error.contains("candidates[0].pose.rpy"), "{error}");
}
