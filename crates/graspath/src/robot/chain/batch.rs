//! Forward kinematics of many configurations per call. On x86-64 processors with AVX2, chains
//! without mimic joints run four configurations at once, one per vector lane, each lane doing
//! the scalar pass's operations (bit-identical to one call per configuration).
//!
//! Two kinds of entry point:
//!
//! * [`Chain::for_each_pose_and_jacobian`] and [`Chain::for_each_pose`] hand each result to a
//!   closure, on the calling thread;
//! * [`Chain::batch_into`] (caller's buffers) and [`Chain::batch_poses`],
//!   [`Chain::batch_jacobians`], [`Chain::batch_poses_and_jacobians`] (new buffers) write
//!   row-major arrays — the layout of numpy's `(n, 4, 4)` and `(n, 6, dof)` — in parallel
//!   (rayon), each value written once, straight from the vector lanes into its place.

#[cfg(target_arch = "x86_64")]
use super::{avx2, pose_from_columns};
use super::{Chain, MAX_JOINTS};
use crate::robot::error::RobotError;
use nalgebra::IsometryMatrix3;
use rayon::prelude::*;

/// Configurations per parallel task of [`Chain::batch_into`]: whole lane groups, and about
/// 120 kB of a 7-joint chain's poses and Jacobians, which stay in the core's cache while they
/// are written.
pub(crate) const BATCH_CHUNK: usize = 256;

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
        if self.drives.is_none() && dof > 0 && crate::cpu::has_avx2() {
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
        if self.drives.is_none() && dof > 0 && crate::cpu::has_avx2() {
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
        if self.drives.is_none() && crate::cpu::has_avx2() {
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

impl Chain {
    /// Tip poses and geometric Jacobians of many configurations, written into the caller's
    /// row-major buffers in parallel (rayon, 256 configurations per task).
    ///
    /// `q` holds `n` configurations one after another (`dof` values each, rad / m). `poses`,
    /// when given, receives `n` homogeneous 4 × 4 matrices `base_from_tip` (16 values each,
    /// row after row, metres); `jacobians`, when given, `n` geometric Jacobians of the tip in
    /// the base frame as 6 × dof matrices (rows `[v; ω]`, row after row: `v` in m/rad or
    /// per metre for prismatic joints, `ω` in rad/rad). These are the layouts of numpy's
    /// C-ordered `(n, 4, 4)` and `(n, 6, dof)` arrays. Every value is bit-identical to
    /// [`Chain::pose_and_jacobian_into`] on that configuration alone, at any thread count.
    ///
    /// For a chain without joints `q` is empty and `n` is taken from `poses` (16 values per
    /// configuration; the Jacobians are empty).
    ///
    /// Errors: `q` not a whole number of configurations ([`RobotError::WrongDof`]), a buffer
    /// of another length than `n` configurations need ([`RobotError::WrongBufferLength`]),
    /// checked before anything is written; a value of `q` that is not finite
    /// ([`RobotError::NonFiniteJoint`], the first one, indexed into `q`), found while the
    /// buffers are written: the buffers then hold unspecified values.
    pub fn batch_into(
        &self,
        q: &[f64],
        poses: Option<&mut [f64]>,
        jacobians: Option<&mut [f64]>,
    ) -> Result<(), RobotError> {
        let dof = self.dof();
        let n = self.batch_count(q, poses.as_deref(), jacobians.as_deref())?;
        if dof == 0 {
            // No joint: every pose is the fixed tip pose, the Jacobians are empty.
            let pose = self.pose_unchecked(&[]);
            if let Some(poses) = poses {
                poses
                    .par_chunks_mut(16)
                    .with_min_len(BATCH_CHUNK)
                    .for_each(|out| write_pose_rows(out, &pose));
            }
            return Ok(());
        }
        debug_assert_eq!(q.len(), n * dof);
        // Each task checks its rows while they are in cache, then writes its results.
        let run = |q: &[f64], poses: Option<&mut [f64]>, jacobians: Option<&mut [f64]>| {
            if !q.iter().all(|v| v.is_finite()) {
                return Err(());
            }
            self.rows_into(q, poses, jacobians);
            Ok(())
        };
        let rows = q.par_chunks(dof * BATCH_CHUNK);
        let result = match (poses, jacobians) {
            (Some(poses), Some(jacobians)) => poses
                .par_chunks_mut(16 * BATCH_CHUNK)
                .zip(jacobians.par_chunks_mut(6 * dof * BATCH_CHUNK))
                .zip(rows)
                .try_for_each(|((p, j), q)| run(q, Some(p), Some(j))),
            (Some(poses), None) => poses
                .par_chunks_mut(16 * BATCH_CHUNK)
                .zip(rows)
                .try_for_each(|(p, q)| run(q, Some(p), None)),
            (None, Some(jacobians)) => jacobians
                .par_chunks_mut(6 * dof * BATCH_CHUNK)
                .zip(rows)
                .try_for_each(|(j, q)| run(q, None, Some(j))),
            (None, None) => rows.try_for_each(|q| run(q, None, None)),
        };
        result.map_err(|()| RobotError::NonFiniteJoint {
            index: q.iter().position(|v| !v.is_finite()).unwrap_or(0),
        })
    }

    /// The tip poses of the configurations `q` (`dof` values each) in a new row-major buffer
    /// of 16 values per configuration, computed in parallel: [`Chain::batch_into`] with poses
    /// only. A chain without joints gives no pose (its `q` names no configuration count).
    pub fn batch_poses(&self, q: &[f64]) -> Result<Vec<f64>, RobotError> {
        let mut poses = vec![0.0; 16 * self.batch_len(q)?];
        self.batch_into(q, Some(&mut poses), None)?;
        Ok(poses)
    }

    /// The geometric Jacobians (base frame, rows `[v; ω]`) of the configurations `q` in a new
    /// row-major buffer of `6 · dof` values per configuration, computed in parallel:
    /// [`Chain::batch_into`] with Jacobians only.
    pub fn batch_jacobians(&self, q: &[f64]) -> Result<Vec<f64>, RobotError> {
        let mut jacobians = vec![0.0; 6 * self.dof() * self.batch_len(q)?];
        self.batch_into(q, None, Some(&mut jacobians))?;
        Ok(jacobians)
    }

    /// The tip poses and geometric Jacobians of the configurations `q`, in new row-major
    /// buffers (16 and `6 · dof` values per configuration), computed in parallel in one pass:
    /// [`Chain::batch_into`] with both.
    pub fn batch_poses_and_jacobians(&self, q: &[f64]) -> Result<(Vec<f64>, Vec<f64>), RobotError> {
        let n = self.batch_len(q)?;
        let mut poses = vec![0.0; 16 * n];
        let mut jacobians = vec![0.0; 6 * self.dof() * n];
        self.batch_into(q, Some(&mut poses), Some(&mut jacobians))?;
        Ok((poses, jacobians))
    }

    /// The number of configurations in `q` (none for a chain without joints).
    fn batch_len(&self, q: &[f64]) -> Result<usize, RobotError> {
        let dof = self.dof();
        if dof == 0 {
            return Ok(0);
        }
        if !q.len().is_multiple_of(dof) {
            return Err(RobotError::WrongDof {
                chain: self.name(),
                expected: dof,
                got: q.len(),
            });
        }
        Ok(q.len() / dof)
    }

    /// The number of configurations of a [`Chain::batch_into`] call, with the buffers'
    /// lengths checked against it.
    fn batch_count(
        &self,
        q: &[f64],
        poses: Option<&[f64]>,
        jacobians: Option<&[f64]>,
    ) -> Result<usize, RobotError> {
        let dof = self.dof();
        let n = if dof == 0 {
            if !q.is_empty() {
                return Err(RobotError::WrongDof {
                    chain: self.name(),
                    expected: 0,
                    got: q.len(),
                });
            }
            poses.map_or(0, |p| p.len() / 16)
        } else {
            self.batch_len(q)?
        };
        let check = |what: &'static str, buffer: Option<&[f64]>, width: usize| match buffer {
            Some(b) if b.len() != width * n => Err(RobotError::WrongBufferLength {
                what,
                expected: width * n,
                got: b.len(),
            }),
            _ => Ok(()),
        };
        check("pose", poses, 16)?;
        check("Jacobian", jacobians, 6 * dof)?;
        Ok(n)
    }

    /// Writes the results of checked, finite configurations `q` into row-major buffers sized
    /// for them, on the calling thread: on AVX2 processors, four at a time straight from the
    /// vector lanes.
    fn rows_into(
        &self,
        q: &[f64],
        mut poses: Option<&mut [f64]>,
        mut jacobians: Option<&mut [f64]>,
    ) {
        let dof = self.dof();
        #[cfg(target_arch = "x86_64")]
        if self.drives.is_none() && dof > 0 && crate::cpu::has_avx2() {
            // Without mimic joints there is one segment per joint (at most MAX_JOINTS).
            let n = self.segments.len();
            let mut values = [[0.0; 4]; MAX_JOINTS];
            let mut lanes = [[0.0; 4]; 6 * MAX_JOINTS];
            for (group, rows) in q.chunks(4 * dof).enumerate() {
                let values = &mut values[..n];
                fill_lanes(values, rows, dof);
                let jacobian_lanes = jacobians.is_some().then_some(&mut lanes[..6 * n]);
                // SAFETY: AVX2 is present (checked above); the buffers have the sizes asked.
                let tip =
                    unsafe { avx2::forward4(&self.segments, values, jacobian_lanes, self.tail()) };
                let count = rows.len() / dof;
                let first = 4 * group;
                if let Some(poses) = poses.as_deref_mut() {
                    // SAFETY: AVX2 is present (checked above).
                    unsafe { avx2::store_pose_rows(&tip, count, &mut poses[16 * first..]) };
                }
                if let Some(jacobians) = jacobians.as_deref_mut() {
                    // SAFETY: AVX2 is present (checked above).
                    unsafe {
                        avx2::store_jacobian_rows(
                            &lanes[..6 * n],
                            dof,
                            count,
                            &mut jacobians[6 * dof * first..],
                        );
                    }
                }
            }
            return;
        }
        let mut column_major = [0.0; 6 * MAX_JOINTS];
        let column_major = &mut column_major[..6 * dof];
        for (k, row) in q.chunks(dof.max(1)).enumerate() {
            let pose = self.pose_and_jacobian_unchecked(row, column_major);
            if let Some(poses) = poses.as_deref_mut() {
                write_pose_rows(&mut poses[16 * k..16 * (k + 1)], &pose);
            }
            if let Some(jacobians) = jacobians.as_deref_mut() {
                let out = &mut jacobians[6 * dof * k..6 * dof * (k + 1)];
                for (c, column) in column_major.chunks_exact(6).enumerate() {
                    for (r, value) in column.iter().enumerate() {
                        out[r * dof + c] = *value;
                    }
                }
            }
        }
    }
}

/// Writes the 16 row-major values of the homogeneous matrix of `pose` into `out`.
fn write_pose_rows(out: &mut [f64], pose: &IsometryMatrix3<f64>) {
    let (rotation, origin) = (pose.rotation.matrix(), &pose.translation.vector);
    for r in 0..3 {
        for c in 0..3 {
            out[4 * r + c] = rotation[(r, c)];
        }
        out[4 * r + 3] = origin[r];
    }
    out[12..16].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
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
