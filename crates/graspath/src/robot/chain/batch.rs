//! Forward kinematics of many configurations per call. On x86-64 processors with AVX2, chains
//! without mimic joints run four configurations at once, one per vector lane, each lane doing
//! the scalar pass's operations (bit-identical to one call per configuration).

#[cfg(target_arch = "x86_64")]
use super::{avx2, pose_from_columns};
use super::{Chain, MAX_JOINTS};
use crate::robot::error::RobotError;
use nalgebra::IsometryMatrix3;

impl Chain {
    /// Forward kinematics of many configurations: `q` holds them one after another (`dof`
    /// values each, rad / m). For configuration `k`, `emit(k, pose, jacobian)` receives the tip
    /// pose `base_from_tip` and the geometric Jacobian as a column-major 6 × dof slice (rows
    /// `[v; ω]`, base frame), exactly what [`Chain::pose_and_jacobian_into`] gives for it.
    ///
    /// On processors with AVX2, chains without mimic joints evaluate four configurations at
    /// once, one per vector lane, with the scalar pass's operations (bit-identical results);
    /// faster per configuration than one call each.
    ///
    /// Nothing is emitted when `q` is not a whole number of configurations
    /// ([`RobotError::WrongDof`]) or holds a value that is not finite
    /// ([`RobotError::NonFiniteJoint`], indexed into `q`).
    pub fn for_each_pose_and_jacobian(
        &self,
        q: &[f64],
        mut emit: impl FnMut(usize, &IsometryMatrix3<f64>, &[f64]),
    ) -> Result<(), RobotError> {
        self.check_batch(q)?;
        let dof = self.dof();
        #[cfg(target_arch = "x86_64")]
        if self.drives.is_none() && dof > 0 && avx2::available() {
            let n = self.segments.len();
            let mut values = vec![[0.0; 4]; n];
            let mut lanes = vec![[0.0; 4]; 6 * n];
            let mut column_major = vec![0.0; 6 * n];
            for (group, rows) in q.chunks(4 * dof).enumerate() {
                fill_lanes(&mut values, rows, dof);
                // SAFETY: AVX2 is present (checked above); the buffers have the sizes asked.
                let poses = unsafe {
                    avx2::forward4(&self.segments, &values, Some(&mut lanes), self.tail())
                };
                for (lane, pose) in lane_poses(&poses).iter().take(rows.len() / dof).enumerate() {
                    for (value, lanes) in column_major.iter_mut().zip(&lanes) {
                        *value = lanes[lane];
                    }
                    emit(4 * group + lane, pose, &column_major);
                }
            }
            return Ok(());
        }
        let mut jacobian = vec![0.0; 6 * dof];
        for (k, row) in q.chunks(dof.max(1)).enumerate() {
            let pose = self.pose_and_jacobian_unchecked(row, &mut jacobian);
            emit(k, &pose, &jacobian);
        }
        Ok(())
    }

    /// Like [`Chain::for_each_pose_and_jacobian`], for the tip poses alone.
    pub fn for_each_pose(
        &self,
        q: &[f64],
        mut emit: impl FnMut(usize, &IsometryMatrix3<f64>),
    ) -> Result<(), RobotError> {
        self.check_batch(q)?;
        let dof = self.dof();
        #[cfg(target_arch = "x86_64")]
        if self.drives.is_none() && dof > 0 && avx2::available() {
            let mut values = vec![[0.0; 4]; self.segments.len()];
            for (group, rows) in q.chunks(4 * dof).enumerate() {
                fill_lanes(&mut values, rows, dof);
                // SAFETY: AVX2 is present (checked above); `values` has one entry per segment.
                let poses = unsafe { avx2::forward4(&self.segments, &values, None, self.tail()) };
                for (lane, pose) in lane_poses(&poses).iter().take(rows.len() / dof).enumerate() {
                    emit(4 * group + lane, pose);
                }
            }
            return Ok(());
        }
        for (k, row) in q.chunks(dof.max(1)).enumerate() {
            emit(k, &self.pose_unchecked(row));
        }
        Ok(())
    }

    /// Tip poses and Jacobians of four configurations at once, in lane layout: `q[j][lane]` is
    /// joint `j` (rad / m) of configuration `lane`, and `jacobian[6·j + row][lane]` receives row
    /// `row` (`[v; ω]`, base frame) of column `j` of its geometric Jacobian. Returns the four
    /// tip poses `base_from_tip`. Each lane's results are bit-identical to
    /// [`Chain::pose_and_jacobian_into`] on that configuration.
    ///
    /// On processors with AVX2, chains without mimic joints run the four configurations in one
    /// vector pass; otherwise one configuration after the other. No checks: `q` and `jacobian`
    /// must hold `dof` and `6 · dof` entries, and the values must be finite.
    pub(crate) fn four_poses_and_jacobians(
        &self,
        q: &[[f64; 4]],
        jacobian: &mut [[f64; 4]],
    ) -> [IsometryMatrix3<f64>; 4] {
        #[cfg(target_arch = "x86_64")]
        if self.drives.is_none() && avx2::available() {
            // SAFETY: AVX2 is present (checked just above); without mimic joints there is one
            // segment per joint, so `q` and `jacobian` have the sizes `forward4` needs.
            let poses = unsafe { avx2::forward4(&self.segments, q, Some(jacobian), self.tail()) };
            return lane_poses(&poses);
        }
        let dof = self.dof();
        let mut column_major = [0.0; 6 * MAX_JOINTS];
        std::array::from_fn(|lane| {
            let configuration: [f64; MAX_JOINTS] =
                std::array::from_fn(|j| if j < dof { q[j][lane] } else { 0.0 });
            let pose = self
                .pose_and_jacobian_unchecked(&configuration[..dof], &mut column_major[..6 * dof]);
            for (lanes, value) in jacobian.iter_mut().zip(&column_major[..6 * dof]) {
                lanes[lane] = *value;
            }
            pose
        })
    }

    /// Checks a batch of configurations: whole rows, finite values.
    fn check_batch(&self, q: &[f64]) -> Result<(), RobotError> {
        let dof = self.dof();
        if !q.len().is_multiple_of(dof) {
            return Err(RobotError::WrongDof {
                chain: self.name(),
                expected: dof,
                got: q.len(),
            });
        }
        if let Some(index) = q.iter().position(|v| !v.is_finite()) {
            return Err(RobotError::NonFiniteJoint { index });
        }
        Ok(())
    }
}

/// Fills `values[j]` with joint `j` of up to four configurations (`rows`, `dof` values each),
/// one per lane; missing lanes repeat the last configuration.
#[cfg(target_arch = "x86_64")]
fn fill_lanes(values: &mut [[f64; 4]], rows: &[f64], dof: usize) {
    let count = rows.len() / dof;
    for (j, lanes) in values.iter_mut().enumerate() {
        *lanes = std::array::from_fn(|lane| rows[lane.min(count - 1) * dof + j]);
    }
}

/// The four poses of a lane group.
#[cfg(target_arch = "x86_64")]
fn lane_poses(poses: &avx2::Poses4) -> [IsometryMatrix3<f64>; 4] {
    // SAFETY: `__m256d` and `[f64; 4]` have the same size and every bit pattern is valid.
    let lanes = |v: &std::arch::x86_64::__m256d| unsafe {
        std::mem::transmute::<std::arch::x86_64::__m256d, [f64; 4]>(*v)
    };
    let rotation = poses.rotation.each_ref().map(|c| c.each_ref().map(lanes));
    let origin = poses.origin.each_ref().map(lanes);
    std::array::from_fn(|lane| {
        pose_from_columns(
            &rotation.map(|c| c.map(|v| v[lane])),
            &origin.map(|v| v[lane]),
        )
    })
}
