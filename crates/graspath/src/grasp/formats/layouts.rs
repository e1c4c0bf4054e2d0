//! The readers of each layout (`docs/grasp-files.md`): every grasp as the file gives it, in
//! the file's frame and the generator's gripper frame, with where it is in the file.

use super::array::Array;
use super::arrays::{parse_npy, read_npz, Member};
use super::{hdf5, npz_limit, pickle, Grasp, GraspFormat};
use crate::geometry::pose_from_rows;
use nalgebra::{Isometry3, Point3};
use std::path::Path;

type Grasps = Result<Vec<Grasp>, (String, String)>;

/// Arrays by segment id (Contact-GraspNet).
type Segments = Vec<(i64, Array)>;

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

pub(super) fn acronym_h5(bytes: Vec<u8>) -> Grasps {
    const T: &str = "grasps/transforms";
    const Q: &str = "grasps/qualities/flex/object_in_gripper";
    let mut found = hdf5::read_datasets(bytes, &[T, Q])?.into_iter();
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
    // Nested lists of numbers (booleans as 0/1), rectangular.
    fn walk(
        v: &serde_json::Value,
        depth: usize,
        shape: &mut Vec<usize>,
        out: &mut Vec<f64>,
    ) -> Result<(), String> {
        match v {
            serde_json::Value::Array(items) => {
                if shape.len() == depth {
                    shape.push(items.len());
                } else if shape.get(depth) != Some(&items.len()) {
                    return Err("the nested lists are not rectangular".into());
                }
                items
                    .iter()
                    .try_for_each(|x| walk(x, depth + 1, shape, out))
            }
            serde_json::Value::Number(n) if shape.len() == depth => {
                out.push(n.as_f64().unwrap_or(f64::NAN));
                Ok(())
            }
            serde_json::Value::Bool(b) if shape.len() == depth => {
                out.push(if *b { 1.0 } else { 0.0 });
                Ok(())
            }
            _ => Err("expected nested lists of numbers".into()),
        }
    }
    let mut shape = Vec::new();
    let mut data = Vec::new();
    walk(value, 0, &mut shape, &mut data).map_err(|m| (field.to_string(), m))?;
    Ok(Array { shape, data })
}

pub(super) fn text_grasps(format: GraspFormat, bytes: &[u8]) -> Grasps {
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
    let transforms = array_from_json(t, t_field)?;
    let quality = q.map(|q| array_from_json(q, q_field)).transpose()?;
    pose_grasps(
        &transforms,
        t_field,
        quality.as_ref().map(|q| (q, q_field)),
        None,
    )
}

/// The numeric members of an `.npz`, or the one array of a `.npy`, by name.
fn numeric_members(path: &Path, bytes: &[u8]) -> Result<Vec<(String, Member)>, (String, String)> {
    if bytes.starts_with(b"\x93NUMPY") {
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        return Ok(vec![(
            name,
            parse_npy(bytes).map_err(|m| ("file".to_string(), m))?,
        )]);
    }
    read_npz(bytes, npz_limit(bytes))
        .map_err(|m| ("file".to_string(), m))?
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

pub(super) fn poses(path: &Path, bytes: &[u8]) -> Grasps {
    let members = numeric_members(path, bytes)?;
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

pub(super) fn graspnet(path: &Path, bytes: &[u8]) -> Grasps {
    let members = numeric_members(path, bytes)?;
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

/// Contact-GraspNet / M2T2: `pred_grasps_cam`, `scores`, `contact_pts`, each either a pickled
/// dictionary `{segment: array}` (what `np.savez` writes for the dictionaries of
/// `inference.py`) or a plain array.
pub(super) fn contact_graspnet(bytes: &[u8], segment: Option<i64>) -> Grasps {
    const P: &str = "pred_grasps_cam";
    let members: Vec<(String, Member)> = read_npz(bytes, npz_limit(bytes))
        .map_err(|m| ("file".to_string(), m))?
        .into_iter()
        .filter(|(k, _)| [P, "scores", "contact_pts", "gripper_openings"].contains(&k.as_str()))
        .map(|(k, data)| {
            let member = parse_npy(&data).map_err(|m| (k.clone(), m))?;
            Ok((k, member))
        })
        .collect::<Result<_, (String, String)>>()?;
    let segments = |key: &str| -> Result<Option<Segments>, (String, String)> {
        let Some((_, member)) = members.iter().find(|(k, _)| k == key) else {
            return Ok(None);
        };
        Ok(Some(match member {
            Member::Numeric(a) => vec![(-1, a.clone())],
            Member::Object(v) => by_segment(v, key)?,
        }))
    };
    let poses = segments(P)?.ok_or_else(|| {
        (
            P.to_string(),
            "missing (a Contact-GraspNet result has it)".to_string(),
        )
    })?;
    let scores = segments("scores")?;
    let contacts = segments("contact_pts")?;
    let openings = segments("gripper_openings")?;
    let mut out = Vec::new();
    let mut row = 0usize;
    let mut any_segment = false;
    for (seg, transforms) in &poses {
        if segment.is_some_and(|s| s != *seg) {
            continue;
        }
        any_segment = true;
        let field = if *seg == -1 && poses.len() == 1 {
            P.to_string()
        } else {
            format!("{P}[{seg}]")
        };
        let n = transforms.shape.first().copied().unwrap_or(0);
        let companion = |list: &Option<Segments>,
                         name: &str,
                         tail: &[Option<usize>],
                         what: &str|
         -> Result<Option<Array>, (String, String)> {
            match find(list, *seg) {
                None => Ok(None),
                Some(None) => Err((
                    name.to_string(),
                    format!("has no segment {seg} (pred_grasps_cam has)"),
                )),
                Some(Some(a)) => {
                    let mut want = vec![Some(n)];
                    want.extend_from_slice(tail);
                    let a = if a.shape.len() == 2 && tail.is_empty() && a.shape[1] == 1 {
                        Array {
                            shape: vec![a.shape[0]],
                            data: a.data.clone(),
                        }
                    } else {
                        a.clone()
                    };
                    expect_shape(&a, &want, name, what)?;
                    Ok(Some(a))
                }
            }
        };
        let s = companion(&scores, "scores", &[], &format!("({n},)"))?;
        let c = companion(&contacts, "contact_pts", &[Some(3)], &format!("({n}, 3)"))?;
        let w = companion(&openings, "gripper_openings", &[], &format!("({n},)"))?;
        let grasps = pose_grasps(transforms, &field, None, None)?;
        for (i, mut g) in grasps.into_iter().enumerate() {
            g.id = row;
            g.label = if *seg == -1 {
                format!("grasp {i}")
            } else {
                format!("segment {seg} grasp {i}")
            };
            g.score = s.as_ref().map(|s| s.data[i]);
            g.width = w.as_ref().map(|w| w.data[i]);
            g.contact = c
                .as_ref()
                .map(|c| Point3::new(c.data[3 * i], c.data[3 * i + 1], c.data[3 * i + 2]));
            if let Some(p) = g.contact {
                if !p.coords.iter().all(|v| v.is_finite()) {
                    return Err((format!("contact_pts[{seg}][{i}]"), "not finite".into()));
                }
            }
            row += 1;
            out.push(g);
        }
    }
    if !any_segment {
        let have: Vec<String> = poses.iter().map(|(s, _)| s.to_string()).collect();
        return Err((
            P.into(),
            format!(
                "has no segment {} (segments: {})",
                segment.unwrap_or(-1),
                have.join(", ")
            ),
        ));
    }
    Ok(out)
}

/// The array of segment `seg`: `None` without the list, `Some(None)` without the segment.
fn find(list: &Option<Segments>, seg: i64) -> Option<Option<&Array>> {
    list.as_ref()
        .map(|l| l.iter().find(|(s, _)| *s == seg).map(|(_, a)| a))
}

/// `{segment: array}` of a pickled dictionary (a bare array counts as segment −1).
fn by_segment(value: &pickle::Value, key: &str) -> Result<Segments, (String, String)> {
    match value {
        pickle::Value::Array(a) if a.shape.is_empty() => {
            Err((key.into(), "a 0-d array holds no grasps".into()))
        }
        pickle::Value::Array(a) => Ok(vec![(-1, a.clone())]),
        pickle::Value::Dict(items) => items
            .iter()
            .map(|(k, v)| {
                let seg = match k {
                    pickle::Value::Int(s) => *s,
                    pickle::Value::Float(f) if f.fract() == 0.0 => *f as i64,
                    _ => {
                        return Err((
                            key.into(),
                            "a segment key is not a whole number".to_string(),
                        ))
                    }
                };
                match v {
                    pickle::Value::Array(a) => Ok((seg, a.clone())),
                    _ => Err((
                        format!("{key}[{seg}]"),
                        "is not a numeric array".to_string(),
                    )),
                }
            })
            .collect(),
        _ => Err((
            key.into(),
            "holds Python objects that are neither an array nor a {segment: array} dictionary"
                .into(),
        )),
    }
}
