//! The one shape vocabulary against main's outputs at commit a838571
//! (`tests/data/main-a838571/`, captured by main's own code; see its README): clouds sampled
//! from the old spellings are the same to the bit, a version 1 model file loads into the model
//! that training gives today and generates the same candidates to the byte.

use graspath::cloud::{
    load_cloud_argument, CloudShape, CloudSource, LegacyTShape, PointCloud, SampleOptions,
};
use graspath::geometry::shape::Shape;
use graspath::grasp::model::{
    candidates_json, generate, train_file, GenerateOptions, GraspModel, MODEL_FORMAT_VERSION,
};
use nalgebra::{Point3, Vector3};
use std::path::{Path, PathBuf};

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn reference(name: &str) -> PathBuf {
    crate_dir().join("tests/data/main-a838571").join(name)
}

/// FNV-1a over the little-endian bytes of every coordinate, points then normals (the same
/// definition as the capture program).
fn fnv(cloud: &PointCloud) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    let mut eat = |v: f64| {
        for b in v.to_bits().to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x100000001b3);
        }
    };
    for p in &cloud.points {
        p.coords.iter().for_each(|v| eat(*v));
    }
    for n in cloud.normals.iter().flatten() {
        n.iter().for_each(|v| eat(*v));
    }
    h
}

fn check_against(record: &serde_json::Value, cloud: &PointCloud) {
    let name = record["name"].as_str().unwrap();
    assert_eq!(
        cloud.len() as u64,
        record["count"].as_u64().unwrap(),
        "{name}"
    );
    let points: Vec<[f64; 3]> = serde_json::from_value(record["points"].clone()).unwrap();
    let normals: Vec<[f64; 3]> = serde_json::from_value(record["normals"].clone()).unwrap();
    for (k, (p, n)) in points.iter().zip(&normals).enumerate() {
        let now = cloud.points[k];
        let normal = cloud.normals.as_ref().unwrap()[k];
        for i in 0..3 {
            assert_eq!(now[i].to_bits(), p[i].to_bits(), "{name}: point {k}");
            assert_eq!(normal[i].to_bits(), n[i].to_bits(), "{name}: normal {k}");
        }
    }
    assert_eq!(
        format!("{:016x}", fnv(cloud)),
        record["fnv1a"].as_str().unwrap(),
        "{name}: the hash of every coordinate"
    );
}

#[test]
fn old_cloud_spellings_sample_main_clouds_to_the_bit() {
    let text = std::fs::read_to_string(reference("clouds.json")).unwrap();
    let records: Vec<serde_json::Value> = serde_json::from_str(&text).unwrap();
    assert_eq!(records.len(), 15);
    for record in &records {
        let name = record["name"].as_str().unwrap();
        let cloud = if let Some(file) = name.strip_prefix("examples/grasp/") {
            load_cloud_argument(&crate_dir().join("../../examples/grasp").join(file)).unwrap()
        } else {
            let source: CloudSource = serde_json::from_value(record["source"].clone()).unwrap();
            source.load(Path::new(".")).unwrap()
        };
        check_against(record, &cloud);
    }
}

#[test]
fn new_spellings_of_the_same_solids_give_the_same_clouds() {
    let text = std::fs::read_to_string(reference("clouds.json")).unwrap();
    let records: Vec<serde_json::Value> = serde_json::from_str(&text).unwrap();
    for record in &records {
        let name = record["name"].as_str().unwrap();
        let mut source = record["source"].clone();
        let Some(shape) = source.pointer_mut("/primitive/shape") else {
            continue;
        };
        // `length` for `height`; box and sphere are spelled alike; the upright T has no new
        // spelling in its own frame (it is the new T turned over, see below).
        if let Some(cylinder) = shape.get_mut("cylinder") {
            let height = cylinder["height"].take();
            *cylinder = serde_json::json!({"radius": cylinder["radius"], "length": height});
        } else if shape.get("t_shape").is_some() {
            continue;
        }
        let source: CloudSource = serde_json::from_value(source).unwrap();
        let CloudSource::Primitive {
            shape: CloudShape::Shape(shape),
            sampling,
        } = &source
        else {
            panic!("{name}: a shape");
        };
        check_against(
            record,
            &graspath::cloud::sample_shape(shape, sampling).unwrap(),
        );
    }
}

/// The upright T of earlier files is the new T turned over: every sampled point lies on the
/// surface of `to_shape()` placed at its pose, and each normal is that surface's gradient.
#[test]
fn the_upright_t_is_the_new_t_turned_over() {
    let legacy = LegacyTShape::new([0.04, 0.045, 0.1], [0.16, 0.045, 0.04]).unwrap();
    let (shape, object_from_shape) = legacy.to_shape();
    let cloud = legacy
        .sample(&SampleOptions {
            points: 3000,
            seed: 5,
            ..Default::default()
        })
        .unwrap();
    let sd = |p: &Point3<f64>| shape.signed_distance(&object_from_shape.inverse_transform_point(p));
    let h = 1e-7;
    for (p, n) in cloud.points.iter().zip(cloud.normals.as_ref().unwrap()) {
        assert!(sd(p).abs() < 1e-12, "{p}: {}", sd(p));
        // Outward: a step along the normal leaves the solid, a step back enters it.
        assert!(
            sd(&(p + n * h)) > 0.5 * h && sd(&(p - n * h)) < 0.0,
            "{p} {n}"
        );
    }
    // Same extent: the bounding boxes agree.
    let aabb = shape.aabb_at(&object_from_shape);
    let lo = cloud
        .points
        .iter()
        .fold(Vector3::repeat(f64::INFINITY), |m, p| m.inf(&p.coords));
    let hi = cloud
        .points
        .iter()
        .fold(Vector3::repeat(f64::NEG_INFINITY), |m, p| m.sup(&p.coords));
    assert!((aabb.min.coords - lo).norm() < 2e-3 && (aabb.max.coords - hi).norm() < 2e-3);
    assert!((aabb.min.z + 0.07).abs() < 1e-12 && (aabb.max.z - 0.07).abs() < 1e-12);
}

fn t_shape_options() -> GenerateOptions {
    GenerateOptions {
        initial_grasps: 3000,
        steps: 150,
        first_stage_steps: 30,
        query_kernels: 1500,
        seed: 7,
        ..GenerateOptions::default()
    }
}

#[test]
fn a_version_1_model_from_main_loads_as_todays_model_and_generates_the_same_bytes() {
    let v1 = GraspModel::read(&reference("model_v1.json")).unwrap();
    assert_eq!(v1.format_version, MODEL_FORMAT_VERSION);
    // Training today gives exactly the model main wrote, hand shapes converted exactly.
    let today = train_file(&crate_dir().join("../../examples/grasp/demo_box.json")).unwrap();
    assert_eq!(v1, today);
    // Written again, it is a version 2 file that reads back equal.
    let back = GraspModel::from_json(
        std::str::from_utf8(&v1.to_json().unwrap()).unwrap(),
        "v2.json",
    )
    .unwrap();
    assert_eq!(back, v1);
    let cloud =
        load_cloud_argument(&crate_dir().join("../../examples/grasp/t_shape.json")).unwrap();
    let candidates = generate(&v1, &cloud, &t_shape_options(), "t_shape.json", &|_| {}).unwrap();
    let bytes = candidates_json(&candidates[..candidates.len().min(30)], &v1.label).unwrap();
    let expected = std::fs::read(reference("generate_t_shape_seed7.json")).unwrap();
    assert!(bytes == expected, "generate output differs from main's");
}

#[test]
fn bad_version_1_hand_shapes_are_named() {
    let text = std::fs::read_to_string(reference("model_v1.json")).unwrap();
    let bad = text.replacen("{\"box\":{\"half\":[", "{\"box\":{\"half\":[-", 1);
    assert_ne!(bad, text);
    let err = GraspModel::from_json(&bad, "old.json")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("old.json")
            && err.contains("hand.links[0].shapes[0].shape")
            && err.contains("box.size[0]"),
        "{err}"
    );
    let bad = text.replacen("{\"box\":{\"half\":", "{\"box\":{\"halves\":", 1);
    let err = GraspModel::from_json(&bad, "old.json")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("hand.links[0].shapes[0].shape") && err.contains("half"),
        "{err}"
    );
}

#[test]
fn cloud_shape_spellings_and_errors() {
    let parse = |s: &str| serde_json::from_str::<CloudShape>(s);
    let old = parse(r#"{"cylinder": {"radius": 0.02, "height": 0.1}}"#).unwrap();
    let new = parse(r#"{"cylinder": {"radius": 0.02, "length": 0.1}}"#).unwrap();
    assert_eq!(old, new);
    assert_eq!(new, CloudShape::Shape(Shape::cylinder(0.02, 0.1).unwrap()));
    // Written back in today's spelling; the upright T in its own (the only one it has).
    assert_eq!(
        serde_json::to_string(&old).unwrap(),
        r#"{"cylinder":{"radius":0.02,"length":0.1}}"#
    );
    let t =
        parse(r#"{"t_shape": {"stem": [0.04, 0.045, 0.1], "bar": [0.16, 0.045, 0.04]}}"#).unwrap();
    assert!(matches!(t, CloudShape::LegacyT(_)));
    assert_eq!(parse(&serde_json::to_string(&t).unwrap()).unwrap(), t);
    let t = parse(r#"{"t_shape": {"bar": [0.16, 0.045, 0.04], "stem": {"box": {"size": [0.04, 0.045, 0.1]}}}}"#)
        .unwrap();
    assert!(matches!(t, CloudShape::Shape(Shape::TShape(_))));
    for (text, words) in [
        (
            r#"{"t_shape": {"stem": [0.04, -1, 0.1], "bar": [0.16, 0.045, 0.04]}}"#,
            &["t_shape.stem[1]", "positive"][..],
        ),
        (
            r#"{"t_shape": {"stem": [0.04, 0.1], "bar": [0.16, 0.045, 0.04]}}"#,
            &["t_shape.stem", "[x, y, z]"][..],
        ),
        (
            r#"{"t_shape": {"bar": [0.16, 0.045, 0.04]}}"#,
            &["missing field `stem`"][..],
        ),
        (
            r#"{"cylinder": {"radius": 0.02, "height": -0.1}}"#,
            &["cylinder.length", "positive"][..],
        ),
        (
            r#"{"cylinder": {"radius": 0.02, "height": 0.1, "length": 0.1}}"#,
            &["length"][..],
        ),
        (r#"{"cone": {"radius": 0.02}}"#, &["cone"][..]),
    ] {
        let err = parse(text).unwrap_err().to_string();
        assert!(words.iter().all(|w| err.contains(w)), "{text}: {err}");
    }
}
