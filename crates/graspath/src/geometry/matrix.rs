//! Validated conversion between 4×4 row-major homogeneous matrices and poses.

use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};

/// How far `RᵀR` may be from the identity (max absolute entry) for a 4×4 matrix to be accepted
/// as a rigid transform.
pub const ROTATION_TOLERANCE: f64 = 1e-6;

/// Why a 4×4 matrix is not a rigid transform.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PoseError {
    /// An entry is NaN or infinite.
    #[error("entry [{row}][{col}] is not a finite number")]
    NonFinite {
        /// Row index (0-based).
        row: usize,
        /// Column index (0-based).
        col: usize,
    },
    /// The last row is not `[0, 0, 0, 1]`.
    #[error("the last row must be [0, 0, 0, 1]")]
    BadLastRow,
    /// The rotation block is not orthonormal with determinant +1.
    #[error("the 3×3 rotation block is not orthonormal (max |RᵀR − I| = {deviation:.3e}, det = {determinant:.6})")]
    NotOrthonormal {
        /// Largest absolute entry of `RᵀR − I`.
        deviation: f64,
        /// Determinant of the rotation block.
        determinant: f64,
    },
}

impl crate::fault::Classify for PoseError {
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        Some(crate::fault::ErrorKind::Content)
    }
}

/// A pose from a 4×4 homogeneous matrix in row-major nested rows (metres).
///
/// The rotation block must be orthonormal to [`ROTATION_TOLERANCE`]; it is then
/// re-orthonormalised exactly.
pub fn pose_from_rows(rows: &[[f64; 4]; 4]) -> Result<Isometry3<f64>, PoseError> {
    for (r, row) in rows.iter().enumerate() {
        for (c, value) in row.iter().enumerate() {
            if !value.is_finite() {
                return Err(PoseError::NonFinite { row: r, col: c });
            }
        }
    }
    if rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(PoseError::BadLastRow);
    }
    let r = Matrix3::from_fn(|i, j| rows[i][j]);
    let deviation = (r.transpose() * r - Matrix3::identity()).abs().max();
    let determinant = r.determinant();
    if deviation > ROTATION_TOLERANCE || determinant <= 0.0 {
        return Err(PoseError::NotOrthonormal {
            deviation,
            determinant,
        });
    }
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
    let translation = Translation3::from(Vector3::new(rows[0][3], rows[1][3], rows[2][3]));
    Ok(Isometry3::from_parts(translation, rotation))
}

/// The 4×4 homogeneous matrix of a pose, row-major nested rows.
pub fn pose_to_rows(pose: &Isometry3<f64>) -> [[f64; 4]; 4] {
    let m = pose.to_homogeneous();
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn round_trip() {
        let pose = Isometry3::from_parts(
            Translation3::new(0.3, -0.1, 0.7),
            UnitQuaternion::from_scaled_axis(Vector3::new(0.2, 1.1, -0.4)),
        );
        let back = pose_from_rows(&pose_to_rows(&pose)).expect("valid");
        assert_relative_eq!(
            back.to_homogeneous(),
            pose.to_homogeneous(),
            epsilon = 1e-15
        );
    }

    #[test]
    fn rejects_bad_matrices() {
        let mut rows = pose_to_rows(&Isometry3::identity());
        rows[0][0] = 2.0;
        assert!(matches!(
            pose_from_rows(&rows),
            Err(PoseError::NotOrthonormal { .. })
        ));
        let mut rows = pose_to_rows(&Isometry3::identity());
        rows[1][2] = f64::NAN;
        assert_eq!(
            pose_from_rows(&rows),
            Err(PoseError::NonFinite { row: 1, col: 2 })
        );
        let mut rows = pose_to_rows(&Isometry3::identity());
        rows[3][0] = 1.0;
        assert_eq!(pose_from_rows(&rows), Err(PoseError::BadLastRow));
        // A reflection is orthonormal but not a rotation.
        let mut rows = pose_to_rows(&Isometry3::identity());
        rows[2][2] = -1.0;
        assert!(matches!(
            pose_from_rows(&rows),
            Err(PoseError::NotOrthonormal { .. })
        ));
    }
}
