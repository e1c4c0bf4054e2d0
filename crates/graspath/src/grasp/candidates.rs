//! Grasp candidates and their import from JSON and CSV, so that any external generator (GPD,
//! Contact-GraspNet, GraspIt!, the learned model) can feed the selection.
//!
//! JSON: `{"format":"graspath-candidates","version":1,"frame":"object","candidates":[...]}` or a
//! bare list; each candidate has its wrist pose in the object frame as `pose` in the task file's
//! pose syntax ([`PoseSpec`]: `{xyz, rpy | rpy_deg | quaternion}` or `{matrix}`), or in the
//! older forms `object_from_wrist` (4×4 row-major) or `xyz` + `quaternion` (`[x, y, z, w]`) —
//! all read by the one pose parser — and optionally `id`, `label`, `likelihood` or `log_likelihood`, `contact`
//! (`[x, y, z]` or null) and `hand_joints`. CSV: a header with `x,y,z,qx,qy,qz,qw` and
//! optionally `id,label,likelihood|log_likelihood,contact_x,contact_y,contact_z` and
//! `hand_joints` (numbers separated by spaces or `;`).
//!
//! Checked, with an error naming the file, the candidate (`candidates[3]` or `line 7`) and the
//! field: every number finite; a quaternion's norm within [`QUATERNION_NORM_TOLERANCE`](crate::geometry::QUATERNION_NORM_TOLERANCE) of 1
//! (then normalised), a matrix orthonormal (see [`crate::geometry::ROTATION_TOLERANCE`]); wrist
//! and contact positions within [`MAX_OFFSET`] of the object origin; ids unique; the file at
//! most [`MAX_FILE_BYTES`] long (the number of candidates is what the file holds).
//!
//! A file is read record by record, never held as text: [`read_candidates`] keeps every
//! candidate, [`CandidateFile`] checks the file once and reads it again in chunks; both read
//! through the same record reader, so they give the same candidates and the same errors.

mod indexed;
mod rows;

pub use indexed::{CandidateFile, INDEX_STRIDE};

use crate::geometry::PoseSpec;
use nalgebra::{Isometry3, Point3};
use rows::{scan_file, Flow, Row, ScanError};
use serde::Deserialize;
use std::fmt;
use std::io;
use std::path::Path;
use std::sync::Arc;

/// The largest distance (m) of a wrist or contact coordinate from the object origin: a grasp
/// holds the object, so a larger value is a unit mistake (millimetres) or a corrupt file.
pub(super) const MAX_OFFSET: f64 = 10.0;

/// The largest candidate file read (bytes, 1 GiB: about five million JSON candidates).
pub(super) const MAX_FILE_BYTES: u64 = 1 << 30;

/// One grasp candidate.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// Identifier, unique within its set.
    pub id: usize,
    /// A human-readable label.
    pub label: String,
    /// The wrist (tool) pose in the object frame, `object_from_wrist` (m).
    pub object_from_wrist: Isometry3<f64>,
    /// Natural log of the grasp likelihood (0 when all candidates are equally likely).
    pub log_likelihood: f64,
    /// The contact point on the object, object frame (m), when known.
    pub contact: Option<Point3<f64>>,
    /// Hand joint values of the grasp (rad or m), when the generator gives them.
    pub hand_joints: Vec<f64>,
    /// The finger opening the generator predicted for this grasp (m), when its file gives
    /// one (GraspNet / AnyGrasp widths): wider than the gripper's opening is a
    /// `gripper_width` failure.
    pub width: Option<f64>,
}

impl Candidate {
    /// Where the hand holds the object, object frame (m): the contact point when known, else
    /// the wrist origin. Two arms' grasps overlap when these are too close.
    pub fn grasp_point(&self) -> Point3<f64> {
        self.contact
            .unwrap_or_else(|| Point3::from(self.object_from_wrist.translation.vector))
    }
}

/// A candidate file that cannot be used: the file, where in it, and why. When the file cannot
/// be read (missing, not a regular file, larger than `MAX_FILE_BYTES`, 1 GiB) the operating
/// system's error — or the size cap's, of kind [`std::io::ErrorKind::FileTooLarge`] — is kept
/// as the [`source`](std::error::Error::source): the message says `cannot read`, the source
/// says why.
#[derive(Debug, Clone)]
pub struct CandidateError {
    /// The file.
    pub file: String,
    /// Where: `candidates[3].object_from_wrist`, `line 7`, or `file`.
    pub location: String,
    /// What is wrong.
    pub message: String,
    /// Why the file cannot be read, when that is what is wrong (the error's source).
    pub cause: Option<Arc<io::Error>>,
}

impl CandidateError {
    /// An error about `location` of `file`: `message`.
    pub fn new(
        file: impl Into<String>,
        location: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Self {
            file: file.into(),
            location: location.into(),
            message: message.into(),
            cause: None,
        }
    }

    /// The file at `path` cannot be read: `cause` says why.
    pub fn unreadable(path: &Path, cause: io::Error) -> Self {
        Self {
            cause: Some(Arc::new(cause)),
            ..Self::new(path.display().to_string(), "file", "cannot read")
        }
    }
}

impl fmt::Display for CandidateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}: {}", self.file, self.location, self.message)
    }
}

impl std::error::Error for CandidateError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.cause
            .as_deref()
            .map(|e| e as &(dyn std::error::Error + 'static))
    }
}

impl PartialEq for CandidateError {
    /// Equal when the file, location, message and the cause's kind and message are.
    fn eq(&self, other: &Self) -> bool {
        let cause = |e: &Self| e.cause.as_ref().map(|c| (c.kind(), c.to_string()));
        (&self.file, &self.location, &self.message)
            == (&other.file, &other.location, &other.message)
            && cause(self) == cause(other)
    }
}

impl crate::fault::Classify for CandidateError {
    /// A file that cannot be read has its cause's kind
    /// ([`ErrorKind::of_io`](crate::fault::ErrorKind::of_io): a missing or unreadable file is
    /// [`File`](crate::fault::ErrorKind::File), one over the size cap
    /// [`Limit`](crate::fault::ErrorKind::Limit)); anything else is
    /// [`Content`](crate::fault::ErrorKind::Content).
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        match self.cause {
            Some(_) => None,
            None => Some(crate::fault::ErrorKind::Content),
        }
    }

    fn file(&self) -> Option<&str> {
        Some(&self.file)
    }

    fn field(&self) -> Option<&str> {
        Some(&self.location)
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    #[serde(default)]
    id: Option<usize>,
    #[serde(default)]
    label: Option<String>,
    #[serde(default)]
    pose: Option<PoseSpec>,
    #[serde(default)]
    object_from_wrist: Option<[[f64; 4]; 4]>,
    #[serde(default)]
    xyz: Option<[f64; 3]>,
    #[serde(default)]
    quaternion: Option<[f64; 4]>,
    #[serde(default)]
    likelihood: Option<f64>,
    #[serde(default)]
    log_likelihood: Option<f64>,
    #[serde(default)]
    contact: Option<[f64; 3]>,
    #[serde(default)]
    hand_joints: Vec<f64>,
}

/// The fields of one candidate before validation.
struct Raw {
    id: Option<usize>,
    label: Option<String>,
    pose: Option<PoseSpec>,
    matrix: Option<[[f64; 4]; 4]>,
    xyz: Option<[f64; 3]>,
    quaternion: Option<[f64; 4]>,
    likelihood: Option<f64>,
    log_likelihood: Option<f64>,
    contact: Option<[f64; 3]>,
    hand_joints: Vec<f64>,
}

impl Raw {
    fn into_candidate(self, index: usize) -> Result<Candidate, (String, String)> {
        // Every form is read by the one pose parser ([`PoseSpec::to_isometry`]): `pose` in the
        // task file's syntax, or the older `object_from_wrist` (its `matrix` form) and
        // `xyz` + `quaternion`.
        let (spec, field) = match (self.pose, self.matrix, self.xyz, self.quaternion) {
            (Some(spec), None, None, None) => (spec, "pose"),
            (None, Some(rows), None, None) => (
                PoseSpec {
                    matrix: Some(rows),
                    ..PoseSpec::default()
                },
                "object_from_wrist",
            ),
            (None, None, Some(xyz), Some(q)) => (
                PoseSpec {
                    xyz: Some(xyz),
                    quaternion: Some(q),
                    ..PoseSpec::default()
                },
                "xyz",
            ),
            _ => {
                return Err((
                    "pose".into(),
                    "give pose (e.g. {xyz, rpy_deg}), or object_from_wrist (4×4), or xyz and \
                     quaternion"
                        .into(),
                ))
            }
        };
        let pose = spec.to_isometry().map_err(|e| {
            let at = match field {
                "pose" => format!("pose.{}", e.field),
                "object_from_wrist" => "object_from_wrist".to_string(),
                _ => e.field.to_string(),
            };
            (at, e.message)
        })?;
        check_offset(field, &pose.translation.vector.into())?;
        let log_likelihood = match (self.likelihood, self.log_likelihood) {
            (Some(_), Some(_)) => {
                return Err((
                    "likelihood".into(),
                    "give likelihood or log_likelihood, not both".into(),
                ))
            }
            (Some(l), None) => {
                if !(l.is_finite() && l > 0.0) {
                    return Err((
                        "likelihood".into(),
                        format!("must be a positive number, got {l}"),
                    ));
                }
                l.ln()
            }
            (None, Some(l)) => {
                if !l.is_finite() {
                    return Err(("log_likelihood".into(), "must be finite".into()));
                }
                l
            }
            (None, None) => 0.0,
        };
        let contact = match self.contact {
            Some(c) if c.iter().any(|v| !v.is_finite()) => {
                return Err(("contact".into(), "not finite".into()))
            }
            Some(c) => {
                check_offset("contact", &c)?;
                Some(Point3::new(c[0], c[1], c[2]))
            }
            None => None,
        };
        if self.hand_joints.iter().any(|v| !v.is_finite()) {
            return Err(("hand_joints".into(), "not finite".into()));
        }
        let id = self.id.unwrap_or(index);
        Ok(Candidate {
            id,
            label: self.label.unwrap_or_else(|| format!("candidate {id}")),
            object_from_wrist: pose,
            log_likelihood,
            contact,
            hand_joints: self.hand_joints,
            width: None,
        })
    }
}

/// The refusal of a file of at least `bytes` bytes, more than [`MAX_FILE_BYTES`]: an error of
/// kind [`io::ErrorKind::FileTooLarge`], as [`crate::input::read`] gives for other files.
pub(super) fn too_large(bytes: u64) -> io::Error {
    io::Error::new(
        io::ErrorKind::FileTooLarge,
        format!(
            "the file is larger than {MAX_FILE_BYTES} bytes (at least {bytes}); split the \
             candidates into several files"
        ),
    )
}

/// Refuses a position with a coordinate beyond ±[`MAX_OFFSET`].
pub(super) fn check_offset(field: &str, xyz: &[f64; 3]) -> Result<(), (String, String)> {
    let farthest = xyz.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if farthest > MAX_OFFSET {
        return Err((
            field.to_string(),
            format!(
                "a coordinate is {farthest} m from the object origin; more than {MAX_OFFSET} m is refused (are the units metres?)"
            ),
        ));
    }
    Ok(())
}

/// Reads candidates from a `.json` or `.csv` file (by extension; others are tried as JSON).
/// Refuses an empty set and duplicate ids. The file is read record by record
/// ([`CandidateFile`] reads it the same way, chunk by chunk).
pub fn read_candidates(path: &Path) -> Result<Vec<Candidate>, CandidateError> {
    let mut candidates = Vec::new();
    check_file(path, |row| candidates.push(row.candidate))?;
    Ok(candidates)
}

/// Reads the whole file, checking every record, the ids unique and the file not empty, and
/// hands each candidate on to `keep` in file order. A duplicate id is reported at its second
/// use, naming the first (found by reading the file again up to it).
fn check_file(path: &Path, mut keep: impl FnMut(Row)) -> Result<(), CandidateError> {
    let file_error = |location: String, message: String| {
        CandidateError::new(path.display().to_string(), location, message)
    };
    let mut seen = std::collections::HashSet::new();
    let mut twice = None;
    let mut count = 0usize;
    scan_file(
        path,
        &mut |row: Row| -> Result<Flow, std::convert::Infallible> {
            if !seen.insert(row.candidate.id) {
                twice = Some((row.location, row.candidate.id));
                return Ok(Flow::Stop);
            }
            count += 1;
            keep(row);
            Ok(Flow::Continue)
        },
    )
    .map_err(ScanError::into_file)?;
    if let Some((location, id)) = twice {
        let mut first = None;
        scan_file(
            path,
            &mut |row: Row| -> Result<Flow, std::convert::Infallible> {
                if row.candidate.id == id {
                    first = Some(row.location);
                    return Ok(Flow::Stop);
                }
                Ok(Flow::Continue)
            },
        )
        .map_err(ScanError::into_file)?;
        let earlier = first.map_or_else(|| "an earlier candidate".to_string(), |l| l.to_string());
        return Err(file_error(
            location.to_string(),
            format!("id {id} is used twice (also by {earlier})"),
        ));
    }
    if count == 0 {
        return Err(file_error("file".into(), "contains no candidates".into()));
    }
    Ok(())
}

#[cfg(test)]
mod tests;
