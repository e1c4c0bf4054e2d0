//! Grasp files of external generators (`tests/data/grasp_files/`, written by
//! `make_fixtures.py` the way each generator saves them) read back to the poses that script
//! computed independently (`expected.json`), to 1e-12; frame changes checked by composition.

use graspath::grasp::{
    read_grasp_file, GraspFileOptions, GraspFormat, GraspFrame, GripperConvention,
};
use graspath::spelling::Spelled;
use nalgebra::{Isometry3, Matrix4};
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/grasp_files")
}

fn expected() -> serde_json::Value {
    let text = std::fs::read_to_string(dir().join("expected.json")).expect("expected.json");
    serde_json::from_str(&text).expect("json")
}

fn matrix(v: &serde_json::Value) -> Matrix4<f64> {
    Matrix4::from_fn(|i, j| v[i][j].as_f64().expect("number"))
}

fn isometry(v: &serde_json::Value) -> Isometry3<f64> {
    graspath::geometry::pose_from_rows(&std::array::from_fn(|i| {
        std::array::from_fn(|j| v[i][j].as_f64().expect("number"))
    }))
    .expect("rigid")
}

/// The task's `object_from_world` (`world_from_object⁻¹`) for world-frame fixtures (M2T2).
fn object_from_world(e: &serde_json::Value) -> Isometry3<f64> {
    isometry(&e["world_from_object"]).inverse()
}

/// The task's `object_from_camera` for camera-frame fixtures.
fn object_from_camera(e: &serde_json::Value) -> Isometry3<f64> {
    isometry(&e["world_from_object"]).inverse() * isometry(&e["world_from_camera"])
}

fn check(name: &str, format: GraspFormat, object_from_frame: Isometry3<f64>) {
    let e = expected();
    let want = e["files"][name].as_array().expect(name);
    let options = GraspFileOptions {
        object_from_frame,
        ..GraspFileOptions::default()
    };
    let (guessed, got) = read_grasp_file(&dir().join(name), &options).expect(name);
    assert_eq!(guessed, format, "{name}: format guessed from the content");
    assert_eq!(got.len(), want.len(), "{name}: number of candidates");
    for (c, w) in got.iter().zip(want) {
        assert_eq!(c.id as u64, w["id"].as_u64().unwrap(), "{name}");
        let diff = (c.object_from_wrist.to_homogeneous() - matrix(&w["object_from_tool"]))
            .abs()
            .max();
        assert!(diff < 1e-12, "{name} id {}: pose differs by {diff}", c.id);
        let ll = w["log_likelihood"].as_f64().unwrap();
        assert!(
            (c.log_likelihood - ll).abs() < 1e-12,
            "{name} id {}: {} vs {ll}",
            c.id,
            c.log_likelihood
        );
        assert_eq!(c.width, w["width"].as_f64(), "{name} id {}", c.id);
        match (&c.contact, w["contact"].as_array()) {
            (None, None) => {}
            (Some(p), Some(q)) => {
                for k in 0..3 {
                    assert!(
                        (p[k] - q[k].as_f64().unwrap()).abs() < 1e-12,
                        "{name} contact"
                    );
                }
            }
            other => panic!("{name}: contact {other:?}"),
        }
    }
}

#[test]
fn acronym_hdf5_reads_to_the_scripts_poses_without_failed_grasps() {
    check("acronym.h5", GraspFormat::Acronym, Isometry3::identity());
}

#[test]
fn graspgen_isaac_yaml_and_dataset_json_read_to_the_scripts_poses() {
    check(
        "graspgen.yaml",
        GraspFormat::GraspGen,
        Isometry3::identity(),
    );
    check(
        "graspgen_dataset.json",
        GraspFormat::GraspGen,
        Isometry3::identity(),
    );
}

#[test]
fn contact_graspnet_segments_in_the_camera_frame_land_in_the_object_frame() {
    check(
        "contact_graspnet.npz",
        GraspFormat::ContactGraspnet,
        object_from_camera(&expected()),
    );
}

#[test]
fn generic_pose_arrays_read_to_the_scripts_poses() {
    check("poses.npy", GraspFormat::Poses, Isometry3::identity());
    check("poses.npz", GraspFormat::Poses, Isometry3::identity());
}

#[test]
fn graspnet_rows_read_with_widths_and_scores() {
    check(
        "graspnet.npy",
        GraspFormat::GraspNet,
        object_from_camera(&expected()),
    );
}

#[test]
fn one_segment_of_a_contact_graspnet_file_can_be_chosen() {
    let options = GraspFileOptions {
        segment: Some(3),
        ..GraspFileOptions::default()
    };
    let (_, got) = read_grasp_file(&dir().join("contact_graspnet.npz"), &options).unwrap();
    assert_eq!(got.len(), 2);
    assert!(got.iter().all(|c| c.label.starts_with("segment 3")));
    let options = GraspFileOptions {
        segment: Some(7),
        ..GraspFileOptions::default()
    };
    let err = read_grasp_file(&dir().join("contact_graspnet.npz"), &options).unwrap_err();
    assert_eq!(err.location, "pred_grasps_cam");
    assert!(err.message.contains("segments: 1, 3"), "{err}");
}

/// Frame invariants: reading with `object_from_frame = A` equals `A ·` (reading in the
/// object frame), and an overriding `gripper_from_tool = B` equals (default reading) ·
/// default⁻¹ · B.
#[test]
fn frame_changes_compose() {
    let path = dir().join("acronym.h5");
    let (_, plain) = read_grasp_file(&path, &GraspFileOptions::default()).unwrap();
    let a = Isometry3::new(
        nalgebra::Vector3::new(0.1, -0.2, 0.3),
        nalgebra::Vector3::new(0.4, 0.5, -0.6),
    );
    let b = Isometry3::new(
        nalgebra::Vector3::new(0.0, 0.01, 0.11),
        nalgebra::Vector3::new(0.0, 0.0, 1.0),
    );
    let moved = read_grasp_file(
        &path,
        &GraspFileOptions {
            object_from_frame: a,
            ..GraspFileOptions::default()
        },
    )
    .unwrap()
    .1;
    let tooled = read_grasp_file(
        &path,
        &GraspFileOptions {
            gripper_from_tool: Some(b),
            ..GraspFileOptions::default()
        },
    )
    .unwrap()
    .1;
    let default = GripperConvention::FrankaHand.gripper_from_tool();
    for ((p, m), t) in plain.iter().zip(&moved).zip(&tooled) {
        let d1 = ((a * p.object_from_wrist).to_homogeneous()
            - m.object_from_wrist.to_homogeneous())
        .abs()
        .max();
        let d2 = ((p.object_from_wrist * default.inverse() * b).to_homogeneous()
            - t.object_from_wrist.to_homogeneous())
        .abs()
        .max();
        assert!(d1 < 1e-12 && d2 < 1e-12, "{d1} {d2}");
    }
}

/// The Franka convention maps the hand's closing axis `x` to the tool's `y` and keeps the
/// approach `z`; GraspNet's approach `x` becomes the tool's `z`.
#[test]
fn gripper_conventions_map_the_axes_as_documented() {
    let f = GripperConvention::FrankaHand.gripper_from_tool();
    let y = f.rotation * nalgebra::Vector3::y();
    let z = f.rotation * nalgebra::Vector3::z();
    assert!(
        (y - nalgebra::Vector3::x()).norm() < 1e-15 && (z - nalgebra::Vector3::z()).norm() < 1e-15
    );
    assert!((f.translation.vector.z - 0.1034).abs() < 1e-15);
    // GraspGen's franka_panda: the same axes, its own depth (config/grippers/franka_panda.yaml).
    let g = GripperConvention::GraspGenFranka.gripper_from_tool();
    assert_eq!(g.rotation, f.rotation);
    assert!((g.translation.vector.z - 0.10527314).abs() < 1e-15);
    assert_eq!(
        GraspFormat::GraspGen.gripper(),
        GripperConvention::GraspGenFranka
    );
    for format in [
        GraspFormat::Acronym,
        GraspFormat::ContactGraspnet,
        GraspFormat::M2T2,
    ] {
        assert_eq!(
            format.gripper(),
            GripperConvention::FrankaHand,
            "{format:?}"
        );
    }
    let g = GripperConvention::GraspNet.gripper_from_tool();
    let z = g.rotation * nalgebra::Vector3::z();
    let y = g.rotation * nalgebra::Vector3::y();
    assert!(
        (z - nalgebra::Vector3::x()).norm() < 1e-15 && (y - nalgebra::Vector3::y()).norm() < 1e-15
    );
}

/// Bad files: one error naming the file and the field, no panic; a header claiming more data
/// than the file holds is refused before anything is allocated for it.
#[test]
fn bad_grasp_files_give_one_clear_error() {
    let cases: &[(&str, &str, &str)] = &[
        ("no_transforms.h5", "grasps/transforms", "dataset missing"),
        // Present, with a damaged object header: why it cannot be read, not "missing".
        (
            "damaged_transforms.h5",
            "grasps/transforms",
            "cannot be opened: ",
        ),
        (
            "transforms_3x3.h5",
            "grasps/transforms",
            "expected (N, 4, 4)",
        ),
        (
            "wrong_shape.npz",
            "pred_grasps_cam",
            "has shape (3, 4), expected (N, 4, 4)",
        ),
        ("not_rigid.npy", "not_rigid[1]", "not orthonormal"),
        ("nan.npy", "nan[0]", "not a finite number"),
        ("empty.npy", "file", "is empty"),
        ("scores_mismatch.npz", "scores", "one per grasp"),
        ("huge_header.npy", "file", "only 128 bytes of data follow"),
        ("huge_header.h5", "grasps/transforms", "more than a"),
        (
            "mixed_segments.npz",
            "scores",
            "is split by segment or object, but pred_grasps_cam is one array",
        ),
        // Issue 34: refused, never converted (complex values would lose their imaginary part).
        (
            "complex.npz",
            "grasps",
            "dtype '<c16' holds complex numbers",
        ),
        (
            "complex_segments.npz",
            "pred_grasps_cam",
            "dtype 'c8' holds complex numbers",
        ),
        ("longdouble.npy", "file", "holds long doubles"),
        // Pickled dtypes NumPy never writes: no panic.
        (
            "pickled_f0.npz",
            "pred_grasps_cam",
            "dtype 'f0' is not a number type",
        ),
        (
            "pickled_empty_dtype.npz",
            "pred_grasps_cam",
            "dtype '' is not a number type",
        ),
        // Memory bounded before it is used: a 590-byte memo bomb (2^40 copies), lists nested
        // 1000 deep, a 13-byte header claiming 4 GiB.
        (
            "memo_bomb.npz",
            "pred_grasps_cam",
            "the pickle decodes to more than",
        ),
        (
            "deep_pickle.npz",
            "pred_grasps_cam",
            "nests containers more than 64 deep",
        ),
        (
            "header_4gib.npy",
            "file",
            "the .npy header declares 4294967295 bytes; more than 65536 is refused",
        ),
        ("ragged.json", "transforms", "not rectangular"),
    ];
    for (name, location, message) in cases {
        let path = dir().join("bad").join(name);
        let err = read_grasp_file(&path, &GraspFileOptions::default())
            .err()
            .unwrap_or_else(|| panic!("{name} was accepted"));
        assert!(err.file.ends_with(name), "{name}: {err}");
        assert_eq!(err.location, *location, "{name}: {err}");
        assert!(err.message.contains(message), "{name}: {err}");
    }
}

/// A grasp file holding more grasps than the task's candidate limit is refused from the arrays'
/// declared shapes, before their values are read: in each binary layout and the text ones.
#[test]
fn a_grasp_count_over_the_limit_is_refused_before_reading() {
    let cases: &[(&str, Option<GraspFormat>, &str)] = &[
        ("poses.npy", None, "poses"),
        ("poses.npz", None, "grasps"),
        ("graspnet.npy", None, "graspnet"),
        ("acronym.h5", None, "grasps/transforms"),
        ("contact_graspnet.npz", None, "pred_grasps_cam"),
        ("m2t2_equal.npz", None, "grasps"),
        ("graspgen.yaml", None, "grasps"),
        ("graspgen_dataset.json", None, "grasps.transforms"),
    ];
    for (name, format, location) in cases {
        let path = dir().join(name);
        let (_, all) = read_grasp_file(&path, &GraspFileOptions::default()).expect(name);
        assert!(all.len() > 1, "{name}");
        let options = GraspFileOptions {
            format: *format,
            max_candidates: Some(1),
            ..GraspFileOptions::default()
        };
        let err = read_grasp_file(&path, &options)
            .err()
            .unwrap_or_else(|| panic!("{name}: over the limit, accepted"));
        assert_eq!(err.location, *location, "{name}: {err}");
        assert!(
            err.message
                .contains("more than the limit 1; raise limits.max_candidates"),
            "{name}: {err}"
        );
        let options = GraspFileOptions {
            max_candidates: Some(100_000),
            ..GraspFileOptions::default()
        };
        assert_eq!(
            read_grasp_file(&path, &options).expect(name).1.len(),
            all.len()
        );
    }
}

/// A camera-frame format without a camera pose is refused by the task loader, naming the field.
#[test]
fn camera_frame_files_need_a_camera_pose_in_the_task() {
    let task = format!(
        r#"
robot: {{ builtin: baxter }}
arms: left
object: {{ pose: {{ xyz: [0.75, 0.0, -0.10] }} }}
candidates: {{ file: {} }}
trajectory: {{ samples_per_step: 2, steps: [ {{ lift: 0.1 }} ] }}
"#,
        dir().join("graspnet.npy").display()
    );
    let file = graspath::task::TaskFile::parse(&task, "t.yaml", "yaml").unwrap();
    let Err(err) = graspath::task::Task::from_file(&file, "t.yaml", Path::new(".")) else {
        panic!("a camera-frame file without a camera pose was accepted");
    };
    assert_eq!(err.field, "candidates.frame", "{err}");
    assert!(err.message.contains("world_from_camera"), "{err}");
}

/// `world_from_camera` in a task file places camera-frame grasps where the hand-computed
/// `object_from_camera = world_from_object⁻¹ · world_from_camera` puts them.
#[test]
fn a_task_file_with_world_from_camera_gives_the_scripts_poses() {
    let e = expected();
    let rows = |key: &str| serde_json::to_string(&e[key]).unwrap();
    let task = format!(
        r#"{{
  "robot": {{ "builtin": "baxter" }},
  "arms": "left",
  "object": {{ "pose": {{ "matrix": {} }} }},
  "candidates": {{ "file": "{}", "world_from_camera": {{ "matrix": {} }} }},
  "trajectory": {{ "samples_per_step": 2, "steps": [ {{ "lift": 0.1 }} ] }}
}}"#,
        rows("world_from_object"),
        dir().join("contact_graspnet.npz").display(),
        rows("world_from_camera"),
    );
    let file = graspath::task::TaskFile::parse(&task, "t.json", "json").unwrap();
    let builder = graspath::task::builder_from_file(&file, "t.json", Path::new(".")).unwrap();
    let task = builder.build().unwrap();
    let want = e["files"]["contact_graspnet.npz"].as_array().unwrap();
    let got = &task.candidates().held().expect("held candidates");
    assert_eq!(got.len(), want.len());
    for (c, w) in got.iter().zip(want) {
        let diff = (c.object_from_wrist.to_homogeneous() - matrix(&w["object_from_tool"]))
            .abs()
            .max();
        assert!(diff < 1e-12, "{diff}");
    }
}

/// GraspNet widths feed the gripper-opening check: exactly the grasps wider than the opening
/// (by the script's widths) fail with `gripper_width`, whether or not the object's shape is known.
#[test]
fn widths_from_the_file_wider_than_the_opening_fail_for_gripper_width() {
    let e = expected();
    let opening = 0.07;
    let task = format!(
        r#"{{
  "robot": {{ "builtin": "baxter" }},
  "arms": "left",
  "object": {{ "pose": {{ "matrix": {} }} }},
  "candidates": {{ "file": "{}", "world_from_camera": {{ "matrix": {} }} }},
  "gripper": {{ "opening": {opening} }},
  "trajectory": {{ "samples_per_step": 2, "steps": [ {{ "lift": 0.1 }} ] }}
}}"#,
        serde_json::to_string(&e["world_from_object"]).unwrap(),
        dir().join("graspnet.npy").display(),
        serde_json::to_string(&e["world_from_camera"]).unwrap(),
    );
    let file = graspath::task::TaskFile::parse(&task, "t.json", "json").unwrap();
    let task = graspath::task::Task::from_file(&file, "t.json", Path::new(".")).unwrap();
    let selection = graspath::select::select(&task, &|| {}).unwrap();
    let want = e["files"]["graspnet.npy"].as_array().unwrap();
    let scores = &selection.arms[0].scores;
    assert_eq!(scores.len(), want.len());
    let mut wide = 0;
    for (s, w) in scores.iter().zip(want) {
        let too_wide = w["width"].as_f64().unwrap() > opening;
        let failed_width = s
            .failure
            .as_ref()
            .is_some_and(|f| f.reason == graspath::failure::FailureReason::GripperWidth);
        assert_eq!(too_wide, failed_width, "{:?}", s.failure);
        wide += usize::from(too_wide);
    }
    assert_eq!(wide, 2, "the fixture has two grasps wider than 7 cm");
}

/// The example's GraspGen file (11 grasps, `grasp_0` … `grasp_10`): ids follow GraspGen's
/// numbering, not the names' alphabetical order, and the Franka convention puts each tool
/// point 2 cm below the box's top, approaching down, fingers closing across the box (object x).
#[test]
fn the_graspgen_example_reads_in_its_writers_order_with_tool_points_under_the_top() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/grasp_files/graspgen_box.yaml");
    let (format, got) = read_grasp_file(&path, &GraspFileOptions::default()).unwrap();
    assert_eq!(format, GraspFormat::GraspGen);
    assert_eq!(got.len(), 11);
    for (k, c) in got.iter().enumerate() {
        assert_eq!((c.id, c.label.as_str()), (k, format!("grasp_{k}").as_str()));
        let y = -0.18 + 0.036 * k as f64;
        let t = c.object_from_wrist.translation.vector;
        assert!(
            (t - nalgebra::Vector3::new(0.0, y, 0.03)).norm() < 1e-12,
            "{k}: {t}"
        );
        let approach = c.object_from_wrist.rotation * nalgebra::Vector3::z();
        let closing = c.object_from_wrist.rotation * nalgebra::Vector3::y();
        assert!(
            (approach + nalgebra::Vector3::z()).norm() < 1e-12,
            "{approach}"
        );
        assert!((closing.x.abs() - 1.0).abs() < 1e-12, "{closing}");
    }
}

/// The example task selects among the GraspGen grasps: they are the box's top grasps, so the
/// arm reaches most of them.
#[test]
fn the_graspgen_example_task_runs() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/grasp_files/pick_and_place_graspgen.yaml");
    let task = graspath::task::Task::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(task.candidate_count(), 11);
    let selection = graspath::select::select(&task, &|| {}).unwrap();
    let feasible = selection.arms[0]
        .scores
        .iter()
        .filter(|s| s.failure.is_none())
        .count();
    assert!(feasible >= 6, "{feasible} of 11 feasible");
}

/// Contact-GraspNet run with `local_regions` (`predict_grasps` per segment) writes a segment
/// with one grasp with `contact_pts` squeezed to `(3,)`, and a segment emptied by
/// `filter_segment` with `contact_pts` `(0,)` (make_fixtures.py follows
/// `contact_grasp_estimator.py`): both read, the lone grasp with its contact.
#[test]
fn contact_graspnet_segments_of_one_grasp_and_of_none_are_read() {
    check(
        "contact_graspnet_one_grasp.npz",
        GraspFormat::ContactGraspnet,
        object_from_camera(&expected()),
    );
    let (_, got) = read_grasp_file(
        &dir().join("contact_graspnet_one_grasp.npz"),
        &GraspFileOptions {
            segment: Some(2),
            ..GraspFileOptions::default()
        },
    )
    .unwrap();
    assert_eq!(got.len(), 1);
    assert_eq!(got[0].label, "segment 2 grasp 0");
    assert!(got[0].contact.is_some());
}

/// M2T2's per-object outputs (`demo.py`'s lists of `grasps`, `grasp_confidence`,
/// `grasp_contacts`) saved as object lists, as dictionaries keyed by object name, and as the
/// stacked arrays numpy makes of equal-length lists: guessed as M2T2, read in the world frame,
/// each object a segment whose label names it.
#[test]
fn m2t2_lists_and_named_objects_read_in_the_world_frame() {
    let e = expected();
    for name in ["m2t2_objects.npz", "m2t2_named.npz", "m2t2_equal.npz"] {
        check(name, GraspFormat::M2T2, object_from_world(&e));
    }
    assert_eq!(GraspFormat::M2T2.default_frame(), GraspFrame::World);
    assert_eq!(
        GraspFormat::ContactGraspnet.default_frame(),
        GraspFrame::Camera
    );
    assert_eq!(GraspFormat::from_name("m2t2"), Some(GraspFormat::M2T2));
    let labels = |name: &str, segment: Option<i64>| -> Vec<String> {
        let options = GraspFileOptions {
            segment,
            ..GraspFileOptions::default()
        };
        let (_, got) = read_grasp_file(&dir().join(name), &options).expect(name);
        got.into_iter().map(|c| c.label).collect()
    };
    assert_eq!(
        labels("m2t2_objects.npz", None),
        [
            "object 0 grasp 0",
            "object 0 grasp 1",
            "object 1 grasp 0",
            "object 2 grasp 0",
            "object 2 grasp 1",
            "object 2 grasp 2"
        ]
    );
    assert_eq!(
        labels("m2t2_named.npz", None)[2..4],
        ["object_01 grasp 0", "object_02 grasp 0"]
    );
    assert_eq!(
        labels("m2t2_equal.npz", Some(1)),
        ["object 1 grasp 0", "object 1 grasp 1"]
    );
    let err = read_grasp_file(
        &dir().join("m2t2_named.npz"),
        &GraspFileOptions {
            segment: Some(0),
            ..GraspFileOptions::default()
        },
    )
    .unwrap_err();
    assert_eq!(err.location, "grasps", "{err}");
    assert!(err.message.contains("'object_00', 'object_01'"), "{err}");
}

/// A task reading an M2T2 file: the default frame is the world, so `object.pose` alone places
/// the grasps where make_fixtures.py computed them; a camera pose without `frame: camera` is
/// refused naming `candidates.frame` (it would move the grasps by the camera pose), and with
/// `frame: camera` it is applied.
#[test]
fn an_m2t2_task_reads_world_grasps_and_refuses_a_camera_pose_it_would_misapply() {
    let e = expected();
    let task = |extra: &str| {
        format!(
            r#"{{
  "robot": {{ "builtin": "baxter" }},
  "arms": "left",
  "object": {{ "pose": {{ "matrix": {} }} }},
  "candidates": {{ "file": "{}", "format": "m2t2"{extra} }},
  "trajectory": {{ "samples_per_step": 2, "steps": [ {{ "lift": 0.1 }} ] }}
}}"#,
            serde_json::to_string(&e["world_from_object"]).unwrap(),
            dir().join("m2t2_objects.npz").display(),
        )
    };
    let load = |text: String| {
        let file = graspath::task::TaskFile::parse(&text, "t.json", "json").unwrap();
        graspath::task::Task::from_file(&file, "t.json", Path::new("."))
    };
    let got = load(task("")).unwrap_or_else(|err| panic!("{err}"));
    let want = e["files"]["m2t2_objects.npz"].as_array().unwrap();
    assert_eq!(got.candidate_count(), want.len());
    for (c, w) in got
        .candidates()
        .held()
        .expect("held candidates")
        .iter()
        .zip(want)
    {
        let diff = (c.object_from_wrist.to_homogeneous() - matrix(&w["object_from_tool"]))
            .abs()
            .max();
        assert!(diff < 1e-12, "{diff}");
    }
    let camera = format!(
        r#", "world_from_camera": {{ "matrix": {} }}"#,
        serde_json::to_string(&e["world_from_camera"]).unwrap()
    );
    let Err(err) = load(task(&camera)) else {
        panic!("a camera pose was applied to M2T2's world-frame grasps");
    };
    assert_eq!(err.field, "candidates.frame", "{err}");
    assert!(err.message.contains("frame is world"), "{err}");
    let explicit = load(task(&format!(r#"{camera}, "frame": "camera""#))).unwrap();
    let object_from_camera = object_from_camera(&e);
    for (c, w) in explicit
        .candidates()
        .held()
        .expect("held candidates")
        .iter()
        .zip(want)
    {
        // Read as camera-frame poses: object_from_camera · world_from_object · (expected).
        let moved = object_from_camera.to_homogeneous()
            * isometry(&e["world_from_object"]).to_homogeneous()
            * matrix(&w["object_from_tool"]);
        let diff = (c.object_from_wrist.to_homogeneous() - moved).abs().max();
        assert!(diff < 1e-12, "{diff}");
    }
}

/// docs/grasp-files.md's optical-frame rule: ROS's `camera_link` → `camera_color_optical_frame`
/// is `rpy = (−π/2, 0, −π/2)`, which maps the optical `z` (forward) to the link's `x`, the
/// optical `x` (right) to the link's `−y` and the optical `y` (down) to the link's `−z`; a
/// GraspNet grasp 0.5 m in front of the camera, read with `world_from_camera` = the link's pose
/// · that rotation, lands 0.5 m along the link's `x`.
#[test]
fn the_documented_optical_frame_relation_points_the_camera_along_the_links_x() {
    use nalgebra::Vector3;
    let spec = graspath::geometry::PoseSpec {
        rpy: Some([
            -std::f64::consts::FRAC_PI_2,
            0.0,
            -std::f64::consts::FRAC_PI_2,
        ]),
        ..Default::default()
    };
    let link_from_optical = spec.to_isometry().unwrap();
    let r = link_from_optical.rotation;
    assert!((r * Vector3::z() - Vector3::x()).norm() < 1e-15);
    assert!((r * Vector3::x() + Vector3::y()).norm() < 1e-15);
    assert!((r * Vector3::y() + Vector3::z()).norm() < 1e-15);
    // A GraspNet-1Billion row (graspnetAPI GraspGroup.save_npy layout) at (0, 0, 0.5) in the
    // optical frame, identity rotation, written as the fixture script writes graspnet.npy.
    let mut row = [0.0f32; 17];
    row[0] = 0.9;
    row[1] = 0.05;
    row[4] = 1.0;
    row[8] = 1.0;
    row[12] = 1.0;
    row[15] = 0.5;
    let header = "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 17), }";
    let mut h = header.to_string();
    while !(10 + h.len() + 1).is_multiple_of(64) {
        h.push(' ');
    }
    h.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(h.len() as u16).to_le_bytes());
    bytes.extend_from_slice(h.as_bytes());
    for v in row {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let dir = std::env::temp_dir().join(format!("graspath-optical-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("one.npy");
    std::fs::write(&path, bytes).unwrap();
    let world_from_link = Isometry3::new(Vector3::new(0.2, 0.0, 0.8), Vector3::zeros());
    let options = GraspFileOptions {
        object_from_frame: GraspFrame::Camera
            .object_from_frame(
                &Isometry3::identity(),
                Some(&(world_from_link * link_from_optical)),
                None,
            )
            .unwrap(),
        ..GraspFileOptions::default()
    };
    let (format, got) = read_grasp_file(&path, &options).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(format, GraspFormat::GraspNet);
    let t = got[0].object_from_wrist.translation.vector;
    assert!((t - Vector3::new(0.7, 0.0, 0.8)).norm() < 1e-12, "{t}");
    // GraspNet's approach (gripper x = optical x, here) becomes the tool z: the link's −y.
    let approach = got[0].object_from_wrist.rotation * Vector3::z();
    assert!((approach + Vector3::y()).norm() < 1e-12, "{approach}");
}
