//! Unit tests of the restricted pickle reader and the array limits (the formats themselves are
//! tested on files written by their generators' code in `tests/grasp_files.rs`).

use super::arrays::{parse_npy, read_npz, Member};
use super::pickle::{parse, Value};
use crate::spelling::Spelled;

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
    let all = |_: &str| true;
    let any = |_: &str, _: &npyz::NpyHeader| Ok(());
    assert!(read_npz(&npz, 1 << 20, &all, &any).is_ok());
    let (member, err) = read_npz(&npz, 100, &all, &any).unwrap_err();
    // Refused from the member's header, before its data are decompressed.
    assert_eq!(member, "grasps");
    assert!(
        err.contains("more than the archive may expand to (100 bytes)"),
        "{err}"
    );
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

/// A pickle that puts a list twice into the next one, 40 times, would decode to 2^40 copies:
/// refused by its budget, in far less time and memory than a copy of one level.
#[test]
fn a_memo_bomb_is_refused_by_the_decoding_budget() {
    let mut bytes = b"\x80\x02]q\x00".to_vec();
    for _ in 0..40 {
        bytes.extend_from_slice(b"(h\x00h\x00lq\x00");
    }
    bytes.push(b'.');
    let err = parse(&bytes).unwrap_err();
    assert!(err.contains("decodes to more than"), "{err}");
    // 16 levels (65,536 copies, a few MB with the memo's) stay within a small pickle's budget.
    let mut small = b"\x80\x02]q\x00".to_vec();
    for _ in 0..16 {
        small.extend_from_slice(b"(h\x00h\x00lq\x00");
    }
    small.push(b'.');
    assert!(matches!(parse(&small), Ok(Value::Seq(_))));
}

/// Nesting deeper than the limit is refused by every opcode that nests: MARK/LIST, APPEND,
/// TUPLE1, SETITEM, and memo copies of a deep value.
#[test]
fn deep_nesting_is_refused_by_every_nesting_opcode() {
    let n = 10_000;
    let cases: Vec<Vec<u8>> = vec![
        [&b"\x80\x02"[..], &b"(".repeat(n), &b"l".repeat(n), b"."].concat(),
        [&b"\x80\x02"[..], &b"]".repeat(n), &b"a".repeat(n - 1), b"."].concat(),
        [&b"\x80\x02N"[..], &b"\x85".repeat(n), b"."].concat(),
        [
            &b"\x80\x02}"[..],
            &b"K\x00}".repeat(n),
            &b"s".repeat(n),
            b".",
        ]
        .concat(),
    ];
    for bytes in cases {
        let err = parse(&bytes).unwrap_err();
        assert!(err.contains("more than 64 deep"), "{err}");
    }
    // 64 deep is read.
    let ok = [&b"\x80\x02"[..], &b"]".repeat(64), &b"a".repeat(63), b"."].concat();
    assert!(parse(&ok).is_ok());
}

/// Dtypes that are not real numbers of 1–8 bytes are refused by name, never read as something
/// else and never a panic: empty, sizeless, complex, long double, half, multibyte, huge sizes.
#[test]
fn pickled_dtypes_that_are_not_real_numbers_are_refused() {
    use super::pickle::number_type;
    for (t, want) in [
        ("", "is not a number type"),
        ("f0", "is not a number type"),
        ("<", "is not a number type"),
        ("é8", "is not a number type"),
        ("f99999999999999999999999", "is not a number type"),
        ("c16", "complex numbers"),
        ("<c8", "complex numbers"),
        ("<f16", "long doubles"),
        ("g", "long doubles"),
        ("f2", "half floats"),
        ("U5", "is not a number type"),
    ] {
        let err = number_type(t).unwrap_err();
        assert!(err.contains(want), "{t}: {err}");
    }
    assert_eq!(number_type("<f8"), Ok(('f', 8)));
    assert_eq!(number_type("|u1"), Ok(('u', 1)));
    assert_eq!(number_type(">i2"), Ok(('i', 2)));
}

/// `.npy` headers are checked before npyz reads them: a declared length past the bytes present
/// or the cap, brackets nested too deep, a shape whose element count overflows.
#[test]
fn npy_headers_are_checked_before_they_are_read() {
    let err = parse_npy(b"\x93NUMPY\x02\x00\xff\xff\xff\xff{").unwrap_err();
    assert!(
        err.contains("declares 4294967295 bytes; more than 65536"),
        "{err}"
    );
    let err = parse_npy(b"\x93NUMPY\x01\x00\x00\x01{'descr'").unwrap_err();
    assert!(
        err.contains("declares 256 bytes but only 8 follow"),
        "{err}"
    );
    let nested = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': {}1{}, }}",
        "(".repeat(40),
        ")".repeat(40)
    );
    let err = parse_npy(&npy_preamble(&nested)).unwrap_err();
    assert!(err.contains("nests brackets more than 16 deep"), "{err}");
    let overflow =
        "{'descr': '<f8', 'fortran_order': False, 'shape': (4294967296, 4294967296, 16), }";
    let err = parse_npy(&npy_preamble(overflow)).unwrap_err();
    assert!(err.contains("more elements than can be counted"), "{err}");
    // The shape npyz reads, however it is spelled: a repeated key (the last counts), dimensions
    // in hexadecimal or with underscores (a fuzz finding: npyz's element count overflowed).
    for shape in [
        "'shape': (1,), 'shape': (4294967296, 4294967296, 16)",
        "'shape': (0x100000000, 0x100000000, 16)",
        "\"shape\": [4_294_967_296, 4_294_967_296, 16]",
    ] {
        let header = format!("{{'descr': '<f8', 'fortran_order': False, {shape}, }}");
        match parse_npy(&npy_preamble(&header)) {
            Err(err) => assert!(
                err.contains("more elements than can be counted") || err.contains("not a NumPy"),
                "{shape}: {err}"
            ),
            Ok(_) => panic!("{shape}: read"),
        }
    }
    let complex = "{'descr': '<c16', 'fortran_order': False, 'shape': (1,), }";
    let mut bytes = npy_preamble(complex);
    bytes.extend_from_slice(&[0; 16]);
    let err = parse_npy(&bytes).unwrap_err();
    assert!(err.contains("complex numbers"), "{err}");
}

/// A pickled Fortran-ordered array is read by its order, as a `.npy` one is.
#[test]
fn a_pickled_fortran_array_is_read_in_c_order() {
    // _reconstruct(ndarray, (0,), b'b') then BUILD with (1, (2, 3), dtype('<f8'), True, data).
    let mut bytes = b"\x80\x02cnumpy.core.multiarray\n_reconstruct\ncnumpy\nndarray\nK\x00\x85C\x01b\x87R(K\x01K\x02K\x03\x86cnumpy\ndtype\nX\x02\x00\x00\x00f8\x89\x88\x87R(K\x03X\x01\x00\x00\x00<NNNJ\xff\xff\xff\xffJ\xff\xff\xff\xffK\x00tb\x88B\x30\x00\x00\x00".to_vec();
    for v in [0.0f64, 3.0, 1.0, 4.0, 2.0, 5.0] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    bytes.extend_from_slice(b"tb.");
    let Value::Array(a) = parse(&bytes).unwrap() else {
        panic!("not an array")
    };
    assert_eq!(a.shape, vec![2, 3]);
    assert_eq!(a.data, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
}
