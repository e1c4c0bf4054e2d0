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
//! * [`GraspFormat::ContactGraspnet`]: Contact-GraspNet `.npz` (`pred_grasps_cam`, `scores`,
//!   `contact_pts`, per segment as pickled dictionaries, or plain arrays), camera frame;
//! * [`GraspFormat::M2T2`]: M2T2's per-object `grasps`, `grasp_confidence`, `grasp_contacts`
//!   (or the Contact-GraspNet keys) saved as `.npz`: lists per object, dictionaries by object
//!   name or id, or plain arrays; world frame (M2T2's `config.yaml`, `world_coord: True`);
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

mod array;
mod arrays;
mod hdf5;
mod layouts;
mod pickle;

use super::candidates::{
    check_offset, too_large, Candidate, CandidateError, CandidateFile, MAX_FILE_BYTES,
};
use crate::spelling::spelled;
use crate::spelling::Spelled;
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use std::io::Read;
use std::path::Path;

/// The largest array read from a grasp file (bytes, 1 GiB).
pub const MAX_ARRAY_BYTES: u64 = 1 << 30;

/// The franka hand's tool centre point along its `z` (m): `panda_hand_tcp` in
/// franka_description, Contact-GraspNet's `gripper_depth` (NVlabs/contact_graspnet
/// `contact_graspnet/contact_graspnet.py`, `build_6d_grasp`) and M2T2's (NVlabs/M2T2
/// `m2t2/action_decoder.py`, `build_6d_grasp`). ACRONYM's hand is the same Panda hand.
pub const FRANKA_TCP_DEPTH: f64 = 0.1034;

/// GraspGen's Franka Panda tool centre point along the hand's `z` (m): `depth` of NVlabs/GraspGen
/// `config/grippers/franka_panda.yaml` ("from base link frame to TCP frame",
/// `docs/GRIPPER_DESCRIPTION.md`), the distance `grasp_gen/models/action_decoder.py` puts between
/// a grasp's origin and its contact along the approach axis.
pub const GRASPGEN_FRANKA_TCP_DEPTH: f64 = 0.10527314;

/// A grasp-file layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GraspFormat {
    /// graspath's own JSON or CSV (`read_candidates`): tool poses in the object frame.
    Graspath,
    /// GraspGen output YAML/JSON (Isaac grasp format) or dataset JSON; Franka hand frame.
    GraspGen,
    /// ACRONYM HDF5 or JSON; Franka hand frame, object frame.
    Acronym,
    /// Contact-GraspNet `.npz`; Franka hand frame, camera frame.
    ContactGraspnet,
    /// M2T2's outputs saved as `.npz`; Franka hand frame, world frame.
    M2T2,
    /// Generic `N×4×4` `.npy` / `.npz`; tool poses unless `gripper_from_tool` is given.
    Poses,
    /// GraspNet-1Billion / AnyGrasp `N×17` arrays; GraspNet gripper frame, camera frame.
    GraspNet,
}

spelled!(GraspFormat {
    Graspath => "graspath",
    GraspGen => "graspgen",
    Acronym => "acronym",
    ContactGraspnet => "contact_graspnet",
    M2T2 => "m2t2",
    Poses => "poses",
    GraspNet => "graspnet" | "anygrasp",
});

impl GraspFormat {
    /// The gripper whose frame the format's poses are in.
    pub fn gripper(self) -> GripperConvention {
        match self {
            Self::Graspath | Self::Poses => GripperConvention::Tool,
            Self::GraspGen => GripperConvention::GraspGenFranka,
            Self::Acronym | Self::ContactGraspnet | Self::M2T2 => GripperConvention::FrankaHand,
            Self::GraspNet => GripperConvention::GraspNet,
        }
    }

    /// The frame the format's poses are in unless the task says otherwise: `camera` for
    /// Contact-GraspNet (`pred_grasps_cam`) and GraspNet / AnyGrasp, `world` for M2T2 (its
    /// shipped `config.yaml` sets `world_coord: True`: the cloud, and so the grasps, are moved
    /// by the scene's camera pose into the frame that pose is given in; an `.npz` records no
    /// frame, so `frame: camera` is needed for M2T2 run with `world_coord: False`), else
    /// `object`.
    pub fn default_frame(self) -> GraspFrame {
        match self {
            Self::ContactGraspnet | Self::GraspNet => GraspFrame::Camera,
            Self::M2T2 => GraspFrame::World,
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

spelled!(GraspFrame { Object => "object", World => "world", Camera => "camera" });

impl GraspFrame {
    /// `object_from_frame`: where this frame is in the object frame, given the object in the
    /// world (`world_from_object`) and, for [`GraspFrame::Camera`] only, the camera's placement
    /// (`world_from_camera` or `camera_from_object`, not both). Errors name the field at fault
    /// (`frame`, `world_from_camera`, `camera_from_object`).
    pub fn object_from_frame(
        self,
        world_from_object: &Isometry3<f64>,
        world_from_camera: Option<&Isometry3<f64>>,
        camera_from_object: Option<&Isometry3<f64>>,
    ) -> Result<Isometry3<f64>, FramePlacementError> {
        let fail =
            |field: &'static str, message: &'static str| FramePlacementError { field, message };
        let object_from_camera = match (world_from_camera, camera_from_object) {
            (Some(_), Some(_)) => {
                return Err(fail(
                    "camera_from_object",
                    "give world_from_camera or camera_from_object, not both",
                ))
            }
            (Some(w), None) => Some(world_from_object.inverse() * w),
            (None, Some(c)) => Some(c.inverse()),
            (None, None) => None,
        };
        match (self, object_from_camera) {
            (Self::Camera, Some(pose)) => Ok(pose),
            (Self::Camera, None) => Err(fail(
                "frame",
                "poses in the camera frame need world_from_camera or camera_from_object",
            )),
            (Self::World, Some(_)) => Err(fail(
                "frame",
                "a camera pose is given but the frame is world (M2T2's default: its grasps are \
                 in the world frame); say frame: camera if the poses are in the camera frame",
            )),
            (Self::Object, Some(_)) => Err(fail(
                "frame",
                "a camera pose is given but the frame is object; say frame: camera if the \
                 poses are in the camera frame",
            )),
            (Self::Object, None) => Ok(Isometry3::identity()),
            (Self::World, None) => Ok(world_from_object.inverse()),
        }
    }
}

/// A grasp file's frame that cannot be placed in the object frame: the option at fault and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct FramePlacementError {
    /// The option at fault: `frame`, `world_from_camera` or `camera_from_object`.
    pub field: &'static str,
    /// What is wrong.
    pub message: &'static str,
}

impl crate::fault::Classify for FramePlacementError {
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        Some(crate::fault::ErrorKind::Content)
    }

    fn field(&self) -> Option<&str> {
        Some(self.field)
    }
}

/// A generator's gripper frame and how it maps to graspath's tool frame (`z` approach, the
/// fingers closing along `y`, the tool point at the origin).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GripperConvention {
    /// Poses are already tool poses.
    Tool,
    /// The Franka (Panda) hand frame of ACRONYM, Contact-GraspNet and M2T2: origin at the
    /// hand's base, `z` approach, fingers closing along `x`; the tool point
    /// [`FRANKA_TCP_DEPTH`] along `z`.
    FrankaHand,
    /// GraspGen's Franka Panda: the same hand frame, the tool point
    /// [`GRASPGEN_FRANKA_TCP_DEPTH`] along `z`.
    GraspGenFranka,
    /// GraspNet-1Billion / AnyGrasp: origin at the grasp centre, approach along `x`, fingers
    /// closing along `y` (graspnetAPI `plot_gripper_pro_max`).
    GraspNet,
}

impl GripperConvention {
    /// `gripper_from_tool`: the tool frame in the generator's gripper frame (translation in m).
    /// Franka: `Trans(0, 0, d) · Rz(−90°)` (tool `y` = hand `x`, tool `z` = hand `z`) with
    /// `d` = 0.1034 ([`FRANKA_TCP_DEPTH`]) or, for GraspGen, 0.10527314
    /// ([`GRASPGEN_FRANKA_TCP_DEPTH`]); GraspNet: `Ry(90°)` (tool `z` = gripper `x`, tool `y` =
    /// gripper `y`).
    pub fn gripper_from_tool(self) -> Isometry3<f64> {
        let franka = |depth: f64| {
            Isometry3::from_parts(
                Translation3::new(0.0, 0.0, depth),
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), -std::f64::consts::FRAC_PI_2),
            )
        };
        match self {
            Self::Tool => Isometry3::identity(),
            Self::FrankaHand => franka(FRANKA_TCP_DEPTH),
            Self::GraspGenFranka => franka(GRASPGEN_FRANKA_TCP_DEPTH),
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
    /// Contact-GraspNet / M2T2: read only this segment (a segment id, or an object's position
    /// in a per-object list; default: every segment).
    pub segment: Option<i64>,
    /// The most grasps the file may hold (a task's `limits.max_candidates`), checked on the
    /// arrays' declared shapes before their values are read; `None`: no limit beyond
    /// [`MAX_ARRAY_BYTES`] per array.
    pub max_candidates: Option<usize>,
}

impl Default for GraspFileOptions {
    fn default() -> Self {
        Self {
            format: None,
            object_from_frame: Isometry3::identity(),
            gripper_from_tool: None,
            segment: None,
            max_candidates: None,
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

/// A grasp file's candidates as [`open_grasp_file`] gives them.
#[derive(Debug, Clone)]
pub enum GraspCandidates {
    /// Read whole.
    Held(Vec<Candidate>),
    /// A graspath candidate file checked and indexed, read again in chunks.
    Indexed(CandidateFile),
}

/// Reads a grasp file of any [`GraspFormat`] as candidates in the object frame.
pub fn read_grasp_file(
    path: &Path,
    options: &GraspFileOptions,
) -> Result<(GraspFormat, Vec<Candidate>), CandidateError> {
    let format = format_of(path, options)?;
    read_whole(path, format, options).map(|c| (format, c))
}

/// [`read_grasp_file`], except that a graspath candidate file (JSON or CSV) that is a regular
/// file is checked and indexed ([`CandidateFile::index`]) rather than held: its candidates
/// are read again chunk by chunk when asked for. The generators' formats (NumPy, HDF5,
/// pickles, GraspGen YAML) are read whole.
pub fn open_grasp_file(
    path: &Path,
    options: &GraspFileOptions,
) -> Result<(GraspFormat, GraspCandidates), CandidateError> {
    let format = format_of(path, options)?;
    if format == GraspFormat::Graspath && CandidateFile::can_index(path) {
        check_graspath_options(path, options)?;
        return CandidateFile::index(path).map(|f| (format, GraspCandidates::Indexed(f)));
    }
    let options = GraspFileOptions {
        format: Some(format),
        ..options.clone()
    };
    read_grasp_file(path, &options).map(|(f, c)| (f, GraspCandidates::Held(c)))
}

/// The file's format: the one `options` gives, else guessed ([`guess_format`]). An empty file
/// is refused.
fn format_of(path: &Path, options: &GraspFileOptions) -> Result<GraspFormat, CandidateError> {
    let head = read_head(path)?;
    if head.is_empty() {
        return Err(file_error(path, "is empty".into()));
    }
    match options.format {
        Some(f) => Ok(f),
        None => guess_format(path),
    }
}

/// A graspath candidate file holds tool poses in the object frame: a frame or gripper
/// convention is refused.
fn check_graspath_options(path: &Path, options: &GraspFileOptions) -> Result<(), CandidateError> {
    if options.object_from_frame != Isometry3::identity() || options.gripper_from_tool.is_some() {
        return Err(file_error(
            path,
            "graspath candidate files hold tool poses in the object frame: frame and \
             gripper_from_tool do not apply"
                .into(),
        ));
    }
    Ok(())
}

fn file_error(path: &Path, message: String) -> CandidateError {
    CandidateError::new(path.display().to_string(), "file", message)
}

/// A grasp file of a known format, read whole.
fn read_whole(
    path: &Path,
    format: GraspFormat,
    options: &GraspFileOptions,
) -> Result<Vec<Candidate>, CandidateError> {
    let file = path.display().to_string();
    let error = |location: &str, message: String| CandidateError::new(&file, location, message);
    if format == GraspFormat::Graspath {
        check_graspath_options(path, options)?;
        return super::read_candidates(path);
    }
    let bytes = crate::input::read(path, MAX_FILE_BYTES)
        .map_err(|e| CandidateError::unreadable(path, e))?;
    let max = options.max_candidates;
    let grasps = match format {
        GraspFormat::Graspath => unreachable!("handled above"),
        GraspFormat::GraspGen | GraspFormat::Acronym if !bytes.starts_with(hdf5::SIGNATURE) => {
            layouts::text_grasps(format, &bytes, max)
        }
        GraspFormat::GraspGen | GraspFormat::Acronym => layouts::acronym_h5(bytes, max),
        GraspFormat::ContactGraspnet | GraspFormat::M2T2 => {
            layouts::contact_graspnet(&bytes, options.segment, max)
        }
        GraspFormat::Poses => layouts::poses(path, &bytes, max),
        GraspFormat::GraspNet => layouts::graspnet(path, &bytes, max),
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
    Ok(candidates)
}

/// The most an `.npz` of these bytes may expand to: deflate's largest ratio, at most
/// [`MAX_ARRAY_BYTES`].
fn npz_limit(bytes: &[u8]) -> u64 {
    (bytes.len() as u64)
        .saturating_mul(arrays::DEFLATE_MAX_RATIO)
        .min(MAX_ARRAY_BYTES)
}

/// A short, printable excerpt of file content for messages: at most `max` characters, each
/// control or non-UTF-8 byte shown as `?`, `…` where it is cut.
pub(crate) fn excerpt(bytes: &[u8], max: usize) -> String {
    let text = String::from_utf8_lossy(bytes);
    let mut out: String = text
        .chars()
        .take(max)
        .map(|c| {
            if c.is_control() || c == char::REPLACEMENT_CHARACTER {
                '?'
            } else {
                c
            }
        })
        .collect();
    if text.chars().nth(max).is_some() {
        out.push('…');
    }
    out
}

/// The first bytes of a file (at most 8: enough for every binary signature), the file
/// refused above [`MAX_FILE_BYTES`] when its length is known.
fn read_head(path: &Path) -> Result<Vec<u8>, CandidateError> {
    let unreadable = |e| CandidateError::unreadable(path, e);
    let file = crate::input::open(path).map_err(unreadable)?;
    if let Ok(metadata) = file.metadata() {
        if metadata.is_file() && metadata.len() > MAX_FILE_BYTES {
            return Err(unreadable(too_large(metadata.len())));
        }
    }
    let mut head = Vec::with_capacity(8);
    file.take(8).read_to_end(&mut head).map_err(unreadable)?;
    Ok(head)
}

/// Whether a file starting with `head` is one of the binary layouts (HDF5, `.npy`, `.npz`).
fn is_binary(head: &[u8]) -> bool {
    head.starts_with(hdf5::SIGNATURE) || head.starts_with(b"\x93NUMPY") || head.starts_with(b"PK")
}

/// The format of a file from its content (signature, keys, shapes) and extension. A CSV file
/// is guessed from its extension and a JSON document from its top-level keys, read as they
/// come (a graspath candidate file is not held); binary and YAML files are read whole.
pub fn guess_format(path: &Path) -> Result<GraspFormat, CandidateError> {
    let head = read_head(path)?;
    let has_extension = |names: &[&str]| {
        path.extension()
            .is_some_and(|e| names.iter().any(|n| e.eq_ignore_ascii_case(n)))
    };
    if !is_binary(&head) {
        if has_extension(&["csv"]) {
            return Ok(GraspFormat::Graspath);
        }
        if !has_extension(&["yaml", "yml"]) {
            let file = crate::input::open(path).map_err(|e| CandidateError::unreadable(path, e))?;
            let reader = std::io::BufReader::new(file.take(MAX_FILE_BYTES));
            let mut de = serde_json::Deserializer::from_reader(reader);
            let keys = serde::Deserialize::deserialize(&mut de)
                .and_then(|k: TopKeys| de.end().map(|()| k));
            if let Ok(keys) = keys {
                return Ok(keys.format());
            }
        }
    }
    let bytes = crate::input::read(path, MAX_FILE_BYTES)
        .map_err(|e| CandidateError::unreadable(path, e))?;
    guess(path, &bytes).map_err(|m| file_error(path, m))
}

/// What tells the text layouts apart: a top-level `format` (GraspGen's `isaac_grasp`), a
/// `grasps` object with `transforms` (GraspGen's dataset JSON), a top-level `transforms`
/// (ACRONYM's JSON). Every other value is skipped as it is read.
#[derive(Debug, Default)]
struct TopKeys {
    format: Option<serde_json::Value>,
    grasps: Option<serde_json::Value>,
    transforms: bool,
}

impl TopKeys {
    fn format(&self) -> GraspFormat {
        let isaac = self.format.as_ref().and_then(|f| f.as_str()) == Some("isaac_grasp");
        let dataset = self
            .grasps
            .as_ref()
            .and_then(|g| g.get("transforms"))
            .is_some();
        if isaac || dataset {
            GraspFormat::GraspGen
        } else if self.transforms {
            GraspFormat::Acronym
        } else {
            GraspFormat::Graspath
        }
    }
}

impl<'de> serde::Deserialize<'de> for TopKeys {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Keys;
        impl<'de> serde::de::Visitor<'de> for Keys {
            type Value = TopKeys;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("an object or a list")
            }

            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<TopKeys, A::Error> {
                while seq.next_element::<serde::de::IgnoredAny>()?.is_some() {}
                Ok(TopKeys::default())
            }

            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<TopKeys, A::Error> {
                let mut keys = TopKeys::default();
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "format" => keys.format = Some(map.next_value()?),
                        "grasps" => keys.grasps = Some(map.next_value()?),
                        "transforms" => {
                            map.next_value::<serde::de::IgnoredAny>()?;
                            keys.transforms = true;
                        }
                        _ => {
                            map.next_value::<serde::de::IgnoredAny>()?;
                        }
                    }
                }
                Ok(keys)
            }
        }
        deserializer.deserialize_any(Keys)
    }
}

fn guess(path: &Path, bytes: &[u8]) -> Result<GraspFormat, String> {
    let ask = |what: &str| {
        format!(
            "{what}; give candidates.format ({})",
            GraspFormat::spellings()
        )
    };
    if bytes.starts_with(hdf5::SIGNATURE) {
        return Ok(GraspFormat::Acronym);
    }
    if bytes.starts_with(b"\x93NUMPY") {
        let (header, _) = arrays::npy_header(bytes)?;
        if header.uses_pickled_array() {
            return Err(ask("a .npy of Python objects"));
        }
        return match header.shape() {
            [_, 4, 4] => Ok(GraspFormat::Poses),
            [_, 17] => Ok(GraspFormat::GraspNet),
            shape => Err(ask(&format!(
                "a .npy of shape {} is neither N×4×4 poses nor N×17 GraspNet grasps",
                array::shape_text(shape)
            ))),
        };
    }
    if bytes.starts_with(b"PK") {
        let members = arrays::npz_shapes(bytes)?;
        if members.iter().any(|(k, _)| k == "pred_grasps_cam") {
            return Ok(GraspFormat::ContactGraspnet);
        }
        // M2T2's own output names (`ActionDecoder.forward` in NVlabs/M2T2).
        if members.iter().any(|(k, _)| k == "grasps")
            && members
                .iter()
                .any(|(k, _)| k == "grasp_confidence" || k == "grasp_contacts")
        {
            return Ok(GraspFormat::M2T2);
        }
        let mut kinds = Vec::new();
        for (key, shape) in &members {
            match shape.as_deref() {
                Some([_, 4, 4]) => kinds.push((key.clone(), GraspFormat::Poses)),
                Some([_, 17]) => kinds.push((key.clone(), GraspFormat::GraspNet)),
                _ => {}
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
    // Any document that is not an object or a list is left to the graspath reader to refuse.
    Ok(serde_json::from_value::<TopKeys>(value)
        .unwrap_or_default()
        .format())
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

#[cfg(test)]
mod tests;
