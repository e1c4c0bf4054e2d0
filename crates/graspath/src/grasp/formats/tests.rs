//! Unit tests of the restricted pickle reader and the array limits (the formats themselves are
//! tested on files written by their generators' code in `tests/grasp_files.rs`).

use super::arrays::{parse_npy, read_npz, Member};
use super::pickle::{parse, Value};

/// A protocol-2 pickle calling `os.system("ls")`: refused by name, nothing run.
#[test]
fn a_pickle_calling_anything_but_numpy_is_refused_by_name() {
    let bytes = b"\x80\x02cos\nsystem\nq\x00X\x02\x00\x00\x00lsq\x01\x85q\x02Rq\x03.";
    let err = parse(bytes).unwrap_err();
    assert!(err.contains("os.system"), "{err}");
}

/// A BINBYTES length beyond the input is refused before allocating.
#[test]
fn a_pickle_length_beyond_the_input_is_refused() {
    let bytes = b"\x80\x03B\xff\xff\xff\x7fabc.";
    let err = parse(bytes).unwrap_err();
    assert!(err.contains("declares 2147483647 bytes"), "{err}");
}

/// Plain containers decode as Python builds them: `{1: [2.5, True], -1: (None, 'x')}`
/// (protocol 2, as `pickle.dumps(..., protocol=2)` writes it).
#[test]
fn plain_containers_decode() {
    let bytes = b"\x80\x02}q\x00(K\x01]q\x01(G@\x04\x00\x00\x00\x00\x00\x00\x88eJ\xff\xff\xff\xffNX\x01\x00\x00\x00xq\x02\x86q\x03u.";
    let value = parse(bytes).unwrap();
    let expected = Value::Dict(vec![
        (
            Value::Int(1),
            Value::Seq(vec![Value::Float(2.5), Value::Bool(true)]),
        ),
        (
            Value::Int(-1),
            Value::Seq(vec![Value::None, Value::Str("x".into())]),
        ),
    ]);
    assert_eq!(value, expected);
}

/// A Fortran-order `.npy` (NumPy writes one for a transposed array) is read in C order.
#[test]
fn a_fortran_order_npy_is_read_in_c_order() {
    // np.save of np.asfortranarray([[0., 1., 2.], [3., 4., 5.]]).
    let header = "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3), }";
    let mut bytes = npy_preamble(header);
    for v in [0.0f64, 3.0, 1.0, 4.0, 2.0, 5.0] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let Member::Numeric(a) = parse_npy(&bytes).unwrap() else {
        panic!("not numeric")
    };
    assert_eq!(a.shape, vec![2, 3]);
    assert_eq!(a.data, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
}

/// An archive is read through its limit: one that would expand past it is refused.
#[test]
fn an_npz_expanding_past_its_limit_is_refused() {
    let npz = std::fs::read(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/grasp_files/poses.npz"),
    )
    .unwrap();
    assert!(read_npz(&npz, 1 << 20).is_ok());
    let err = read_npz(&npz, 100).unwrap_err();
    assert!(err.contains("expands to more than 100 bytes"), "{err}");
}

fn npy_preamble(header: &str) -> Vec<u8> {
    let mut h = header.to_string();
    while !(10 + h.len() + 1).is_multiple_of(64) {
        h.push(' ');
    }
    h.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(h.len() as u16).to_le_bytes());
    bytes.extend_from_slice(h.as_bytes());
    bytes
}

/// The frames of a grasp file placed in the object frame: a point given in the camera (or
/// world) frame lands where the hand-composed transforms put it.
#[test]
fn grasp_frames_are_placed_by_the_given_camera_or_world_pose() {
    use super::GraspFrame;
    use nalgebra::{Isometry3, Point3, Vector3};
    let world_from_object = Isometry3::new(Vector3::new(0.4, -0.2, 0.1), Vector3::z() * 0.7);
    let world_from_camera =
        Isometry3::new(Vector3::new(1.0, 0.5, 1.2), Vector3::new(2.0, 0.3, -0.4));
    let p_camera = Point3::new(0.01, 0.02, 0.6);
    // In the world: world_from_camera · p; in the object frame: world_from_object⁻¹ of that.
    let expected = world_from_object.inverse_transform_point(&(world_from_camera * p_camera));
    let by_world = GraspFrame::Camera
        .object_from_frame(&world_from_object, Some(&world_from_camera), None)
        .unwrap();
    assert!((by_world * p_camera - expected).norm() < 1e-12);
    let camera_from_object = world_from_camera.inverse() * world_from_object;
    let by_camera = GraspFrame::Camera
        .object_from_frame(&Isometry3::identity(), None, Some(&camera_from_object))
        .unwrap();
    assert!((by_camera * p_camera - expected).norm() < 1e-12);
    let p_world = Point3::new(0.3, 0.1, 0.9);
    let world = GraspFrame::World
        .object_from_frame(&world_from_object, None, None)
        .unwrap();
    assert!((world_from_object * (world * p_world) - p_world).norm() < 1e-12);
    let object = GraspFrame::Object
        .object_from_frame(&world_from_object, None, None)
        .unwrap();
    assert_eq!(object, Isometry3::identity());
    let both = GraspFrame::Camera
        .object_from_frame(
            &world_from_object,
            Some(&world_from_camera),
            Some(&camera_from_object),
        )
        .unwrap_err();
    assert_eq!(both.field, "camera_from_object");
    let missing = GraspFrame::Camera
        .object_from_frame(&world_from_object, None, None)
        .unwrap_err();
    assert_eq!(missing.field, "frame");
    let stray = GraspFrame::Object
        .object_from_frame(&world_from_object, Some(&world_from_camera), None)
        .unwrap_err();
    assert_eq!(stray.field, "frame");
    assert_eq!(GraspFrame::from_name("camera"), Some(GraspFrame::Camera));
    assert_eq!(GraspFrame::from_name("tool"), None);
}
