//! Parametric candidate families on primitive shapes (the paper's experiments use the first two).
//!
//! Wrist (tool) frame convention, as Baxter's `left_gripper` / `right_gripper` frames: `z` is the
//! approach direction (out of the palm, towards the object) and the fingers close along `y`.
//! The tool point sits `depth` inside the surface it approaches.

use super::candidates::Candidate;
use crate::geometry::shape::Shape;
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};

/// Widest object the built-in Baxter electric gripper closes on (m).
pub const GRIPPER_MAX_OPENING: f64 = 0.1;

/// The wrist orientation with approach `approach` and closing direction `closing` (unit,
/// orthogonal), as `object_from_wrist` rotation.
fn wrist_rotation(approach: Vector3<f64>, closing: Vector3<f64>) -> UnitQuaternion<f64> {
    let x = closing.cross(&approach);
    let m = Matrix3::from_columns(&[x, closing, approach]);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

fn candidate(
    id: usize,
    label: String,
    position: Point3<f64>,
    rotation: UnitQuaternion<f64>,
) -> Candidate {
    Candidate {
        id,
        label,
        object_from_wrist: Isometry3::from_parts(Translation3::from(position.coords), rotation),
        log_likelihood: 0.0,
        contact: Some(position),
        hand_joints: Vec::new(),
        width: None,
    }
}

/// Why a candidate family cannot be laid out on a shape.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FamilyError {
    /// The family is defined on a box only.
    #[error("the {family} family needs a box shape")]
    NeedsBox {
        /// The family's name.
        family: &'static str,
    },
    /// `count` is zero.
    #[error("count must be at least 1")]
    ZeroCount,
    /// The margin leaves no edge to place grasps on.
    #[error("margin {margin} m leaves no edge on a {side} m box side")]
    NoEdge {
        /// The margin kept from each end (m).
        margin: f64,
        /// The box side's length (m).
        side: f64,
    },
    /// A face name that is not one of the six.
    #[error("unknown face '{0}' (faces: top, bottom, left, right, front, back)")]
    UnknownFace(String),
    /// A yaw family's start or step is not an angle within one turn either way.
    #[error("{field} must be within ±360 degrees, got {degrees}")]
    AngleOutOfRange {
        /// `start_deg` or `step_deg`.
        field: &'static str,
        /// The value given (degrees).
        degrees: f64,
    },
    /// Every face is wider than the gripper opens.
    #[error("no face of a {size:?} m box fits a {GRIPPER_MAX_OPENING} m gripper opening")]
    NoFaceFits {
        /// The box's edge lengths (m).
        size: [f64; 3],
    },
}

impl crate::fault::Classify for FamilyError {
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        Some(crate::fault::ErrorKind::Content)
    }

    fn field(&self) -> Option<&str> {
        match self {
            Self::AngleOutOfRange { field, .. } => Some(field),
            _ => None,
        }
    }
}

/// Top grasps along a box's top edge in the object's `y` direction, from the left-most
/// (`+y`) to the right-most (`−y`) contact, approaching from above (`−z`) with the fingers
/// closing across `x`; `margin` (m) kept from each end.
pub fn edge_family(
    shape: &Shape,
    count: usize,
    depth: f64,
    margin: f64,
) -> Result<Vec<Candidate>, FamilyError> {
    Ok(FamilyLayout::edge(shape, count, depth, margin)?.all())
}

/// A top grasp on the shape's highest part (box top, cylinder top, T-shape handle) turned about
/// the object's `z` axis: candidate `k` at yaw `start + k · step` (rad).
pub fn yaw_family(
    shape: &Shape,
    count: usize,
    start: f64,
    step: f64,
    depth: f64,
) -> Result<Vec<Candidate>, FamilyError> {
    Ok(FamilyLayout::yaw(shape, count, start, step, depth)?.all())
}

/// The faces of a box, by name: outward normal and the two in-plane axes.
const FACES: [(&str, usize, f64); 6] = [
    ("top", 2, 1.0),
    ("bottom", 2, -1.0),
    ("left", 1, 1.0),
    ("right", 1, -1.0),
    ("back", 0, 1.0),
    ("front", 0, -1.0),
];

/// Approaches over a box's faces (those not in `exclude`): on each face, for each in-plane axis
/// the gripper can close across (extent ≤ [`GRIPPER_MAX_OPENING`]) and both finger orders, tool
/// points on the face's centre line along the other axis, `depth` inside the face. `count` is
/// shared equally among the faces, then among each face's lines.
pub fn face_family(
    shape: &Shape,
    count: usize,
    exclude: &[String],
    depth: f64,
) -> Result<Vec<Candidate>, FamilyError> {
    Ok(FamilyLayout::faces(shape, count, exclude, depth)?.all())
}

/// One line of grasps on a box face: its face, the wrist rotation, the tool point's fixed
/// coordinate along the face normal, and the points' spacing along the line.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceLine {
    /// The face's name.
    face: &'static str,
    /// `+` or `-` and the closing axis's name, for the label (`+x`).
    closing: String,
    rotation: UnitQuaternion<f64>,
    /// The axis along the face normal and the tool point's coordinate on it (m).
    normal: (usize, f64),
    /// The axis the line runs along and half its length (m).
    along: (usize, f64),
    /// The index of the line's first candidate in the family.
    first: usize,
    /// How many candidates the line holds.
    count: usize,
}

/// A parametric family laid out once, each candidate computed from its index on demand
/// ([`candidate`](Self::candidate)), so a family of millions of candidates can be read a chunk
/// at a time without holding it. [`edge_family`], [`yaw_family`] and [`face_family`] are
/// `all()` of their layouts.
#[derive(Debug, Clone, PartialEq)]
pub enum FamilyLayout {
    /// [`edge_family`]: `count` tool points from `y = +half` to `−half` at height `z` (m).
    Edge {
        /// Number of candidates.
        count: usize,
        /// Half the edge's usable length (m).
        half: f64,
        /// The tool points' height (m).
        z: f64,
        /// The shared wrist rotation.
        rotation: UnitQuaternion<f64>,
    },
    /// [`yaw_family`]: candidate `k` at yaw `start + k · step` (rad), tool point at height `z`.
    Yaw {
        /// Number of candidates.
        count: usize,
        /// The first yaw (rad).
        start: f64,
        /// The step between candidates (rad).
        step: f64,
        /// The tool point's height (m).
        z: f64,
    },
    /// [`face_family`]: the lines of grasps, in candidate order.
    Faces {
        /// Every line with at least one candidate slot (possibly zero candidates).
        lines: Vec<FaceLine>,
    },
}

impl FamilyLayout {
    /// The layout of [`edge_family`].
    pub fn edge(shape: &Shape, count: usize, depth: f64, margin: f64) -> Result<Self, FamilyError> {
        let Shape::Box(cuboid) = shape else {
            return Err(FamilyError::NeedsBox { family: "edge" });
        };
        let size = cuboid.size();
        if count == 0 {
            return Err(FamilyError::ZeroCount);
        }
        let half = size[1] / 2.0 - margin;
        if half < 0.0 {
            return Err(FamilyError::NoEdge {
                margin,
                side: size[1],
            });
        }
        Ok(Self::Edge {
            count,
            half,
            z: size[2] / 2.0 - depth,
            rotation: wrist_rotation(-Vector3::z(), Vector3::x()),
        })
    }

    /// The layout of [`yaw_family`].
    pub fn yaw(
        shape: &Shape,
        count: usize,
        start: f64,
        step: f64,
        depth: f64,
    ) -> Result<Self, FamilyError> {
        if count == 0 {
            return Err(FamilyError::ZeroCount);
        }
        for (field, angle) in [("start_deg", start), ("step_deg", step)] {
            if !(angle.is_finite() && angle.abs() <= 2.0 * std::f64::consts::PI) {
                return Err(FamilyError::AngleOutOfRange {
                    field,
                    degrees: angle.to_degrees(),
                });
            }
        }
        Ok(Self::Yaw {
            count,
            start,
            step,
            z: top_of(shape) - depth,
        })
    }

    /// The layout of [`face_family`].
    pub fn faces(
        shape: &Shape,
        count: usize,
        exclude: &[String],
        depth: f64,
    ) -> Result<Self, FamilyError> {
        let Shape::Box(cuboid) = shape else {
            return Err(FamilyError::NeedsBox { family: "faces" });
        };
        let size = cuboid.size();
        if let Some(unknown) = exclude
            .iter()
            .find(|e| !FACES.iter().any(|f| f.0 == e.as_str()))
        {
            return Err(FamilyError::UnknownFace(unknown.clone()));
        }
        // Lines: (face name, normal axis, sign, closing axis, closing sign, line axis).
        let mut lines = Vec::new();
        for &(name, normal_axis, sign) in FACES.iter().filter(|f| !exclude.iter().any(|e| e == f.0))
        {
            for closing_axis in (0..3).filter(|&a| a != normal_axis) {
                if size[closing_axis] > GRIPPER_MAX_OPENING {
                    continue;
                }
                let line_axis = 3 - normal_axis - closing_axis;
                for closing_sign in [1.0, -1.0] {
                    lines.push((
                        name,
                        normal_axis,
                        sign,
                        closing_axis,
                        closing_sign,
                        line_axis,
                    ));
                }
            }
        }
        if lines.is_empty() {
            return Err(FamilyError::NoFaceFits { size });
        }
        let margin = 0.01;
        // Share `count` equally among the faces, then equally among each face's lines; the
        // remainders go to the earliest faces and lines.
        let faces: Vec<&str> = FACES
            .iter()
            .map(|f| f.0)
            .filter(|f| lines.iter().any(|l| l.0 == *f))
            .collect();
        let mut counts = vec![0usize; lines.len()];
        for (k, face) in faces.iter().enumerate() {
            let face_count = count / faces.len() + usize::from(k < count % faces.len());
            let members: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].0 == *face).collect();
            for (m, &i) in members.iter().enumerate() {
                counts[i] =
                    face_count / members.len() + usize::from(m < face_count % members.len());
            }
        }
        let mut first = 0;
        let lines = lines
            .iter()
            .zip(&counts)
            .map(|(line, &n)| {
                let &(face, normal_axis, sign, closing_axis, closing_sign, line_axis) = line;
                let mut normal = Vector3::zeros();
                normal[normal_axis] = sign;
                let mut closing = Vector3::zeros();
                closing[closing_axis] = closing_sign;
                let laid = FaceLine {
                    face,
                    closing: format!(
                        "{}{}",
                        if closing_sign > 0.0 { "+" } else { "-" },
                        ["x", "y", "z"][closing_axis]
                    ),
                    rotation: wrist_rotation(-normal, closing),
                    normal: (normal_axis, sign * (size[normal_axis] / 2.0 - depth)),
                    along: (line_axis, (size[line_axis] / 2.0 - margin).max(0.0)),
                    first,
                    count: n,
                };
                first += n;
                laid
            })
            .collect();
        Ok(Self::Faces { lines })
    }

    /// How many candidates the family holds.
    pub fn len(&self) -> usize {
        match self {
            Self::Edge { count, .. } | Self::Yaw { count, .. } => *count,
            Self::Faces { lines } => lines.last().map_or(0, |l| l.first + l.count),
        }
    }

    /// Whether the family holds no candidate.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Candidate `k` (its id is `k`), `None` past the end.
    pub fn candidate(&self, k: usize) -> Option<Candidate> {
        if k >= self.len() {
            return None;
        }
        Some(match self {
            Self::Edge {
                count,
                half,
                z,
                rotation,
            } => {
                let y = if *count == 1 {
                    0.0
                } else {
                    half - 2.0 * half * k as f64 / (count - 1) as f64
                };
                candidate(
                    k,
                    format!("edge y={y:+.3}"),
                    Point3::new(0.0, y, *z),
                    *rotation,
                )
            }
            Self::Yaw { start, step, z, .. } => {
                let yaw = start + step * k as f64;
                let base = wrist_rotation(-Vector3::z(), Vector3::x());
                let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw) * base;
                candidate(
                    k,
                    format!("yaw {:+.0} deg", yaw.to_degrees()),
                    Point3::new(0.0, 0.0, *z),
                    rotation,
                )
            }
            Self::Faces { lines } => {
                // The last line starting at or before k that holds candidates.
                let at = lines.partition_point(|l| l.first <= k) - 1;
                let line = lines[..=at]
                    .iter()
                    .rev()
                    .find(|l| l.count > 0 && k < l.first + l.count)?;
                let (n, i, half) = (line.count, k - line.first, line.along.1);
                let along = if n == 1 {
                    0.0
                } else {
                    -half + 2.0 * half * i as f64 / (n - 1) as f64
                };
                let mut p = Vector3::zeros();
                p[line.normal.0] = line.normal.1;
                p[line.along.0] = along;
                candidate(
                    k,
                    format!("{} close {} at {along:+.3}", line.face, line.closing),
                    Point3::from(p),
                    line.rotation,
                )
            }
        })
    }

    /// Every candidate, in order.
    pub fn all(&self) -> Vec<Candidate> {
        (0..self.len()).filter_map(|k| self.candidate(k)).collect()
    }
}

/// The height of the shape's top above its origin (m): the top of a T-shape's stem.
fn top_of(shape: &Shape) -> f64 {
    match shape {
        Shape::TShape(t) => t.bar().size()[2] / 2.0 + t.stem().length(),
        other => other.aabb().max.z,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::shape::TShape;

    fn approach(c: &Candidate) -> Vector3<f64> {
        c.object_from_wrist.rotation * Vector3::z()
    }
    fn closing(c: &Candidate) -> Vector3<f64> {
        c.object_from_wrist.rotation * Vector3::y()
    }

    #[test]
    fn edge_runs_left_to_right_from_above() {
        let shape = Shape::cuboid([0.06, 0.3, 0.1]).unwrap();
        let c = edge_family(&shape, 5, 0.02, 0.02).unwrap();
        assert_eq!(c.len(), 5);
        let ys: Vec<f64> = c
            .iter()
            .map(|c| c.object_from_wrist.translation.y)
            .collect();
        assert!((ys[0] - 0.13).abs() < 1e-15 && (ys[4] + 0.13).abs() < 1e-15);
        assert!(ys.windows(2).all(|w| w[1] < w[0]));
        for k in &c {
            assert!((approach(k) + Vector3::z()).norm() < 1e-12);
            assert!((closing(k) - Vector3::x()).norm() < 1e-12);
            assert!((k.object_from_wrist.translation.z - 0.03).abs() < 1e-15);
        }
    }

    #[test]
    fn yaw_steps_are_exact() {
        let shape = Shape::TShape(TShape::with_round_stem([0.1, 0.3, 0.04], 0.02, 0.12).unwrap());
        let c = yaw_family(&shape, 16, 0.0, 10f64.to_radians(), 0.02).unwrap();
        for (k, pair) in c.windows(2).enumerate() {
            let angle = pair[0]
                .object_from_wrist
                .rotation
                .angle_to(&pair[1].object_from_wrist.rotation);
            assert!((angle - 10f64.to_radians()).abs() < 1e-12, "step {k}");
        }
        assert!((c[0].object_from_wrist.translation.z - (0.02 + 0.12 - 0.02)).abs() < 1e-15);
    }

    #[test]
    fn faces_cover_the_requested_count_and_respect_the_opening() {
        let size = [0.06, 0.06, 0.2];
        let shape = Shape::cuboid(size).unwrap();
        let c = face_family(&shape, 1000, &["bottom".to_string()], 0.02).unwrap();
        assert_eq!(c.len(), 1000);
        for k in &c {
            let a = approach(k);
            assert!(a.z < 0.5, "nothing approaches from below: {a}");
            // The closing direction spans at most the gripper opening.
            let extent = closing(k).abs().dot(&Vector3::from(size));
            assert!(extent <= GRIPPER_MAX_OPENING + 1e-12);
            // The tool point lies inside, `depth` behind the face it approaches.
            let p = Point3::from(k.object_from_wrist.translation.vector);
            assert!(shape.signed_distance(&p) < 0.0, "{}", k.label);
            let on_face = p - a * 0.02;
            assert!(shape.signed_distance(&on_face).abs() < 1e-12, "{}", k.label);
        }
        assert!(face_family(&shape, 10, &["side".to_string()], 0.02).is_err());
    }
}
