//! The dynamics passes, in the base frame (Featherstone's algorithms in absolute
//! coordinates). A spatial motion vector is `(ω, v)`: the angular velocity and the velocity of
//! the body point at the base origin; a spatial force is `(n, f)`: the moment about the base
//! origin and the force. A segment's joint motion is `S = (z, p × z)` (revolute, axis `z`
//! through `p`) or `(0, z)` (prismatic); a body's spatial inertia about the origin is
//! `(m, h = m·c, I_O)`, mapping `(ω, v)` to `(I_O ω + h × v, m v − h × ω)`.
//!
//! Every pass starts with the forward kinematics of the segment frames (the FK kernel's
//! operations: `p += R t`, `R = R · E`, a turn about `z` or a slide along it); a payload is
//! part of the last segment's body (joined once, by `DynamicsData::set_payload`). Then:
//! * gravity: backward sums of mass and first moment; `τᵢ = zᵢ · ((Cᵢ − Mᵢ pᵢ) × (−g))`;
//! * RNEA: `Vᵢ = Vᵢ₋₁ + Sᵢ q̇ᵢ`, `Aᵢ = Aᵢ₋₁ + Sᵢ q̈ᵢ + Vᵢ × Sᵢ q̇ᵢ` from `A₀ = (0, −g)`,
//!   `Fᵢ = Yᵢ Aᵢ + Vᵢ ×* Yᵢ Vᵢ` evaluated as Newton–Euler at the centre of mass `c`
//!   (`f = m (v̇ + ω̇ × c + ω × (v + ω × c))`, `n_c = R (I ω̇_b + ω_b × I ω_b)` with the body's
//!   own inertia `I` and `ω_b = Rᵀ ω`, `n = n_c + c × f`), then `τᵢ = Sᵢ · Σⱼ≥ᵢ Fⱼ`;
//! * CRBA: composite inertias `Yᶜᵢ = Σⱼ≥ᵢ Yⱼ`, `Mₖᵢ = Sₖ · Yᶜᵢ Sᵢ` for `k ≤ i`.

use super::{Dynamics, DynamicsData, WorldBody};
use crate::robot::chain::MotionKind;
use crate::robot::spec::RigidBody;
use nalgebra::{Matrix3, Vector3};

/// `(I_O ω + h × v, m v − h × ω)`: a body's spatial inertia times a motion `(ω, v)`.
#[inline(always)]
fn apply(body: &WorldBody, w: &Vector3<f64>, v: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    (
        body.rotational * w + body.first_moment.cross(v),
        body.mass * v - body.first_moment.cross(w),
    )
}

/// A body (mass kg, centre `com` m and inertia about it kg·m², in a frame with rotation
/// `rotation` and origin `origin` in the base) about the base origin along base axes.
#[inline(always)]
fn world_body(
    mass: f64,
    com: &Vector3<f64>,
    inertia: &Matrix3<f64>,
    rotation: &Matrix3<f64>,
    origin: &Vector3<f64>,
) -> WorldBody {
    let c = origin + rotation * com;
    let mut turned = symmetric_sandwich(rotation, inertia);
    let (x, y, z) = (c[0], c[1], c[2]);
    let (mx, my, mz) = (mass * x, mass * y, mass * z);
    // + m (‖c‖² 1 − c cᵀ)
    turned[(0, 0)] += my * y + mz * z;
    turned[(1, 1)] += mx * x + mz * z;
    turned[(2, 2)] += mx * x + my * y;
    let (xy, xz, yz) = (mx * y, mx * z, my * z);
    turned[(0, 1)] -= xy;
    turned[(1, 0)] -= xy;
    turned[(0, 2)] -= xz;
    turned[(2, 0)] -= xz;
    turned[(1, 2)] -= yz;
    turned[(2, 1)] -= yz;
    WorldBody {
        mass,
        first_moment: c * mass,
        rotational: turned,
    }
}

/// `R I Rᵀ` for a symmetric `I`, computing the upper triangle and mirroring it.
#[inline(always)]
fn symmetric_sandwich(r: &Matrix3<f64>, inertia: &Matrix3<f64>) -> Matrix3<f64> {
    let a = r * inertia;
    let entry =
        |i: usize, j: usize| a[(i, 0)] * r[(j, 0)] + a[(i, 1)] * r[(j, 1)] + a[(i, 2)] * r[(j, 2)];
    let (xx, xy, xz, yy, yz, zz) = (
        entry(0, 0),
        entry(0, 1),
        entry(0, 2),
        entry(1, 1),
        entry(1, 2),
        entry(2, 2),
    );
    Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz)
}

impl Dynamics {
    /// Segment `i`'s joint value, rate and acceleration from the independent ones.
    #[inline(always)]
    fn drive(&self, i: usize, x: &[f64], with_offset: bool) -> f64 {
        let s = &self.segments[i];
        if self.has_mimic {
            s.multiplier * x[s.source] + if with_offset { s.offset } else { 0.0 }
        } else {
            x[i]
        }
    }

    /// Each segment's aligned frame (base frame) by the FK kernel's link-frame pass (AVX2 when
    /// the processor has it).
    #[inline(always)]
    fn place(&self, data: &mut DynamicsData, q: &[f64]) {
        if self.has_mimic {
            let segments = &self.segments;
            self.frames.frames_into(
                |i| segments[i].multiplier * q[segments[i].source] + segments[i].offset,
                &mut data.frames,
            );
        } else {
            self.frames.frames_into(|i| q[i], &mut data.frames);
        }
    }

    /// Each segment's motion subspace `S = (z, p × z)` (revolute) or `(0, z)` (prismatic)
    /// about the base origin, from the placed frames.
    #[inline(always)]
    fn place_motions(&self, data: &mut DynamicsData) {
        let placed = self
            .segments
            .iter()
            .zip(&data.frames)
            .zip(data.motion_w.iter_mut().zip(data.motion_v.iter_mut()));
        for ((s, frame), (motion_w, motion_v)) in placed {
            let z = frame.rotation.matrix().column(2).into_owned();
            (*motion_w, *motion_v) = match s.kind {
                MotionKind::Revolute => (z, frame.translation.vector.cross(&z)),
                MotionKind::Prismatic => (Vector3::zeros(), z),
            };
        }
    }

    /// Segment `i`'s body in its aligned frame: mass (kg), centre of mass (m), inertia about
    /// it (kg·m²); the last segment's is `loaded_last` when a payload is joined to it
    /// (`DynamicsData::loaded_last`).
    #[inline(always)]
    fn body<'a>(
        &'a self,
        loaded_last: Option<&'a RigidBody>,
        i: usize,
    ) -> (f64, &'a Vector3<f64>, &'a Matrix3<f64>) {
        match loaded_last {
            Some(loaded) if i + 1 == self.segments.len() => {
                (loaded.mass, &loaded.com, &loaded.inertia)
            }
            _ => {
                let s = &self.segments[i];
                (s.mass, &s.com, &s.inertia)
            }
        }
    }

    /// Adds the segment torques of `data.segment_tau` into `tau` through the drives (mimic
    /// followers reach their leader times the multiplier).
    #[inline(always)]
    fn gather(&self, data: &DynamicsData, tau: &mut [f64]) {
        if !self.has_mimic {
            tau.copy_from_slice(&data.segment_tau);
            return;
        }
        tau.fill(0.0);
        for (s, t) in self.segments.iter().zip(&data.segment_tau) {
            tau[s.source] += s.multiplier * t;
        }
    }

    /// `g(q)` without checks: one backward sum of masses and first moments over the placed
    /// frames.
    pub(super) fn gravity_unchecked(&self, data: &mut DynamicsData, q: &[f64], tau: &mut [f64]) {
        self.place(data, q);
        self.gravity_sweep(data, tau);
    }

    /// `g(q)` into `tau` from the frames already placed.
    #[inline(always)]
    fn gravity_sweep(&self, data: &mut DynamicsData, tau: &mut [f64]) {
        let lift = -self.gravity;
        let mut mass = 0.0;
        let mut moment = Vector3::<f64>::zeros();
        for i in (0..self.segments.len()).rev() {
            let (m, com, _) = self.body(data.loaded_last.as_ref(), i);
            let frame = &data.frames[i];
            let r = frame.rotation.matrix();
            let p = &frame.translation.vector;
            mass += m;
            moment += (p + r * com) * m;
            let z = r.column(2);
            data.segment_tau[i] = match self.segments[i].kind {
                MotionKind::Revolute => z.dot(&(moment - p * mass).cross(&lift)),
                MotionKind::Prismatic => z.dot(&lift) * mass,
            };
        }
        self.gather(data, tau);
    }

    /// `g(q)` into `tau` and, into `per_kg`, the torques that hold one kilogram at `point`
    /// (tool frame, m) still: `τᵢ = zᵢ · ((c − pᵢ) × (−g))` (revolute) or `zᵢ · (−g)`
    /// (prismatic) with `c` the point in the base frame, from one placement of the frames,
    /// without checks.
    pub(super) fn gravity_and_point_load_unchecked(
        &self,
        data: &mut DynamicsData,
        q: &[f64],
        point: &Vector3<f64>,
        tau: &mut [f64],
        per_kg: &mut [f64],
    ) {
        self.gravity_unchecked(data, q, tau);
        let Some(last) = data.frames.last() else {
            per_kg.fill(0.0);
            return;
        };
        let c = last.translation.vector
            + last.rotation.matrix() * (self.tail_rotation * point + self.tail_translation);
        let lift = -self.gravity;
        for ((s, frame), t) in self
            .segments
            .iter()
            .zip(&data.frames)
            .zip(data.segment_tau.iter_mut())
        {
            let z = frame.rotation.matrix().column(2);
            *t = match s.kind {
                MotionKind::Revolute => z.dot(&(c - frame.translation.vector).cross(&lift)),
                MotionKind::Prismatic => z.dot(&lift),
            };
        }
        self.gather(data, per_kg);
    }

    /// `g(q)` and the tool frame's geometric Jacobian (6 × dof column-major storage `jacobian`,
    /// rows `[v; ω]`, base frame) from one placement of the frames, without checks.
    pub(super) fn gravity_and_jacobian_unchecked(
        &self,
        data: &mut DynamicsData,
        q: &[f64],
        tau: &mut [f64],
        jacobian: &mut [f64],
    ) {
        self.gravity_unchecked(data, q, tau);
        let Some(last) = data.frames.last() else {
            return;
        };
        let tool = last.translation.vector + last.rotation.matrix() * self.tail_translation;
        if self.has_mimic {
            jacobian.fill(0.0);
        }
        for (s, frame) in self.segments.iter().zip(&data.frames) {
            let z = frame.rotation.matrix().column(2).into_owned();
            let (linear, angular) = match s.kind {
                MotionKind::Revolute => (z.cross(&(tool - frame.translation.vector)), z),
                MotionKind::Prismatic => (z, Vector3::zeros()),
            };
            let column = &mut jacobian[6 * s.source..6 * s.source + 6];
            let m = if self.has_mimic { s.multiplier } else { 1.0 };
            for (entry, value) in column.iter_mut().zip(linear.iter().chain(angular.iter())) {
                if self.has_mimic {
                    *entry += m * value;
                } else {
                    *entry = *value;
                }
            }
        }
    }

    /// `τ(q, q̇, q̈)` without checks.
    pub(super) fn rnea_unchecked(
        &self,
        data: &mut DynamicsData,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        tau: &mut [f64],
    ) {
        self.place(data, q);
        self.place_motions(data);
        self.newton_euler_forces(data, Some(qd), qdd, -self.gravity);
        self.joint_torques(data, tau);
    }

    /// Along a path `q(s)` at `q` with `dq = q'(s)` and `ddq = q''(s)`, without checks: `g(q)`,
    /// `M(q) q'` and `M(q) q'' + C(q, q') q'`, from one placement of the frames.
    pub(super) fn path_torques_unchecked(
        &self,
        data: &mut DynamicsData,
        [q, dq, ddq]: [&[f64]; 3],
        [g, a, b]: [&mut [f64]; 3],
    ) {
        self.place(data, q);
        self.place_motions(data);
        self.gravity_sweep(data, g);
        self.newton_euler_forces(data, None, dq, Vector3::zeros());
        self.joint_torques(data, a);
        self.newton_euler_forces(data, Some(dq), ddq, Vector3::zeros());
        self.joint_torques(data, b);
    }

    /// Each body's spatial force about the base origin into `data.force_n` / `force_f`, for
    /// joint rates `qd` (`None`: at rest) and accelerations `qdd`, the base accelerating at
    /// `base` (`−g` for gravity). Velocities and accelerations are propagated about the base
    /// origin; each body's force is Newton–Euler's at its centre of mass (the rotational part
    /// in the body's own frame, where its inertia is constant), moved to the base origin.
    #[inline(always)]
    fn newton_euler_forces(
        &self,
        data: &mut DynamicsData,
        qd: Option<&[f64]>,
        qdd: &[f64],
        base: Vector3<f64>,
    ) {
        let (mut w, mut v) = (Vector3::<f64>::zeros(), Vector3::<f64>::zeros());
        let (mut dw, mut dv) = (Vector3::<f64>::zeros(), base);
        for i in 0..self.segments.len() {
            let accel = self.drive(i, qdd, false);
            let (sw, sv) = (data.motion_w[i], data.motion_v[i]);
            if let Some(qd) = qd {
                let rate = self.drive(i, qd, false);
                let (jw, jv) = (sw * rate, sv * rate);
                w += jw;
                v += jv;
                // A += S q̈ + V × (S q̇).
                dw += sw * accel + w.cross(&jw);
                dv += sv * accel + w.cross(&jv) + v.cross(&jw);
            } else {
                dw += sw * accel;
                dv += sv * accel;
            }
            let (mass, com, inertia) = self.body(data.loaded_last.as_ref(), i);
            let frame = &data.frames[i];
            let r = frame.rotation.matrix();
            let c = frame.translation.vector + r * com;
            // The centre of mass's classical acceleration (gravity included through the base).
            let velocity = v + w.cross(&c);
            let f = (dv + dw.cross(&c) + w.cross(&velocity)) * mass;
            let (w_body, dw_body) = (r.tr_mul(&w), r.tr_mul(&dw));
            let n_body = inertia * dw_body + w_body.cross(&(inertia * w_body));
            data.force_n[i] = r * n_body + c.cross(&f);
            data.force_f[i] = f;
        }
    }

    /// The joint torques `τᵢ = Sᵢ · Σⱼ≥ᵢ Fⱼ` of the forces in `data` into `tau`.
    #[inline(always)]
    fn joint_torques(&self, data: &mut DynamicsData, tau: &mut [f64]) {
        let (mut sum_n, mut sum_f) = (Vector3::<f64>::zeros(), Vector3::<f64>::zeros());
        for i in (0..self.segments.len()).rev() {
            sum_n += data.force_n[i];
            sum_f += data.force_f[i];
            data.segment_tau[i] = data.motion_w[i].dot(&sum_n) + data.motion_v[i].dot(&sum_f);
        }
        self.gather(data, tau);
    }

    /// `M(q)` without checks; `out` is the column-major dof × dof storage. The bodies are
    /// placed about the base origin in the backward sweep that sums them. On a processor with
    /// AVX2 the same code is compiled for it (three-operand instructions, no fused
    /// multiply–add: the same IEEE operations, the same bits).
    pub(super) fn crba_unchecked(&self, data: &mut DynamicsData, q: &[f64], out: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::has_avx2() {
            // SAFETY: the processor supports AVX2 (checked just above).
            unsafe { self.crba_avx2(data, q, out) };
            return;
        }
        self.crba_portable(data, q, out);
    }

    /// [`Dynamics::crba_portable`] compiled for AVX2.
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn crba_avx2(&self, data: &mut DynamicsData, q: &[f64], out: &mut [f64]) {
        self.crba_portable(data, q, out);
    }

    /// The CRBA sweep (see [`Dynamics::crba_unchecked`]).
    #[inline(always)]
    pub(super) fn crba_portable(&self, data: &mut DynamicsData, q: &[f64], out: &mut [f64]) {
        self.place(data, q);
        self.place_motions(data);
        let n = self.segments.len();
        let mut composite = WorldBody::ZERO;
        let stride = if self.has_mimic { n } else { self.dof };
        let loaded_last = data.loaded_last.as_ref();
        let target: &mut [f64] = if self.has_mimic {
            &mut data.segment_mass
        } else {
            out
        };
        for i in (0..n).rev() {
            let (mass, com, inertia) = self.body(loaded_last, i);
            let frame = &data.frames[i];
            let body = world_body(
                mass,
                com,
                inertia,
                frame.rotation.matrix(),
                &frame.translation.vector,
            );
            composite.mass += body.mass;
            composite.first_moment += body.first_moment;
            composite.rotational += body.rotational;
            let (fn_, ff) = apply(&composite, &data.motion_w[i], &data.motion_v[i]);
            for (k, (kw, kv)) in data.motion_w[..=i]
                .iter()
                .zip(&data.motion_v[..=i])
                .enumerate()
            {
                let entry = kw.dot(&fn_) + kv.dot(&ff);
                target[k * stride + i] = entry;
                target[i * stride + k] = entry;
            }
        }
        if self.has_mimic {
            out.fill(0.0);
            let dof = self.dof;
            for (a, sa) in self.segments.iter().enumerate() {
                for (b, sb) in self.segments.iter().enumerate() {
                    out[sb.source * dof + sa.source] +=
                        sa.multiplier * sb.multiplier * data.segment_mass[b * n + a];
                }
            }
        }
    }
}
