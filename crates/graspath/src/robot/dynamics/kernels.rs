//! The dynamics passes, in the base frame (Featherstone's algorithms in absolute
//! coordinates). A spatial motion vector is `(ω, v)`: the angular velocity and the velocity of
//! the body point at the base origin; a spatial force is `(n, f)`: the moment about the base
//! origin and the force. A segment's joint motion is `S = (z, p × z)` (revolute, axis `z`
//! through `p`) or `(0, z)` (prismatic); a body's spatial inertia about the origin is
//! `(m, h = m·c, I_O)`, mapping `(ω, v)` to `(I_O ω + h × v, m v − h × ω)`.
//!
//! Every pass starts with the forward kinematics of the segment frames (the FK kernel's
//! operations: `p += R t`, `R = R · E`, a turn about `z` or a slide along it), then:
//! * gravity: backward sums of mass and first moment; `τᵢ = zᵢ · ((Cᵢ − Mᵢ pᵢ) × (−g))`;
//! * RNEA: `Vᵢ = Vᵢ₋₁ + Sᵢ q̇ᵢ`, `Aᵢ = Aᵢ₋₁ + Sᵢ q̈ᵢ + Vᵢ × Sᵢ q̇ᵢ` from `A₀ = (0, −g)`,
//!   `Fᵢ = Yᵢ Aᵢ + Vᵢ ×* Yᵢ Vᵢ`, then `τᵢ = Sᵢ · Σⱼ≥ᵢ Fⱼ`;
//! * CRBA: composite inertias `Yᶜᵢ = Σⱼ≥ᵢ Yⱼ`, `Mₖᵢ = Sₖ · Yᶜᵢ Sᵢ` for `k ≤ i`.

use super::{Dynamics, DynamicsData, WorldBody};
use crate::robot::chain::MotionKind;
use nalgebra::{Matrix3, Vector3};

/// `(I_O ω + h × v, m v − h × ω)`: a body's spatial inertia times a motion `(ω, v)`.
#[inline(always)]
fn apply(body: &WorldBody, w: &Vector3<f64>, v: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    (
        body.rotational * w + body.first_moment.cross(v),
        body.mass * v - body.first_moment.cross(w),
    )
}

/// `‖c‖² 1 − c cᵀ`: the rotational inertia about the origin of a unit point mass at `c`.
#[inline(always)]
fn point_inertia(c: &Vector3<f64>) -> Matrix3<f64> {
    let (x, y, z) = (c[0], c[1], c[2]);
    Matrix3::new(
        y * y + z * z,
        -x * y,
        -x * z,
        -x * y,
        x * x + z * z,
        -y * z,
        -x * z,
        -y * z,
        x * x + y * y,
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
    rotational: bool,
) -> WorldBody {
    let c = origin + rotation * com;
    WorldBody {
        mass,
        first_moment: c * mass,
        rotational: if rotational {
            rotation * inertia * rotation.transpose() + point_inertia(&c) * mass
        } else {
            Matrix3::zeros()
        },
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

    /// The forward pass shared by every kernel: each segment's joint origin and axis (base
    /// frame) and its body about the base origin (with its rotational inertia when
    /// `rotational`), the payload joined to the last segment's body.
    #[inline(always)]
    fn place(&self, data: &mut DynamicsData, q: &[f64], rotational: bool) {
        let mut r = Matrix3::<f64>::identity();
        let mut p = Vector3::<f64>::zeros();
        for (i, s) in self.segments.iter().enumerate() {
            let value = self.drive(i, q, true);
            data.value[i] = value;
            p += r * s.translation;
            let mut turned = r * s.rotation;
            match s.kind {
                MotionKind::Revolute => {
                    let (sin, cos) = crate::robot::trig::sin_cos(value);
                    let x = turned.column(0).into_owned();
                    let y = turned.column(1).into_owned();
                    turned.set_column(0, &(x * cos + y * sin));
                    turned.set_column(1, &(y * cos - x * sin));
                }
                MotionKind::Prismatic => {
                    p += turned.column(2) * value;
                }
            }
            r = turned;
            let z = r.column(2).into_owned();
            data.origin[i] = p;
            data.axis[i] = z;
            (data.motion_w[i], data.motion_v[i]) = match s.kind {
                MotionKind::Revolute => (z, p.cross(&z)),
                MotionKind::Prismatic => (Vector3::zeros(), z),
            };
            data.body[i] = world_body(s.mass, &s.com, &s.inertia, &r, &p, rotational);
        }
        data.tool_rotation = r * self.tail_rotation;
        data.tool_origin = p + r * self.tail_translation;
        if let (Some(payload), Some(last)) = (&data.payload, data.body.last_mut()) {
            let extra = world_body(
                payload.mass,
                &payload.com,
                &payload.inertia,
                &data.tool_rotation,
                &data.tool_origin,
                rotational,
            );
            last.mass += extra.mass;
            last.first_moment += extra.first_moment;
            last.rotational += extra.rotational;
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

    /// `g(q)` without checks.
    pub(super) fn gravity_unchecked(&self, data: &mut DynamicsData, q: &[f64], tau: &mut [f64]) {
        self.place(data, q, false);
        let lift = -self.gravity;
        let mut mass = 0.0;
        let mut moment = Vector3::<f64>::zeros();
        for i in (0..self.segments.len()).rev() {
            mass += data.body[i].mass;
            moment += data.body[i].first_moment;
            let z = &data.axis[i];
            data.segment_tau[i] = match self.segments[i].kind {
                MotionKind::Revolute => z.dot(&(moment - data.origin[i] * mass).cross(&lift)),
                MotionKind::Prismatic => z.dot(&lift) * mass,
            };
        }
        self.gather(data, tau);
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
        self.place(data, q, true);
        let n = self.segments.len();
        let (mut w, mut v) = (Vector3::<f64>::zeros(), Vector3::<f64>::zeros());
        let (mut dw, mut dv) = (Vector3::<f64>::zeros(), -self.gravity);
        for i in 0..n {
            let rate = self.drive(i, qd, false);
            let accel = self.drive(i, qdd, false);
            data.rate[i] = rate;
            data.accel[i] = accel;
            let (sw, sv) = (data.motion_w[i], data.motion_v[i]);
            let (jw, jv) = (sw * rate, sv * rate);
            w += jw;
            v += jv;
            // A += S q̈ + V × (S q̇).
            dw += sw * accel + w.cross(&jw);
            dv += sv * accel + w.cross(&jv) + v.cross(&jw);
            let body = &data.body[i];
            let (n_a, f_a) = apply(body, &dw, &dv);
            let (n_v, f_v) = apply(body, &w, &v);
            // F = Y A + V ×* (Y V).
            data.force_n[i] = n_a + w.cross(&n_v) + v.cross(&f_v);
            data.force_f[i] = f_a + w.cross(&f_v);
        }
        let (mut sum_n, mut sum_f) = (Vector3::<f64>::zeros(), Vector3::<f64>::zeros());
        for i in (0..n).rev() {
            sum_n += data.force_n[i];
            sum_f += data.force_f[i];
            data.segment_tau[i] = data.motion_w[i].dot(&sum_n) + data.motion_v[i].dot(&sum_f);
        }
        self.gather(data, tau);
    }

    /// `M(q)` without checks; `out` is the column-major dof × dof storage.
    pub(super) fn crba_unchecked(&self, data: &mut DynamicsData, q: &[f64], out: &mut [f64]) {
        self.place(data, q, true);
        let n = self.segments.len();
        let mut composite = WorldBody::ZERO;
        let stride = if self.has_mimic { n } else { self.dof };
        for i in (0..n).rev() {
            let body = data.body[i];
            composite.mass += body.mass;
            composite.first_moment += body.first_moment;
            composite.rotational += body.rotational;
            let (fn_, ff) = apply(&composite, &data.motion_w[i], &data.motion_v[i]);
            for k in 0..=i {
                let entry = data.motion_w[k].dot(&fn_) + data.motion_v[k].dot(&ff);
                if self.has_mimic {
                    data.segment_mass[k * stride + i] = entry;
                    data.segment_mass[i * stride + k] = entry;
                } else {
                    out[k * stride + i] = entry;
                    out[i * stride + k] = entry;
                }
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
