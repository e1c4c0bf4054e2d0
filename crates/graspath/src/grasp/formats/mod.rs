//! Grasp files written by current grasp generators, read directly as candidates
//! (`docs/grasp-files.md` documents each layout and frame, with the generator file that
//! defines it):
//!
//! * [`GraspFormat::GraspGen`]: GraspGen's output (the Isaac grasp YAML of
//!   `save_to_isaac_grasp_format`: `grasps.<name>.{confidence, position, orientation}`) and
//!   its dataset JSON (`grasps.transforms`, `grasps.object_in_gripper`);
//! * [`GraspFormat::Acronym`]: ACRONYM HDF5 (`grasps/transforms`,
//!   `grasps/qualities/flex/object_in_gripper`) or its JSON (`transforms`,
//!   `quality_flex_object_in_gripper`);
//! * [`GraspFormat::ContactGraspnet`]: Contact-GraspNet / M2T2 `.npz` (`pred_grasps_cam`,
//!   `scores`, `contact_pts`, per segment as pickled dictionaries, or plain arrays);
//! * [`GraspFormat::Poses`]: any `N×4×4` `.npy`, or `.npz` with one `N×4×4` array and
//!   optionally `scores` (and `widths`);
//! * [`GraspFormat::GraspNet`]: GraspNet-1Billion / AnyGrasp `N×17` arrays
//!   (`GraspGroup.save_npy`): score, width, height, depth, rotation (9, row-major),
//!   translation (3), object id.
//!
//! Each pose read is `frame_from_gripper` (the generator's gripper frame in the file's frame);
//! the candidate's wrist pose is `object_from_wrist = object_from_frame · frame_from_gripper ·
//! gripper_from_tool`, with [`GripperConvention::gripper_from_tool`] by default. Grasps
//! scored 0 (ACRONYM's failed simulations) are not candidates; the others keep their row in
//! the file as their id.

mod arrays;
mod hdf5;
mod pickle;

use super::candidates::{check_offset, Candidate, CandidateError, MAX_FILE_BYTES};
use crate::geometry::pose_from_rows;
use arrays::{parse_npy, read_npz, Array, Member};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use std::io::Read;
use std::path::Path;

/// The largest array read from a grasp file (bytes, 1 GiB).
pub const MAX_ARRAY_BYTES: u64 = 1 << 30;

/// The franka hand's tool centre point along its `z` (m): `panda_hand_tcp` in
/// franka_description, and Contact-GraspNet's `gripper_depth` (`contact_graspnet.py`,
/// `build_6d_grasp`).
pub const FRANKA_TCP_DEPTH: f64 = 0.1034;

/// A grasp-file layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GraspFormat {
    /// graspath's own JSON or CSV (`read_candidates`): tool poses in the object frame.
    Graspath,
    /// GraspGen output YAML/JSON (Isaac grasp format) or dataset JSON; Franka hand frame.
    GraspGen,
    /// ACRONYM HDF5 or JSON; Franka hand frame, object frame.
    Acronym,
    /// Contact-GraspNet or M2T2 `.npz`; Franka hand frame, camera frame.
    ContactGraspnet,
    /// Generic `N×4×4` `.npy` / `.npz`; tool poses unless `gripper_from_tool` is given.
    Poses,
    /// GraspNet-1Billion / AnyGrasp `N×17` arrays; GraspNet gripper frame, camera frame.
    GraspNet,
}

impl GraspFormat {
    /// The format of a task file's `format:` (`graspath`, `graspgen`, `acronym`,
    /// `contact_graspnet` or `m2t2`, `poses`, `graspnet` or `anygrasp`).
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "graspath" => Self::Graspath,
            "graspgen" => Self::GraspGen,
            "acronym" => Self::Acronym,
            "contact_graspnet" | "m2t2" => Self::ContactGraspnet,
            "poses" => Self::Poses,
            "graspnet" | "anygrasp" => Self::GraspNet,
            _ => return None,
        })
    }

    /// The names [`Self::from_name`] accepts, for messages.
    pub const NAMES: &'static str =
        "graspath, graspgen, acronym, contact_graspnet (m2t2), poses, graspnet (anygrasp)";

    /// The gripper whose frame the format's poses are in.
    pub fn gripper(self) -> GripperConvention {
        match self {
            Self::Graspath | Self::Poses => GripperConvention::Tool,
            Self::GraspGen | Self::Acronym | Self::ContactGraspnet => GripperConvention::FrankaHand,
            Self::GraspNet => GripperConvention::GraspNet,
        }
    }

    /// The frame the format's poses are in unless the task says otherwise: `camera` for
    /// Contact-GraspNet / M2T2 (`pred_grasps_cam`) and GraspNet / AnyGrasp, else `object`.
    pub fn default_frame(self) -> GraspFrame {
        match self {
            Self::ContactGraspnet | Self::GraspNet => GraspFrame::Camera,
            _ => GraspFrame::Object,
        }
    }
}

/// The frame a grasp file's poses are in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GraspFrame {
    /// The object frame (the task's `object.pose` places it in the world).
    Object,
    /// The task's world frame.
    World,
    /// A camera frame, placed by `world_from_camera` or `camera_from_object`.
    Camera,
}

/// A generator's gripper frame and how it maps to graspath's tool frame (`z` approach, the
/// fingers closing along `y`, the tool point at the origin).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GripperConvention {
    /// Poses are already tool poses.
    Tool,
    /// The Franka (Panda) hand frame of ACRONYM, GraspGen, Contact-GraspNet and M2T2: origin
    /// at the hand's base, `z` approach, fingers closing along `x`; the tool point
    /// [`FRANKA_TCP_DEPTH`] along `z`.
    FrankaHand,
    /// GraspNet-1Billion / AnyGrasp: origin at the grasp centre, approach along `x`, fingers
    /// closing along `y` (graspnetAPI `plot_gripper_pro_max`).
    GraspNet,
}

impl GripperConvention {
    /// `gripper_from_tool`: the tool frame in the generator's gripper frame.
    /// Franka: `Trans(0, 0, 0.1034) · Rz(−90°)` (tool `y` = hand `x`, tool `z` = hand `z`);
    /// GraspNet: `Ry(90°)` (tool `z` = gripper `x`, tool `y` = gripper `y`).
    pub fn gripper_from_tool(self) -> Isometry3<f64> {
        match self {
            Self::Tool => Isometry3::identity(),
            Self::FrankaHand => Isometry3::from_parts(
                Translation3::new(0.0, 0.0, FRANKA_TCP_DEPTH),
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), -std::f64::consts::FRAC_PI_2),
            ),
            Self::GraspNet => Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
            ),
        }
    }
}

/// How to read a grasp file.
#[derive(Debug, Clone, PartialEq)]
pub struct GraspFileOptions {
    /// The layout; `None`: guessed from the content (and extension) where unambiguous.
    pub format: Option<GraspFormat>,
    /// `object_from_frame`: where the file's frame is in the object frame (identity for
    /// object-frame files).
    pub object_from_frame: Isometry3<f64>,
    /// `gripper_from_tool`; `None`: the format's [`GripperConvention::gripper_from_tool`].
    pub gripper_from_tool: Option<Isometry3<f64>>,
    /// Contact-GraspNet: read only this segment (default: every segment).
    pub segment: Option<i64>,
}

impl Default for GraspFileOptions {
    fn default() -> Self {
        Self {
            format: None,
            object_from_frame: Isometry3::identity(),
            gripper_from_tool: None,
            segment: None,
        }
    }
}

/// One grasp as the file gives it.
struct Grasp {
    /// Where in the file (`grasps/transforms[3]`).
    location: String,
    /// Row in the file, the candidate's id.
    id: usize,
    label: String,
    frame_from_gripper: Isometry3<f64>,
    score: Option<f64>,
    width: Option<f64>,
    contact: Option<Point3<f64>>,
}

/// Reads a grasp file of any [`GraspFormat`] as candidates in the object frame.
pub fn read_grasp_file(
    path: &Path,
    options: &GraspFileOptions,
) -> Result<(GraspFormat, Vec<Candidate>), CandidateError> {
    let file = path.display().to_string();
    let error = |location: &str, message: String| CandidateError {
        file: file.clone(),
        location: location.to_string(),
        message,
    };
    let bytes = read_bytes(path).map_err(|m| error("file", m))?;
    if bytes.is_empty() {
        return Err(error("file", "is empty".into()));
    }
    let format = match options.format {
        Some(f) => f,
        None => guess(path, &bytes).map_err(|m| error("file", m))?,
    };
    if format == GraspFormat::Graspath {
        if options.object_from_frame != Isometry3::identity() || options.gripper_from_tool.is_some()
        {
            return Err(error(
                "file",
                "graspath candidate files hold tool poses in the object frame: frame and \
                 gripper_from_tool do not apply"
                    .into(),
            ));
        }
        return super::read_candidates(path).map(|c| (format, c));
    }
    let grasps = match format {
        GraspFormat::Graspath => unreachable!("handled above"),
        GraspFormat::GraspGen | GraspFormat::Acronym if !bytes.starts_with(hdf5::SIGNATURE) => {
            text_grasps(format, &bytes)
        }
        GraspFormat::GraspGen | GraspFormat::Acronym => acronym_h5(bytes),
        GraspFormat::ContactGraspnet => contact_graspnet(&bytes, options.segment),
        GraspFormat::Poses => poses(path, &bytes),
        GraspFormat::GraspNet => graspnet(path, &bytes),
    }
    .map_err(|(l, m)| error(&l, m))?;
    let gripper_from_tool = options
        .gripper_from_tool
        .unwrap_or_else(|| format.gripper().gripper_from_tool());
    let mut candidates = Vec::with_capacity(grasps.len());
    let mut unscored = 0usize;
    for g in grasps {
        let log_likelihood = match g.score {
            Some(s) if !s.is_finite() || s < 0.0 => {
                return Err(error(
                    &g.location,
                    format!("score must be a finite number ≥ 0, got {s}"),
                ))
            }
            Some(0.0) => {
                unscored += 1;
                continue;
            }
            Some(s) => s.ln(),
            None => 0.0,
        };
        if let Some(w) = g.width {
            if !(w.is_finite() && w >= 0.0) {
                return Err(error(
                    &g.location,
                    format!("width must be a finite length ≥ 0 (m), got {w}"),
                ));
            }
        }
        let object_from_wrist =
            options.object_from_frame * g.frame_from_gripper * gripper_from_tool;
        check_offset("pose", &object_from_wrist.translation.vector.into())
            .map_err(|(f, m)| error(&format!("{} ({f} in the object frame)", g.location), m))?;
        let contact = g.contact.map(|c| options.object_from_frame * c);
        if let Some(c) = contact {
            check_offset("contact", &c.coords.into())
                .map_err(|(f, m)| error(&format!("{} ({f} in the object frame)", g.location), m))?;
        }
        candidates.push(Candidate {
            id: g.id,
            label: g.label,
            object_from_wrist,
            log_likelihood,
            contact,
            hand_joints: Vec::new(),
            width: g.width,
        });
    }
    if candidates.is_empty() {
        return Err(error(
            "file",
            if unscored > 0 {
                format!("all {unscored} grasps have score 0 (failed): no candidates")
            } else {
                "contains no grasps".into()
            },
        ));
    }
    Ok((format, candidates))
}

/// The most an `.npz` of these bytes may expand to: deflate's largest ratio, at most
/// [`MAX_ARRAY_BYTES`].
fn npz_limit(bytes: &[u8]) -> u64 {
    (bytes.len() as u64)
        .saturating_mul(arrays::DEFLATE_MAX_RATIO)
        .min(MAX_ARRAY_BYTES)
}

/// The file's bytes, at most [`MAX_FILE_BYTES`].
fn read_bytes(path: &Path) -> Result<Vec<u8>, String> {
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read: {e}"))?;
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read: {e}"))?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(format!("is larger than {MAX_FILE_BYTES} bytes"));
    }
    Ok(bytes)
}

/// The format of a file from its content (signature, keys, shapes) and extension.
pub fn guess_format(path: &Path) -> Result<GraspFormat, CandidateError> {
    let bytes = read_bytes(path).map_err(|m| CandidateError {
        file: path.display().to_string(),
        location: "file".into(),
        message: m,
    })?;
    guess(path, &bytes).map_err(|m| CandidateError {
        file: path.display().to_string(),
        location: "file".into(),
        message: m,
    })
}

fn guess(path: &Path, bytes: &[u8]) -> Result<GraspFormat, String> {
    let ask = |what: &str| format!("{what}; give candidates.format ({})", GraspFormat::NAMES);
    if bytes.starts_with(hdf5::SIGNATURE) {
        return Ok(GraspFormat::Acronym);
    }
    if bytes.starts_with(b"\x93NUMPY") {
        let Member::Numeric(a) = parse_npy(bytes)? else {
            return Err(ask("a .npy of Python objects"));
        };
        return match a.shape.as_slice() {
            [_, 4, 4] => Ok(GraspFormat::Poses),
            [_, 17] => Ok(GraspFormat::GraspNet),
            _ => Err(ask(&format!(
                "a .npy of shape {} is neither N×4×4 poses nor N×17 GraspNet grasps",
                a.shape_text()
            ))),
        };
    }
    if bytes.starts_with(b"PK") {
        let members = read_npz(bytes, npz_limit(bytes))?;
        if members.iter().any(|(k, _)| k == "pred_grasps_cam") {
            return Ok(GraspFormat::ContactGraspnet);
        }
        let mut kinds = Vec::new();
        for (key, data) in &members {
            if let Ok(Member::Numeric(a)) = parse_npy(data) {
                match a.shape.as_slice() {
                    [_, 4, 4] => kinds.push((key.clone(), GraspFormat::Poses)),
                    [_, 17] => kinds.push((key.clone(), GraspFormat::GraspNet)),
                    _ => {}
                }
            }
        }
        return match kinds.as_slice() {
            [(_, f)] => Ok(*f),
            [] => Err(ask("an .npz without pred_grasps_cam, N×4×4 or N×17 arrays")),
            _ => Err(ask("an .npz with several grasp arrays")),
        };
    }
    let is_csv = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    if is_csv {
        return Ok(GraspFormat::Graspath);
    }
    let text = std::str::from_utf8(bytes).map_err(|_| ask("not a known binary layout nor text"))?;
    let value = text_value(path, text).map_err(|m| ask(&m))?;
    if value.get("format").and_then(|f| f.as_str()) == Some("isaac_grasp") {
        return Ok(GraspFormat::GraspGen);
    }
    if value.pointer("/grasps/transforms").is_some() {
        return Ok(GraspFormat::GraspGen);
    }
    if value.get("transforms").is_some() {
        return Ok(GraspFormat::Acronym);
    }
    Ok(GraspFormat::Graspath)
}

fn text_value(path: &Path, text: &str) -> Result<serde_json::Value, String> {
    let yaml = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("yaml") || e.eq_ignore_ascii_case("yml"));
    if !yaml {
        if let Ok(v) = serde_json::from_str(text) {
            return Ok(v);
        }
    }
    serde_saphyr::from_str(text).map_err(|e| format!("not JSON or YAML: {e}"))
}

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

fn acronym_h5(bytes: Vec<u8>) -> Grasps {
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

fn text_grasps(format: GraspFormat, bytes: &[u8]) -> Grasps {
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

fn poses(path: &Path, bytes: &[u8]) -> Grasps {
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

fn graspnet(path: &Path, bytes: &[u8]) -> Grasps {
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
fn contact_graspnet(bytes: &[u8], segment: Option<i64>) -> Grasps {
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

#[cfg(test)]
mod tests;
