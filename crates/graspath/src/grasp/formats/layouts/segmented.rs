//! Contact-GraspNet and M2T2 `.npz` files: poses, scores, contacts and openings kept per
//! segment or per object, under either generator's keys.

use super::*;

/// The names a Contact-GraspNet / M2T2 file gives its poses, scores, contacts and openings.
struct Names {
    poses: &'static str,
    scores: &'static str,
    contacts: &'static str,
    openings: Option<&'static str>,
}

/// Contact-GraspNet's keys (`contact_graspnet/inference.py`, plus `gripper_openings`).
const CONTACT_GRASPNET: Names = Names {
    poses: "pred_grasps_cam",
    scores: "scores",
    contacts: "contact_pts",
    openings: Some("gripper_openings"),
};

/// M2T2's output keys (`m2t2/action_decoder.py`, `ActionDecoder.forward`).
const M2T2: Names = Names {
    poses: "grasps",
    scores: "grasp_confidence",
    contacts: "grasp_contacts",
    openings: None,
};

/// Contact-GraspNet / M2T2 `.npz`: poses, scores and contacts under Contact-GraspNet's keys
/// (`pred_grasps_cam`, `scores`, `contact_pts`, optional `gripper_openings`) or M2T2's
/// (`grasps`, `grasp_confidence`, `grasp_contacts`), each
/// * a pickled dictionary `{segment id: array}` (what `np.savez` writes for the dictionaries of
///   Contact-GraspNet's `inference.py`) or `{object name: array}`;
/// * a list per object (M2T2's outputs): an object array of per-object arrays, or, when every
///   object has as many grasps, the `(K, N, 4, 4)` array `np.savez` makes of the list;
/// * a plain `(N, 4, 4)` array with its `(N,)` and `(N, 3)` companions.
///
/// A segment with one grasp may have its contact squeezed to `(3,)` and its opening to `()`
/// (Contact-GraspNet's `GraspEstimator.predict_grasps` returns
/// `pred_points[selection_idcs].squeeze()`); a segment with no grasps adds none, whatever the
/// shape of its companions (its contacts may be `(0,)` after `filter_segment`).
pub(in crate::grasp::formats) fn contact_graspnet(
    bytes: &[u8],
    segment: Option<i64>,
    max: Option<usize>,
) -> Grasps {
    let known = |k: &str| {
        [&CONTACT_GRASPNET, &M2T2]
            .iter()
            .any(|n| [n.poses, n.scores, n.contacts].contains(&k) || n.openings == Some(k))
    };
    // The pose arrays' grasp counts are checked on their headers, before they are read.
    let check = |key: &str, header: &npyz::NpyHeader| {
        let poses = [CONTACT_GRASPNET.poses, M2T2.poses].contains(&key);
        match grasp_rows(header.shape(), &[POSES, STACKED_POSES]) {
            Some(rows) if poses => check_count(key, rows, max).map_err(|(_, m)| m),
            _ => Ok(()),
        }
    };
    let members: Vec<(String, Member)> = read_npz(bytes, npz_limit(bytes), &known, &check)?
        .into_iter()
        .map(|(k, data)| {
            let member = parse_npy(&data).map_err(|m| (k.clone(), m))?;
            Ok((k, member))
        })
        .collect::<Result<_, (String, String)>>()?;
    let has = |key: &str| members.iter().any(|(k, _)| k == key);
    let names = if !has(CONTACT_GRASPNET.poses) && has(M2T2.poses) {
        &M2T2
    } else {
        &CONTACT_GRASPNET
    };
    let p = names.poses;
    // A numeric (K, N, 4, 4) is a list of K objects of N grasps each: its companions are
    // split along their first axis the same way.
    let stacked = matches!(
        members.iter().find(|(k, _)| k == p),
        Some((_, Member::Numeric(a))) if a.shape.len() == 4
    );
    let segments = |key: &str| -> Result<Option<Segments>, (String, String)> {
        let Some((_, member)) = members.iter().find(|(k, _)| k == key) else {
            return Ok(None);
        };
        Ok(Some(match member {
            Member::Numeric(a) if stacked && !a.shape.is_empty() => split_first_axis(a),
            Member::Numeric(a) => vec![(Key::Whole, a.clone())],
            Member::Object(v) => by_segment(v, key)?,
        }))
    };
    let poses = segments(p)?.ok_or_else(|| {
        (
            p.to_string(),
            "missing (a Contact-GraspNet result has pred_grasps_cam, an M2T2 result grasps)"
                .to_string(),
        )
    })?;
    check_count(
        p,
        poses
            .iter()
            .map(|(_, a)| a.shape.first().copied().unwrap_or(0) as u64)
            .fold(0, u64::saturating_add),
        max,
    )?;
    let scores = segments(names.scores)?;
    let contacts = segments(names.contacts)?;
    let openings = names.openings.map(segments).transpose()?.flatten();
    let mut out = Vec::new();
    let mut row = 0usize;
    let mut any_segment = false;
    for (key, transforms) in &poses {
        if segment.is_some_and(|s| key.number() != Some(s)) {
            continue;
        }
        any_segment = true;
        let index = key.index();
        let field = format!("{p}{index}");
        expect_shape(transforms, &[None, Some(4), Some(4)], &field, "(N, 4, 4)")?;
        let n = transforms.shape[0];
        if n == 0 {
            continue;
        }
        let companion = |list: &Option<Segments>,
                         name: &str,
                         tail: &[Option<usize>],
                         what: &str|
         -> Result<Option<Array>, (String, String)> {
            let located = format!("{name}{index}");
            match find(list, key) {
                None => Ok(None),
                Some(None) => Err((
                    name.to_string(),
                    match key {
                        Key::Whole => {
                            format!("is split by segment or object, but {p} is one array")
                        }
                        _ => format!("has no entry {index} ({p} has)"),
                    },
                )),
                Some(Some(a)) => {
                    let mut want = vec![Some(n)];
                    want.extend_from_slice(tail);
                    // (N, 1) scores; a lone grasp's contact squeezed to (3,), its score or
                    // opening to ().
                    let squeezed_one = n == 1 && a.shape.len() + 1 == want.len();
                    let a = if (a.shape.len() == 2 && tail.is_empty() && a.shape[1] == 1)
                        || squeezed_one
                    {
                        let mut shape = vec![n];
                        shape.extend(tail.iter().map(|d| d.unwrap_or(0)));
                        if shape.iter().product::<usize>() == a.data.len() {
                            Array {
                                shape,
                                data: a.data.clone(),
                            }
                        } else {
                            a.clone()
                        }
                    } else {
                        a.clone()
                    };
                    expect_shape(&a, &want, &located, what)?;
                    Ok(Some(a))
                }
            }
        };
        let s = companion(&scores, names.scores, &[], &format!("({n},)"))?;
        let c = companion(&contacts, names.contacts, &[Some(3)], &format!("({n}, 3)"))?;
        let w = match names.openings {
            Some(name) => companion(&openings, name, &[], &format!("({n},)"))?,
            None => None,
        };
        let grasps = pose_grasps(transforms, &field, None, None)?;
        for (i, mut g) in grasps.into_iter().enumerate() {
            g.id = row;
            g.label = key.label(i);
            g.score = s.as_ref().map(|s| s.data[i]);
            g.width = w.as_ref().map(|w| w.data[i]);
            g.contact = c
                .as_ref()
                .map(|c| Point3::new(c.data[3 * i], c.data[3 * i + 1], c.data[3 * i + 2]));
            if let Some(pt) = g.contact {
                if !pt.coords.iter().all(|v| v.is_finite()) {
                    return Err((
                        format!("{}{index}[{i}]", names.contacts),
                        "not finite".into(),
                    ));
                }
            }
            row += 1;
            out.push(g);
        }
    }
    if !any_segment {
        let have: Vec<String> = poses
            .iter()
            .map(|(k, _)| match k {
                Key::Named(n) => format!("'{}'", crate::grasp::formats::excerpt(n.as_bytes(), 40)),
                other => other.number().unwrap_or(-1).to_string(),
            })
            .collect();
        let named = poses.iter().any(|(k, _)| matches!(k, Key::Named(_)));
        return Err((
            p.into(),
            format!(
                "has no segment {} (segments: {}){}",
                segment.unwrap_or(-1),
                have.join(", "),
                if named {
                    "; segment selects numbered segments, not named objects"
                } else {
                    ""
                }
            ),
        ));
    }
    Ok(out)
}

/// The entries of a `(K, …)` array along its first axis, as objects `0..K`.
fn split_first_axis(a: &Array) -> Segments {
    let k = a.shape[0];
    let rest: Vec<usize> = a.shape[1..].to_vec();
    let size: usize = rest.iter().product();
    (0..k)
        .map(|i| {
            (
                Key::Object(i),
                Array {
                    shape: rest.clone(),
                    data: a.data[i * size..(i + 1) * size].to_vec(),
                },
            )
        })
        .collect()
}

/// The array of segment `key`: `None` without the list, `Some(None)` without the segment.
fn find<'a>(list: &'a Option<Segments>, key: &Key) -> Option<Option<&'a Array>> {
    list.as_ref()
        .map(|l| l.iter().find(|(k, _)| k == key).map(|(_, a)| a))
}

/// The arrays of a pickled object: a dictionary `{segment id or object name: array}`, a list
/// of per-object arrays, or a bare array (the whole file).
fn by_segment(value: &pickle::Value, key: &str) -> Result<Segments, (String, String)> {
    match value {
        pickle::Value::Array(a) if a.shape.is_empty() => {
            Err((key.into(), "a 0-d array holds no grasps".into()))
        }
        pickle::Value::Array(a) => Ok(vec![(Key::Whole, a.clone())]),
        pickle::Value::Dict(items) => items
            .iter()
            .map(|(k, v)| {
                let seg = match k {
                    pickle::Value::Int(s) => Key::Segment(*s),
                    pickle::Value::Float(f) if f.fract() == 0.0 => Key::Segment(*f as i64),
                    pickle::Value::Str(name) => Key::Named(name.clone()),
                    _ => {
                        return Err((
                            key.into(),
                            "a dictionary key is neither a whole number (a segment id) nor \
                             text (an object name)"
                                .to_string(),
                        ))
                    }
                };
                match v {
                    pickle::Value::Array(a) => Ok((seg, a.clone())),
                    _ => Err((
                        format!("{key}{}", seg.index()),
                        "is not a numeric array".to_string(),
                    )),
                }
            })
            .collect(),
        pickle::Value::Seq(items) => items
            .iter()
            .enumerate()
            .map(|(k, v)| match v {
                pickle::Value::Array(a) => Ok((Key::Object(k), a.clone())),
                _ => Err((
                    format!("{key}[{k}]"),
                    "is not a numeric array (save each object's array with .numpy())".to_string(),
                )),
            })
            .collect(),
        _ => Err((
            key.into(),
            "holds Python objects that are neither an array, a list of arrays nor a dictionary \
             of arrays"
                .into(),
        )),
    }
}
