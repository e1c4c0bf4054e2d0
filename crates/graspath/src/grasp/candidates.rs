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

use crate::geometry::PoseSpec;
use nalgebra::{Isometry3, Point3};
use serde::Deserialize;
use std::io::Read;
use std::path::Path;

/// The largest distance (m) of a wrist or contact coordinate from the object origin: a grasp
/// holds the object, so a larger value is a unit mistake (millimetres) or a corrupt file.
pub const MAX_OFFSET: f64 = 10.0;

/// The largest candidate file read (bytes, 1 GiB: about five million JSON candidates).
pub const MAX_FILE_BYTES: u64 = 1 << 30;

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

/// A candidate file that cannot be used: the file, where in it, and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {location}: {message}")]
pub struct CandidateError {
    /// The file.
    pub file: String,
    /// Where: `candidates[3].object_from_wrist`, `line 7`, or `file`.
    pub location: String,
    /// What is wrong.
    pub message: String,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Wrapped {
    #[serde(default)]
    format: Option<String>,
    #[serde(default)]
    version: Option<u32>,
    #[serde(default)]
    frame: Option<String>,
    candidates: Vec<serde_json::Value>,
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
/// Refuses an empty set and duplicate ids.
pub fn read_candidates(path: &Path) -> Result<Vec<Candidate>, CandidateError> {
    let file = path.display().to_string();
    let error = |location: String, message: String| CandidateError {
        file: file.clone(),
        location,
        message,
    };
    let text = read_text(path).map_err(|m| error("file".into(), m))?;
    let is_csv = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let located = if is_csv {
        parse_csv(&text).map_err(|(l, m)| error(l, m))?
    } else {
        parse_json(&text).map_err(|(l, m)| error(l, m))?
    };
    if located.is_empty() {
        return Err(error("file".into(), "contains no candidates".into()));
    }
    let mut first_use = std::collections::HashMap::with_capacity(located.len());
    for (location, candidate) in &located {
        if let Some(earlier) = first_use.insert(candidate.id, location) {
            return Err(error(
                location.clone(),
                format!("id {} is used twice (also by {earlier})", candidate.id),
            ));
        }
    }
    Ok(located.into_iter().map(|(_, c)| c).collect())
}

/// The file's text, at most [`MAX_FILE_BYTES`] long (also for pipes and devices).
fn read_text(path: &Path) -> Result<String, String> {
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read: {e}"))?;
    if let Ok(metadata) = file.metadata() {
        if metadata.is_file() && metadata.len() > MAX_FILE_BYTES {
            return Err(too_large(metadata.len()));
        }
    }
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read: {e}"))?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(too_large(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| {
        format!(
            "not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        )
    })
}

fn too_large(bytes: u64) -> String {
    format!("is larger than {MAX_FILE_BYTES} bytes (at least {bytes}); split the candidates into several files")
}

/// Candidates with where each one is in its file (`candidates[3]`, `line 7`).
type Located = Vec<(String, Candidate)>;

fn parse_json(text: &str) -> Result<Located, (String, String)> {
    let document: serde_json::Value = serde_json::from_str(text)
        .map_err(|e| ("file".to_string(), format!("not a candidate document: {e}")))?;
    let entries = match document {
        serde_json::Value::Array(list) => list,
        object @ serde_json::Value::Object(_) => {
            let w: Wrapped = serde_json::from_value(object)
                .map_err(|e| ("file".to_string(), format!("not a candidate document: {e}")))?;
            if let Some(format) = &w.format {
                if format != "graspath-candidates" {
                    return Err((
                        "format".into(),
                        format!("expected 'graspath-candidates', got '{format}'"),
                    ));
                }
            }
            if let Some(version) = w.version {
                if version != 1 {
                    return Err((
                        "version".into(),
                        format!("version {version} is not supported (this reads version 1)"),
                    ));
                }
            }
            if let Some(frame) = &w.frame {
                if frame != "object" {
                    return Err((
                        "frame".into(),
                        format!("poses must be in the object frame, got '{frame}'"),
                    ));
                }
            }
            w.candidates
        }
        _ => {
            return Err((
                "file".into(),
                "not a candidate document: expected an object with 'candidates' or a list".into(),
            ))
        }
    };
    entries
        .into_iter()
        .enumerate()
        .map(|(i, value)| {
            let location = format!("candidates[{i}]");
            let entry: Entry =
                serde_json::from_value(value).map_err(|e| (location.clone(), e.to_string()))?;
            let candidate = Raw {
                id: entry.id,
                label: entry.label,
                pose: entry.pose,
                matrix: entry.object_from_wrist,
                xyz: entry.xyz,
                quaternion: entry.quaternion,
                likelihood: entry.likelihood,
                log_likelihood: entry.log_likelihood,
                contact: entry.contact,
                hand_joints: entry.hand_joints,
            }
            .into_candidate(i)
            .map_err(|(field, message)| (format!("{location}.{field}"), message))?;
            Ok((location, candidate))
        })
        .collect()
}

fn parse_csv(text: &str) -> Result<Located, (String, String)> {
    const KNOWN: [&str; 16] = [
        "id",
        "label",
        "x",
        "y",
        "z",
        "qx",
        "qy",
        "qz",
        "qw",
        "likelihood",
        "log_likelihood",
        "contact_x",
        "contact_y",
        "contact_z",
        "hand_joints",
        "",
    ];
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| ("line 1".to_string(), e.to_string()))?
        .clone();
    if let Some(unknown) = headers.iter().find(|h| !KNOWN.contains(h)) {
        return Err(("line 1".into(), format!("unknown column '{unknown}'")));
    }
    let column = |name: &str| headers.iter().position(|h| h == name);
    for required in ["x", "y", "z", "qx", "qy", "qz", "qw"] {
        if column(required).is_none() {
            return Err(("line 1".into(), format!("missing column '{required}'")));
        }
    }
    let mut candidates = Vec::new();
    for (i, record) in reader.records().enumerate() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(i + 2, |p| p.line() as usize);
            (format!("line {line}"), e.to_string())
        })?;
        let line = format!(
            "line {}",
            record.position().map_or(i + 2, |p| p.line() as usize)
        );
        let number = |name: &str| -> Result<Option<f64>, (String, String)> {
            match column(name).and_then(|c| record.get(c)) {
                None | Some("") => Ok(None),
                Some(text) => text.parse::<f64>().map(Some).map_err(|_| {
                    (
                        line.clone(),
                        format!("column '{name}': '{text}' is not a number"),
                    )
                }),
            }
        };
        let need = |name: &str| -> Result<f64, (String, String)> {
            number(name)?.ok_or_else(|| (line.clone(), format!("column '{name}' is empty")))
        };
        let id = match column("id").and_then(|c| record.get(c)) {
            None | Some("") => None,
            Some(text) => Some(text.parse::<usize>().map_err(|_| {
                (
                    line.clone(),
                    format!("column 'id': '{text}' is not a whole number"),
                )
            })?),
        };
        let contact = match (
            number("contact_x")?,
            number("contact_y")?,
            number("contact_z")?,
        ) {
            (Some(x), Some(y), Some(z)) => Some([x, y, z]),
            (None, None, None) => None,
            _ => {
                return Err((
                    line,
                    "contact_x, contact_y and contact_z go together".into(),
                ))
            }
        };
        let raw = Raw {
            id,
            label: column("label")
                .and_then(|c| record.get(c))
                .filter(|s| !s.is_empty())
                .map(str::to_string),
            pose: None,
            matrix: None,
            xyz: Some([need("x")?, need("y")?, need("z")?]),
            quaternion: Some([need("qx")?, need("qy")?, need("qz")?, need("qw")?]),
            likelihood: number("likelihood")?,
            log_likelihood: number("log_likelihood")?,
            contact,
            hand_joints: match column("hand_joints").and_then(|c| record.get(c)) {
                None => Vec::new(),
                Some(text) => text
                    .split(|c: char| c.is_whitespace() || c == ';')
                    .filter(|v| !v.is_empty())
                    .map(|v| {
                        v.parse::<f64>().map_err(|_| {
                            (
                                line.clone(),
                                format!("column 'hand_joints': '{v}' is not a number"),
                            )
                        })
                    })
                    .collect::<Result<Vec<f64>, _>>()?,
            },
        };
        let candidate = raw
            .into_candidate(i)
            .map_err(|(field, message)| (line.clone(), format!("{field}: {message}")))?;
        candidates.push((line, candidate));
    }
    Ok(candidates)
}

#[cfg(test)]
mod tests;
