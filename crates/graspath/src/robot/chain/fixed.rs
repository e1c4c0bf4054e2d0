//! [`FixedChain`]: a chain of exactly `N` independent joints in fixed-size arrays, whose
//! forward kinematics returns a stack-allocated `6 × N` Jacobian.

use super::forward::forward;
use super::{Chain, Segment};
use crate::robot::error::RobotError;
use nalgebra::{IsometryMatrix3, Matrix3, SMatrix, Vector3};

impl Chain {
    /// A fixed-size copy for chains of exactly `N` joints without mimic joints: its forward
    /// kinematics returns a stack-allocated `6 × N` Jacobian.
    pub fn fixed<const N: usize>(&self) -> Result<FixedChain<N>, RobotError> {
        let refuse = |reason: String| RobotError::NotFixedSize {
            chain: self.name(),
            requested: N,
            reason,
        };
        if self.drives.is_some() {
            return Err(refuse("it has mimic joints".into()));
        }
        if self.segments.len() != N {
            return Err(refuse(format!("it has {} joints", self.segments.len())));
        }
        Ok(FixedChain {
            segments: std::array::from_fn(|i| self.segments[i]),
            tail_rotation: self.tail_rotation,
            tail_translation: self.tail_translation,
        })
    }
}

/// A chain of exactly `N` independent joints with its data in fixed-size arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedChain<const N: usize> {
    segments: [Segment; N],
    tail_rotation: Matrix3<f64>,
    tail_translation: Vector3<f64>,
}

impl<const N: usize> FixedChain<N> {
    /// The tip pose `base_from_tip` at `q`.
    pub fn pose(&self, q: &[f64; N]) -> IsometryMatrix3<f64> {
        forward(
            &self.segments,
            |i| q[i],
            None,
            (&self.tail_rotation, &self.tail_translation),
        )
    }

    /// The tip pose and the geometric Jacobian (rows `[v; ω]`, base frame) at `q`.
    pub fn pose_and_jacobian(&self, q: &[f64; N]) -> (IsometryMatrix3<f64>, SMatrix<f64, 6, N>) {
        let mut jacobian = SMatrix::<f64, 6, N>::zeros();
        let pose = forward(
            &self.segments,
            |i| q[i],
            Some(jacobian.as_mut_slice()),
            (&self.tail_rotation, &self.tail_translation),
        );
        (pose, jacobian)
    }
}
