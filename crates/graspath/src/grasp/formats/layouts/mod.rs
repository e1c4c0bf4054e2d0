//! The readers of each layout (`docs/grasp-files.md`): every grasp as the file gives it, in
//! the file's frame and the generator's gripper frame, with where it is in the file.

use super::array::Array;
use super::arrays::{npy_header, parse_npy, read_npz, Member};
use super::{hdf5, npz_limit, pickle, Grasp, GraspFormat};
use crate::geometry::pose_from_rows;
use nalgebra::{Isometry3, Point3};
use std::path::Path;

mod segmented;

pub(super) use segmented::contact_graspnet;

type Grasps = Result<Vec<Grasp>, (String, String)>;

/// Refuses `count` grasps in `field` beyond `max` (the task's `limits.max_candidates`).
fn check_count(field: &str, count: u64, max: Option<usize>) -> Result<(), (String, String)> {
    match max {
        Some(max) if count > max as u64 => Err((
            field.to_string(),
            format!(
                "declares {count} grasps, more than the limit {max}; raise limits.max_candidates \
                 if this is intended"
            ),
        )),
        _ => Ok(()),
    }
}

/// The grasps an array of `shape` holds when it is one of `layouts` (`[None, 4, 4]`: poses;
/// a leading `None` is a count), `None` when it is none of them.
fn grasp_rows(shape: &[u64], layouts: &[&[Option<u64>]]) -> Option<u64> {
    layouts.iter().find_map(|want| {
        (shape.len() == want.len()
            && shape
                .iter()
                .zip(want.iter())
                .all(|(d, w)| w.is_none_or(|w| *d == w)))
        .then(|| {
            shape
                .iter()
                .zip(want.iter())
                .filter(|(_, w)| w.is_none())
                .fold(1u64, |n, (d, _)| n.saturating_mul(*d))
        })
    })
}

/// N×4×4 poses.
const POSES: &[Option<u64>] = &[None, Some(4), Some(4)];
/// K×N×4×4 poses (M2T2's list of objects of equal grasp counts).
const STACKED_POSES: &[Option<u64>] = &[None, None, Some(4), Some(4)];
/// N×17 GraspNet grasps.
const GRASPNET: &[Option<u64>] = &[None, Some(17)];

/// Arrays by segment or object (Contact-GraspNet, M2T2).
type Segments = Vec<(Key, Array)>;

/// Which segment of a Contact-GraspNet / M2T2 file an array belongs to.
#[derive(Debug, Clone, PartialEq)]
enum Key {
    /// A plain array: the whole file is one segment.
    Whole,
    /// A dictionary's whole-number key: Contact-GraspNet's segment id (−1 without a
    /// segmentation).
    Segment(i64),
    /// A position in a per-object list (M2T2's outputs are lists, one entry per object).
    Object(usize),
    /// A dictionary's text key: an object's name.
    Named(String),
}

impl Key {
    /// The index written after a field name: `[3]`, `['mug']`, or nothing for a whole array.
    fn index(&self) -> String {
        match self {
            Self::Whole => String::new(),
            Self::Segment(s) => format!("[{s}]"),
            Self::Object(k) => format!("[{k}]"),
            Self::Named(n) => format!("['{}']", super::excerpt(n.as_bytes(), 40)),
        }
    }

    /// The candidate label of grasp `i` of this segment.
    fn label(&self, i: usize) -> String {
        match self {
            Self::Whole => format!("grasp {i}"),
            Self::Segment(s) => format!("segment {s} grasp {i}"),
            Self::Object(k) => format!("object {k} grasp {i}"),
            Self::Named(n) => format!("{} grasp {i}", super::excerpt(n.as_bytes(), 40)),
        }
    }

    /// The number `segment:` selects this segment by (−1 for a whole array, as
    /// Contact-GraspNet's unsegmented key); none for a named object.
    fn number(&self) -> Option<i64> {
        match self {
            Self::Whole => Some(-1),
            Self::Segment(s) => Some(*s),
            Self::Object(k) => i64::try_from(*k).ok(),
            Self::Named(_) => None,
        }
    }
}

/// A pose from 16 row-major numbers; errors name the location.
fn pose16(values: &[f64], location: &str) -> Result<Isometry3<f64>, (String, String)> {
    let rows: [[f64; 4]; 4] = std::array::from_fn(|i| std::array::from_fn(|j| values[4 * i + j]));
    pose_from_rows(&rows).map_err(|e| (location.to_string(), e.to_string()))
}

/// Checks an array's shape against `want` (`None` = any length); the error names `field`.
fn expect_shape(
    a: &Array,
    want: &[Option<usize>],
    field: &str,
    what: &str,
) -> Result<(), (String, String)> {
    let ok = a.shape.len() == want.len()
        && a.shape
            .iter()
            .zip(want)
            .all(|(d, w)| w.is_none_or(|w| *d == w));
    if ok {
        Ok(())
    } else {
        Err((
            field.to_string(),
            format!("has shape {}, expected {what}", a.shape_text()),
        ))
    }
}

fn pose_grasps(
    transforms: &Array,
    field: &str,
    scores: Option<(&Array, &str)>,
    widths: Option<(&Array, &str)>,
) -> Grasps {
    expect_shape(transforms, &[None, Some(4), Some(4)], field, "(N, 4, 4)")?;
    let n = transforms.shape[0];
    if transforms.data.len() != 16 * n {
        return Err((
            field.to_string(),
            "holds fewer values than its shape declares".into(),
        ));
    }
    for (a, name) in scores.iter().chain(widths.iter()) {
        expect_shape(
            a,
            &[Some(n)],
            name,
            &format!("({n},), one per grasp in {field}"),
        )?;
    }
    (0..n)
        .map(|i| {
            let location = format!("{field}[{i}]");
            Ok(Grasp {
                frame_from_gripper: pose16(&transforms.data[16 * i..16 * i + 16], &location)?,
                id: i,
                label: format!("grasp {i}"),
                score: scores.map(|(s, _)| s.data[i]),
                width: widths.map(|(w, _)| w.data[i]),
                contact: None,
                location,
            })
        })
        .collect()
}

pub(super) fn acronym_h5(bytes: Vec<u8>, max: Option<usize>) -> Grasps {
    const T: &str = "grasps/transforms";
    const Q: &str = "grasps/qualities/flex/object_in_gripper";
    // Both datasets hold one entry per grasp: their first dimension is the count.
    let check =
        |name: &str, shape: &[u64]| check_count(name, shape.first().copied().unwrap_or(1), max);
    let mut found = hdf5::read_datasets(bytes, &[T, Q], &check)?.into_iter();
    let transforms = found.next().flatten().ok_or_else(|| {
        (
            T.to_string(),
            "dataset missing (an ACRONYM grasp file has it)".to_string(),
        )
    })?;
    let quality = found.next().flatten();
    pose_grasps(&transforms, T, quality.as_ref().map(|q| (q, Q)), None)
}

fn array_from_json(value: &serde_json::Value, field: &str) -> Result<Array, (String, String)> {
    // Nested lists of numbers (booleans as 0/1), rectangular: every number at the same depth,
    // every list at one depth as long as the others.
    fn walk(
        v: &serde_json::Value,
        depth: usize,
        shape: &mut Vec<usize>,
        leaf_depth: &mut Option<usize>,
        out: &mut Vec<f64>,
    ) -> Result<(), String> {
        let ragged = || "the nested lists are not rectangular".to_string();
        let mut leaf = |x: f64, leaf_depth: &mut Option<usize>| {
            if *leaf_depth.get_or_insert(depth) != depth || shape.len() != depth {
                return Err(ragged());
            }
            out.push(x);
            Ok(())
        };
        match v {
            serde_json::Value::Array(items) => {
                if leaf_depth.is_some_and(|d| depth >= d) {
                    return Err(ragged());
                }
                if shape.len() == depth {
                    shape.push(items.len());
                } else if shape.get(depth) != Some(&items.len()) {
                    return Err(ragged());
                }
                items
                    .iter()
                    .try_for_each(|x| walk(x, depth + 1, shape, leaf_depth, out))
            }
            serde_json::Value::Number(n) => leaf(n.as_f64().unwrap_or(f64::NAN), leaf_depth),
            serde_json::Value::Bool(b) => leaf(if *b { 1.0 } else { 0.0 }, leaf_depth),
            _ => Err("expected nested lists of numbers".into()),
        }
    }
    let mut shape = Vec::new();
    let mut data = Vec::new();
    walk(value, 0, &mut shape, &mut None, &mut data).map_err(|m| (field.to_string(), m))?;
    // Lists that end empty before any number leave the shape shorter than it looks: what
    // was read is all there is.
    if shape.iter().product::<usize>() != data.len() {
        return Err((
            field.to_string(),
            "the nested lists are not rectangular".into(),
        ));
    }
    Ok(Array { shape, data })
}

/// The largest grasp file read as JSON or YAML text (bytes): its parsed value takes up to
/// about 30 times its size.
pub(crate) const MAX_TEXT_BYTES: usize = 32 << 20;

pub(super) fn text_grasps(format: GraspFormat, bytes: &[u8], max: Option<usize>) -> Grasps {
    if bytes.len() > MAX_TEXT_BYTES {
        return Err((
            "file".into(),
            format!(
                "is {} bytes of JSON or YAML text; more than {MAX_TEXT_BYTES} is refused (save \
                 large grasp sets as .npy or .h5)",
                bytes.len()
            ),
        ));
    }
    let text = std::str::from_utf8(bytes)
        .map_err(|_| ("file".to_string(), "not UTF-8 text".to_string()))?;
    let value: serde_json::Value = serde_json::from_str(text)
        .or_else(|_| serde_saphyr::from_str(text))
        .map_err(|e| ("file".to_string(), format!("not JSON or YAML: {e}")))?;
    let get = |pointer: &str| value.pointer(pointer);
    if let Some(grasps) = get("/grasps").filter(|g| g.is_object() && g.get("transforms").is_none())
    {
        // GraspGen's Isaac grasp YAML: grasps.<name>.{confidence, position, orientation}.
        if let Some(f) = value.get("format").and_then(|f| f.as_str()) {
            if f != "isaac_grasp" {
                return Err((
                    "format".into(),
                    format!("expected 'isaac_grasp', got '{f}'"),
                ));
            }
        }
        // GraspGen names its grasps `grasp_<i>` in order; the id is that `i` (the keys are
        // sorted by it, as the map does not keep the file's order), else the rank by name.
        let mut map = grasps
            .as_object()
            .map(|m| m.iter().collect::<Vec<_>>())
            .unwrap_or_default();
        check_count("grasps", map.len() as u64, max)?;
        let number = |name: &str| {
            name.rsplit('_')
                .next()
                .and_then(|n| n.parse::<usize>().ok())
        };
        map.sort_by_key(|(name, _)| (number(name), name.to_string()));
        let numbered = {
            let mut seen = std::collections::HashSet::new();
            map.iter()
                .all(|(name, _)| number(name).is_some_and(|n| seen.insert(n)))
        };
        return map
            .into_iter()
            .enumerate()
            .map(|(rank, (name, g))| {
                let i = if numbered {
                    number(name).unwrap_or(rank)
                } else {
                    rank
                };
                let location = format!("grasps.{name}");
                let err = |field: &str, m: String| (format!("{location}.{field}"), m);
                let numbers = |v: Option<&serde_json::Value>,
                               n: usize,
                               field: &str|
                 -> Result<Vec<f64>, (String, String)> {
                    let a = v
                        .and_then(|v| v.as_array())
                        .filter(|a| a.len() == n)
                        .ok_or_else(|| err(field, format!("expected a list of {n} numbers")))?;
                    a.iter()
                        .map(|x| {
                            x.as_f64()
                                .ok_or_else(|| err(field, "expected numbers".into()))
                        })
                        .collect()
                };
                let p = numbers(g.get("position"), 3, "position")?;
                let xyz = numbers(g.pointer("/orientation/xyz"), 3, "orientation.xyz")?;
                let w = g
                    .pointer("/orientation/w")
                    .and_then(serde_json::Value::as_f64)
                    .ok_or_else(|| err("orientation.w", "expected a number".into()))?;
                let confidence = g
                    .get("confidence")
                    .and_then(serde_json::Value::as_f64)
                    .ok_or_else(|| err("confidence", "expected a number".into()))?;
                let spec = crate::geometry::PoseSpec {
                    xyz: Some([p[0], p[1], p[2]]),
                    quaternion: Some([xyz[0], xyz[1], xyz[2], w]),
                    ..Default::default()
                };
                let pose = spec.to_isometry().map_err(|e| {
                    err(
                        if e.field == "xyz" {
                            "position"
                        } else {
                            "orientation"
                        },
                        e.message,
                    )
                })?;
                Ok(Grasp {
                    location,
                    id: i,
                    label: name.clone(),
                    frame_from_gripper: pose,
                    score: Some(confidence),
                    width: None,
                    contact: None,
                })
            })
            .collect();
    }
    // The dataset JSON of GraspGen (grasps.transforms, grasps.object_in_gripper) or ACRONYM
    // (transforms, quality_flex_object_in_gripper).
    let (t_field, q_field, t, q) = if let Some(t) = get("/grasps/transforms") {
        (
            "grasps.transforms",
            "grasps.object_in_gripper",
            t,
            get("/grasps/object_in_gripper"),
        )
    } else if let Some(t) = get("/transforms") {
        (
            "transforms",
            "quality_flex_object_in_gripper",
            t,
            get("/quality_flex_object_in_gripper"),
        )
    } else {
        let want = if format == GraspFormat::Acronym {
            "transforms"
        } else {
            "grasps"
        };
        return Err((want.into(), "missing (no grasp poses in this file)".into()));
    };
    check_count(t_field, t.as_array().map_or(0, |a| a.len() as u64), max)?;
    let transforms = array_from_json(t, t_field)?;
    let quality = q.map(|q| array_from_json(q, q_field)).transpose()?;
    pose_grasps(
        &transforms,
        t_field,
        quality.as_ref().map(|q| (q, q_field)),
        None,
    )
}

/// The numeric members of an `.npz`, or the one array of a `.npy`, by name. Before the values
/// of an array shaped as one of `layouts` are read, its grasp count is checked against `max`.
fn numeric_members(
    path: &Path,
    bytes: &[u8],
    layouts: &[&[Option<u64>]],
    max: Option<usize>,
) -> Result<Vec<(String, Member)>, (String, String)> {
    let check = |key: &str, header: &npyz::NpyHeader| match grasp_rows(header.shape(), layouts) {
        Some(rows) => check_count(key, rows, max).map_err(|(_, m)| m),
        None => Ok(()),
    };
    if bytes.starts_with(b"\x93NUMPY") {
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let (header, _) = npy_header(bytes).map_err(|m| ("file".to_string(), m))?;
        check(&name, &header).map_err(|m| (name.clone(), m))?;
        return Ok(vec![(
            name,
            parse_npy(bytes).map_err(|m| ("file".to_string(), m))?,
        )]);
    }
    read_npz(
        bytes,
        npz_limit(bytes),
        &super::arrays::every_member,
        &check,
    )?
    .into_iter()
    .map(|(k, data)| {
        let member = parse_npy(&data).map_err(|m| (k.clone(), m))?;
        Ok((k, member))
    })
    .collect()
}

fn numeric<'a>(
    members: &'a [(String, Member)],
    key: &str,
) -> Result<Option<&'a Array>, (String, String)> {
    match members.iter().find(|(k, _)| k == key) {
        None => Ok(None),
        Some((_, Member::Numeric(a))) => Ok(Some(a)),
        Some((_, Member::Object(_))) => {
            Err((key.into(), "holds Python objects, expected numbers".into()))
        }
    }
}

pub(super) fn poses(path: &Path, bytes: &[u8], max: Option<usize>) -> Grasps {
    let members = numeric_members(path, bytes, &[POSES], max)?;
    let candidates: Vec<&(String, Member)> = members
        .iter()
        .filter(|(_, m)| matches!(m, Member::Numeric(a) if a.shape.len() == 3 && a.shape[1..] == [4, 4]))
        .collect();
    let (key, transforms) = match candidates.as_slice() {
        [(k, Member::Numeric(a))] => (k.clone(), a),
        [] => {
            let described: Vec<String> = members
                .iter()
                .map(|(k, m)| match m {
                    Member::Numeric(a) => format!("{k} {}", a.shape_text()),
                    Member::Object(_) => format!("{k} (objects)"),
                })
                .collect();
            let field = members
                .first()
                .map_or("file".to_string(), |(k, _)| k.clone());
            return Err((
                field,
                format!("no N×4×4 array of poses (found: {})", described.join(", ")),
            ));
        }
        _ => {
            return Err((
                "file".into(),
                "several N×4×4 arrays; keep one per file".into(),
            ))
        }
    };
    let scores = numeric(&members, "scores")?;
    let widths = numeric(&members, "widths")?;
    pose_grasps(
        transforms,
        &key,
        scores.map(|s| (s, "scores")),
        widths.map(|w| (w, "widths")),
    )
}

pub(super) fn graspnet(path: &Path, bytes: &[u8], max: Option<usize>) -> Grasps {
    let members = numeric_members(path, bytes, &[GRASPNET], max)?;
    let (key, a) = match members.as_slice() {
        [(k, Member::Numeric(a))] => (k.clone(), a),
        _ => {
            let found: Vec<&(String, Member)> = members
                .iter()
                .filter(|(_, m)| matches!(m, Member::Numeric(a) if a.shape.len() == 2 && a.shape[1] == 17))
                .collect();
            match found.as_slice() {
                [(k, Member::Numeric(a))] => (k.clone(), a),
                _ => {
                    return Err((
                        "file".into(),
                        "expected exactly one N×17 GraspNet array".into(),
                    ))
                }
            }
        }
    };
    expect_shape(
        a,
        &[None, Some(17)],
        &key,
        "(N, 17): score, width, height, depth, rotation (9), translation (3), object id",
    )?;
    if a.data.len() != 17 * a.shape[0] {
        return Err((key, "holds fewer values than its shape declares".into()));
    }
    (0..a.shape[0])
        .map(|i| {
            let r = &a.data[17 * i..17 * i + 17];
            let location = format!("{key}[{i}]");
            let rows = [
                [r[4], r[5], r[6], r[13]],
                [r[7], r[8], r[9], r[14]],
                [r[10], r[11], r[12], r[15]],
                [0.0, 0.0, 0.0, 1.0],
            ];
            let pose = pose_from_rows(&rows)
                .map_err(|e| (format!("{location} (rotation, translation)"), e.to_string()))?;
            let object = r[16];
            Ok(Grasp {
                location,
                id: i,
                label: if object >= 0.0 {
                    format!("grasp {i} (object {object})")
                } else {
                    format!("grasp {i}")
                },
                frame_from_gripper: pose,
                score: Some(r[0]),
                width: Some(r[1]),
                contact: None,
            })
        })
        .collect()
}
