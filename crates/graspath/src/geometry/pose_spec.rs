//! The one pose syntax of every input file: `xyz` (m) with at most one of `rpy` (rad),
//! `rpy_deg` (degrees) or `quaternion` (`[x, y, z, w]`), or a 4×4 row-major `matrix` alone —
//! and the one function that turns it into a rigid transform.

use super::matrix::{pose_from_rows, PoseError};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use serde::{Deserialize, Serialize};

/// How far a quaternion's norm may be from 1 before it is refused rather than normalised: a
/// quaternion written with 6 significant digits is within this, a typo is not.
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-3;

/// A pose as written in a file. The rotation is URDF roll-pitch-yaw (about fixed x, y, z,
/// applied in that order), degrees, a unit quaternion, or part of a homogeneous matrix.
///
/// ```
/// use graspath::geometry::PoseSpec;
/// let spec: PoseSpec = serde_json::from_str(r#"{"xyz": [0.7, 0, -0.1], "rpy_deg": [0, 0, 90]}"#)
///     .unwrap();
/// let pose = spec.to_isometry().unwrap();
/// assert!((pose.translation.vector.x - 0.7).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseSpec {
    /// Translation (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub xyz: Option<[f64; 3]>,
    /// Roll, pitch, yaw (rad) about fixed x, y, z.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rpy: Option<[f64; 3]>,
    /// Roll, pitch, yaw in degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rpy_deg: Option<[f64; 3]>,
    /// Unit quaternion `[x, y, z, w]`; its norm must be 1 within
    /// [`QUATERNION_NORM_TOLERANCE`] (it is then normalised exactly).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quaternion: Option<[f64; 4]>,
    /// A 4×4 homogeneous matrix, row-major.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<[[f64; 4]; 4]>,
}

/// Why a [`PoseSpec`] is not a pose: the sub-field at fault (`xyz`, `rpy`, `quaternion`, …)
/// and what is wrong with it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("field '{field}': {message}")]
pub struct PoseSpecError {
    /// The sub-field of the pose (`xyz`, `rpy`, `rpy_deg`, `quaternion` or `matrix`).
    pub field: &'static str,
    /// What is wrong.
    pub message: String,
}

impl crate::fault::Classify for PoseSpecError {
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        Some(crate::fault::ErrorKind::Content)
    }

    fn field(&self) -> Option<&str> {
        Some(self.field)
    }
}

impl PoseSpec {
    /// A spec holding exactly `pose` (translation and quaternion).
    pub fn from_isometry(pose: &Isometry3<f64>) -> Self {
        let t = pose.translation.vector;
        let q = pose.rotation.coords;
        Self {
            xyz: Some([t.x, t.y, t.z]),
            quaternion: Some([q[0], q[1], q[2], q[3]]),
            ..Self::default()
        }
    }

    /// The rigid transform this spec describes (identity parts where nothing is given).
    pub fn to_isometry(&self) -> Result<Isometry3<f64>, PoseSpecError> {
        let err = |field: &'static str, message: String| PoseSpecError { field, message };
        if let Some(rows) = &self.matrix {
            if self.xyz.is_some()
                || self.rpy.is_some()
                || self.rpy_deg.is_some()
                || self.quaternion.is_some()
            {
                return Err(err(
                    "matrix",
                    "give a matrix alone, or xyz with rpy / rpy_deg / quaternion".into(),
                ));
            }
            return pose_from_rows(rows).map_err(|e: PoseError| err("matrix", e.to_string()));
        }
        let xyz = self.xyz.unwrap_or([0.0; 3]);
        if xyz.iter().any(|v| !v.is_finite()) {
            return Err(err("xyz", format!("not finite: {xyz:?}")));
        }
        let given = [
            self.rpy.is_some(),
            self.rpy_deg.is_some(),
            self.quaternion.is_some(),
        ];
        if given.iter().filter(|&&b| b).count() > 1 {
            return Err(err(
                "rpy",
                "give at most one of rpy, rpy_deg, quaternion".into(),
            ));
        }
        let rotation = if let Some(rpy) = self.rpy {
            if rpy.iter().any(|v| !v.is_finite()) {
                return Err(err("rpy", format!("not finite: {rpy:?}")));
            }
            UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2])
        } else if let Some(deg) = self.rpy_deg {
            if deg.iter().any(|v| !v.is_finite()) {
                return Err(err("rpy_deg", format!("not finite: {deg:?}")));
            }
            UnitQuaternion::from_euler_angles(
                deg[0].to_radians(),
                deg[1].to_radians(),
                deg[2].to_radians(),
            )
        } else if let Some(q) = self.quaternion {
            unit_quaternion_xyzw(q).map_err(|e| err("quaternion", e.to_string()))?
        } else {
            UnitQuaternion::identity()
        };
        Ok(Isometry3::from_parts(
            Translation3::new(xyz[0], xyz[1], xyz[2]),
            rotation,
        ))
    }
}

/// Why four numbers are not a unit quaternion.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QuaternionError {
    /// A component is NaN or infinite.
    #[error("must be four finite numbers [x, y, z, w]: {0:?}")]
    NonFinite([f64; 4]),
    /// The norm is farther from 1 than [`QUATERNION_NORM_TOLERANCE`].
    #[error("must be a unit quaternion [x, y, z, w] (its norm is {norm:.6}, allowed 1 ± {QUATERNION_NORM_TOLERANCE})")]
    NotUnit {
        /// The quaternion's norm.
        norm: f64,
    },
}

impl crate::fault::Classify for QuaternionError {
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        Some(crate::fault::ErrorKind::Content)
    }
}

/// A unit quaternion from `[x, y, z, w]` (the ROS / Eigen storage order) whose norm is 1 within
/// [`QUATERNION_NORM_TOLERANCE`], normalised exactly.
pub fn unit_quaternion_xyzw(xyzw: [f64; 4]) -> Result<UnitQuaternion<f64>, QuaternionError> {
    if xyzw.iter().any(|c| !c.is_finite()) {
        return Err(QuaternionError::NonFinite(xyzw));
    }
    let q = Quaternion::new(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);
    let norm = q.norm();
    if (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
        return Err(QuaternionError::NotUnit { norm });
    }
    Ok(UnitQuaternion::from_quaternion(q))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    fn spec(json: &str) -> PoseSpec {
        serde_json::from_str(json).expect("spec parses")
    }

    #[test]
    fn rpy_is_fixed_axis_roll_then_pitch_then_yaw() {
        // Oracle: the URDF convention R = Rz(yaw) · Ry(pitch) · Rx(roll), written out.
        let (r, p, y) = (0.3_f64, -0.5_f64, 1.1_f64);
        let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, r.cos(), -r.sin(), 0.0, r.sin(), r.cos());
        let ry = Matrix3::new(p.cos(), 0.0, p.sin(), 0.0, 1.0, 0.0, -p.sin(), 0.0, p.cos());
        let rz = Matrix3::new(y.cos(), -y.sin(), 0.0, y.sin(), y.cos(), 0.0, 0.0, 0.0, 1.0);
        let expected = rz * ry * rx;
        let got = spec(r#"{"rpy": [0.3, -0.5, 1.1]}"#)
            .to_isometry()
            .unwrap()
            .rotation
            .to_rotation_matrix();
        assert!((got.matrix() - expected).abs().max() < 1e-15);
        let degrees = spec(&format!(
            r#"{{"rpy_deg": [{}, {}, {}]}}"#,
            r.to_degrees(),
            p.to_degrees(),
            y.to_degrees()
        ))
        .to_isometry()
        .unwrap();
        assert!(
            (degrees.rotation.to_rotation_matrix().matrix() - expected)
                .abs()
                .max()
                < 1e-14
        );
    }

    #[test]
    fn every_rotation_form_describes_the_same_pose() {
        let pose = Isometry3::from_parts(
            Translation3::new(0.1, -0.2, 0.3),
            UnitQuaternion::from_euler_angles(0.2, 0.4, -0.9),
        );
        let from_quaternion = PoseSpec::from_isometry(&pose).to_isometry().unwrap();
        let m = pose.to_homogeneous();
        let rows: [[f64; 4]; 4] = std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]));
        let from_matrix = PoseSpec {
            matrix: Some(rows),
            ..PoseSpec::default()
        }
        .to_isometry()
        .unwrap();
        for other in [from_quaternion, from_matrix] {
            assert!((other.translation.vector - pose.translation.vector).norm() < 1e-15);
            assert!(other.rotation.angle_to(&pose.rotation) < 1e-12);
        }
    }

    #[test]
    fn bad_specs_name_the_sub_field() {
        let cases = [
            (r#"{"xyz": [0, 0, 1e999]}"#, "xyz"),
            (r#"{"rpy": [0, 0, 0], "quaternion": [0, 0, 0, 1]}"#, "rpy"),
            (r#"{"quaternion": [0, 0, 0, 2]}"#, "quaternion"),
            (r#"{"quaternion": [0, 0, 0, 0]}"#, "quaternion"),
            (
                r#"{"xyz": [0, 0, 0], "matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}"#,
                "matrix",
            ),
            (
                r#"{"matrix": [[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}"#,
                "matrix",
            ),
        ];
        for (json, field) in cases {
            let parsed: Result<PoseSpec, _> = serde_json::from_str(json);
            match parsed {
                Ok(s) => assert_eq!(s.to_isometry().unwrap_err().field, field, "{json}"),
                // 1e999 does not even parse as a finite f64 in JSON: also refused.
                Err(_) => assert_eq!(field, "xyz", "{json}"),
            }
        }
    }

    #[test]
    fn a_nearly_unit_quaternion_is_normalised_exactly() {
        // A 0.6/0.8 rotation about z written 0.04 % too long.
        let q = unit_quaternion_xyzw([0.0, 0.0, 0.6 * 1.0004, 0.8 * 1.0004]).unwrap();
        assert!((q.coords.norm() - 1.0).abs() < 1e-15);
        let axis = q.axis().unwrap();
        assert!((axis.into_inner() - Vector3::z()).norm() < 1e-12);
    }
}
