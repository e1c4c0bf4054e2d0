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
//! * CRBA: composite inertias `Yᶜᵢ = Σⱼ≥ᵢ Yⱼ`, `Mₖᵢ = Sₖ · Yᶜᵢ Sᵢ` for `k ≤ i`. Each body's
//!   inertia about its centre is kept as `λ 1 − a aᵀ − b bᵀ` (its principal spread, from one
//!   eigen-decomposition when the model or the payload is set), so turning it into the base
//!   frame takes two rotations of a vector instead of `R I Rᵀ`; the bodies are placed four at
//!   a time, lane by lane (four-lane vector instructions where the processor has them), and
//!   summed in the backward sweep.

use super::{BodyLanes, Dynamics, DynamicsData, PlacedLanes, SegmentBody};
use crate::robot::chain::MotionKind;
use nalgebra::{IsometryMatrix3, Vector3};

/// The composite of bodies about the base origin, base axes, as the CRBA sums it: mass `m`
/// (kg), first moment `h = m·c` (kg·m), and the rotational inertia about the origin
/// `I_O = κ 1 − P` (kg·m²) kept as the scalar `κ` and the symmetric `P` (upper triangle
/// `xx, xy, xz, yy, yz, zz`). A body with centre `c` and inertia `λ 1 − a aᵀ − b bᵀ`
/// (base axes, [`super::PrincipalSpread`]) adds `κ += λ + m ‖c‖²` and
/// `P += a aᵀ + b bᵀ + m c cᵀ` (the parallel-axis term `m (‖c‖² 1 − c cᵀ)` folded in).
#[derive(Debug, Clone, Copy)]
struct Composite {
    mass: f64,
    first_moment: Vector3<f64>,
    scalar: f64,
    outer: [f64; 6],
}

impl Composite {
    const ZERO: Self = Self {
        mass: 0.0,
        first_moment: Vector3::new(0.0, 0.0, 0.0),
        scalar: 0.0,
        outer: [0.0; 6],
    };

    /// Adds the body of mass `mass` placed in lane `lane` of `placed`.
    #[inline(always)]
    fn add(&mut self, mass: f64, placed: &PlacedLanes, lane: usize) {
        self.mass += mass;
        for (sum, row) in self.first_moment.iter_mut().zip(&placed.first_moment) {
            *sum += row[lane];
        }
        self.scalar += placed.scalar[lane];
        for (sum, row) in self.outer.iter_mut().zip(&placed.outer) {
            *sum += row[lane];
        }
    }

    /// `(I_O ω + h × v, m v − h × ω)`: the composite's spatial inertia times a motion `(ω, v)`.
    #[inline(always)]
    fn apply(&self, w: &Vector3<f64>, v: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
        let [xx, xy, xz, yy, yz, zz] = self.outer;
        let outer_w = Vector3::new(
            xx * w[0] + xy * w[1] + xz * w[2],
            xy * w[0] + yy * w[1] + yz * w[2],
            xz * w[0] + yz * w[1] + zz * w[2],
        );
        let h = &self.first_moment;
        (
            w * self.scalar - outer_w + h.cross(v),
            v * self.mass - h.cross(w),
        )
    }
}

/// Places four bodies at once (lane `l`: the body of `bodies` in the frame `frames[l]`,
/// base frame): their first moments and the two parts of their rotational inertias about the
/// base origin ([`Composite`]), into `placed`.
#[inline(always)]
fn place_four(bodies: &BodyLanes, frames: [&IsometryMatrix3<f64>; 4], placed: &mut PlacedLanes) {
    let mut rotation = [[[0.0; 4]; 3]; 3];
    let mut origin = [[0.0; 4]; 3];
    for (l, frame) in frames.iter().enumerate() {
        let r = frame.rotation.matrix();
        for row in 0..3 {
            for col in 0..3 {
                rotation[row][col][l] = r[(row, col)];
            }
            origin[row][l] = frame.translation.vector[row];
        }
    }
    let mut c = turn_lanes(&rotation, &bodies.com);
    let mut h = [[0.0; 4]; 3];
    for row in 0..3 {
        for l in 0..4 {
            c[row][l] += origin[row][l];
            h[row][l] = c[row][l] * bodies.mass[l];
        }
    }
    let (a, b) = (
        turn_lanes(&rotation, &bodies.axes[0]),
        turn_lanes(&rotation, &bodies.axes[1]),
    );
    const PAIRS: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];
    for (out, (i, j)) in placed.outer.iter_mut().zip(PAIRS) {
        for l in 0..4 {
            out[l] = a[i][l] * a[j][l] + b[i][l] * b[j][l] + h[i][l] * c[j][l];
        }
    }
    for l in 0..4 {
        placed.scalar[l] =
            bodies.peak[l] + (h[0][l] * c[0][l] + h[1][l] * c[1][l] + h[2][l] * c[2][l]);
    }
    placed.first_moment = h;
}

/// `R x` in four lanes (`rotation[row][col][lane]`, `x[row][lane]`).
#[inline(always)]
fn turn_lanes(rotation: &[[[f64; 4]; 3]; 3], x: &[[f64; 4]; 3]) -> [[f64; 4]; 3] {
    let mut turned = [[0.0; 4]; 3];
    for (out, r) in turned.iter_mut().zip(rotation) {
        for l in 0..4 {
            out[l] = r[0][l] * x[0][l] + r[1][l] * x[1][l] + r[2][l] * x[2][l];
        }
    }
    turned
}

/// A segment's motion subspace about the base origin from its placed frame (base frame):
/// `(z, p × z)` for a turn about the frame's `z` axis through its origin `p`, `(0, z)` for a
/// slide along it.
#[inline(always)]
fn motion(kind: MotionKind, frame: &IsometryMatrix3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let z = frame.rotation.matrix().column(2).into_owned();
    match kind {
        MotionKind::Revolute => (z, frame.translation.vector.cross(&z)),
        MotionKind::Prismatic => (Vector3::zeros(), z),
    }
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
            (*motion_w, *motion_v) = motion(s.kind, frame);
        }
    }

    /// Segment `i`'s body in its aligned frame; the last segment's is `loaded_last` when a
    /// payload is joined to it (`DynamicsData::loaded_last`).
    #[inline(always)]
    fn body<'a>(&'a self, loaded_last: Option<&'a SegmentBody>, i: usize) -> &'a SegmentBody {
        match loaded_last {
            Some(loaded) if i + 1 == self.segments.len() => loaded,
            _ => &self.segments[i].body,
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
            let body = self.body(data.loaded_last.as_ref(), i);
            let frame = &data.frames[i];
            let r = frame.rotation.matrix();
            let p = &frame.translation.vector;
            mass += body.mass;
            moment += (p + r * body.com) * body.mass;
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
            let SegmentBody {
                mass, com, inertia, ..
            } = self.body(data.loaded_last.as_ref(), i);
            let frame = &data.frames[i];
            let r = frame.rotation.matrix();
            let c = frame.translation.vector + r * com;
            // The centre of mass's classical acceleration (gravity included through the base).
            let velocity = v + w.cross(&c);
            let f = (dv + dw.cross(&c) + w.cross(&velocity)) * *mass;
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

    /// `M(q)` without checks; `out` is the column-major dof × dof storage. One backward sweep
    /// places the bodies about the base origin, sums them into the composite inertias and
    /// keeps each column's force `Fᵢ = Yᶜᵢ Sᵢ`; then each column's upper part
    /// `Mₖᵢ = Sₖ · Fᵢ` (`k ≤ i`, contiguous in column-major storage) is evaluated four rows at
    /// a time from the motions stored component by component, and the lower triangle is
    /// mirrored from it. On a processor with AVX2 the same code is compiled for it
    /// (three-operand and four-lane instructions, no fused multiply–add: the same IEEE
    /// operations, the same bits).
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
        for (g, (bodies, placed)) in data
            .body_lanes
            .iter()
            .zip(data.placed_lanes.iter_mut())
            .enumerate()
        {
            // Lanes past the last segment hold empty bodies: any frame places them at zero.
            let frames = std::array::from_fn(|l| &data.frames[(4 * g + l).min(n - 1)]);
            place_four(bodies, frames, placed);
        }
        let mut composite = Composite::ZERO;
        let stride = if self.has_mimic { n } else { self.dof };
        let target: &mut [f64] = if self.has_mimic {
            &mut data.segment_mass
        } else {
            out
        };
        for i in (0..n).rev() {
            let (g, lane) = (i / 4, i % 4);
            composite.add(data.body_lanes[g].mass[lane], &data.placed_lanes[g], lane);
            let (force_n, force_f) = composite.apply(&data.motion_w[i], &data.motion_v[i]);
            for (k, (kw, kv)) in data.motion_w[..=i]
                .iter()
                .zip(&data.motion_v[..=i])
                .enumerate()
            {
                let entry = kw.dot(&force_n) + kv.dot(&force_f);
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
