//! Rigid-body dynamics of a serial chain, beside the forward kinematics: the gravity torques
//! `g(q)`, inverse dynamics `τ(q, q̇, q̈)` by the recursive Newton–Euler algorithm and the
//! joint-space inertia matrix `M(q)` by the composite rigid body algorithm.
//!
//! **Model and data**, as in Pinocchio: [`Dynamics`] is the model (built once from a
//! [`Chain`] with [`Chain::dynamics`], shared between threads), [`DynamicsData`] the workspace
//! of one thread ([`Dynamics::data`], allocated once). The kernels write into caller buffers
//! and allocate nothing.
//!
//! **Frames and units.** Everything is expressed in the **chain base frame**: the gravity
//! vector (default 9.81 m/s² along the base's −z; a task whose world `z` is not the base's
//! must rotate its gravity into the base frame, `g_base = base_from_world.rotation · g_world`),
//! the joint axes, the bodies. `q` in rad (revolute) or m (prismatic), `q̇` in rad/s or m/s,
//! `q̈` in rad/s² or m/s²; torques in N·m, forces in N; `M` in kg·m² (revolute rows) or kg
//! (prismatic rows). The conventions are Pinocchio's: `g(q) = rnea(q, 0, 0)` is the torque
//! that holds the chain still against gravity, `τ = M(q) q̈ + C(q, q̇) q̇ + g(q)`.
//!
//! **Joints** are those of the FK kernel: revolute and continuous joints turn about their
//! axis, prismatic ones slide along it, fixed joints are folded (their child's body joins the
//! moving segment before them), and a mimic joint moves with its leader,
//! `q_f = m · q_leader + offset`: its segment's torque reaches the leader's entry of `τ`
//! multiplied by `m` (virtual work), and `M` is `Jᵀ M_segments J` with the same mapping.
//!
//! **Payload.** [`DynamicsData::set_payload`] attaches one rigid body to the tool frame (the
//! frame of [`Chain::pose`], after `tip_from_tool`); its mass, centre of mass and inertia are
//! in that frame. The torques are linear in the payload's mass, first moment and inertia,
//! hence affine in its mass for a given shape and grasp.
//!
//! The algorithms work in the base frame (Featherstone's RNEA and CRBA in absolute
//! coordinates): spatial velocities, accelerations and forces are referred to the base
//! origin, so the composite inertias and the backward force sums are plain sums. The
//! kernels themselves are in [`kernels`]; the checks against Pinocchio, closed forms and
//! finite differences in `tests/dynamics.rs` and `tests.rs`.

mod kernels;
#[cfg(test)]
mod tests;

use super::chain::{Chain, MotionKind, SegmentFrames};
use super::error::RobotError;
use super::spec::{MotionLimits, RigidBody};
use nalgebra::{DMatrix, IsometryMatrix3, Matrix3, Matrix6xX, Vector3};

/// Standard gravity (m/s²).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// One moving segment: its placement at `q = 0` in the previous aligned frame (the base for
/// the first), its motion and drive, and its body in its own aligned frame (after the motion).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Segment {
    rotation: Matrix3<f64>,
    translation: Vector3<f64>,
    kind: MotionKind,
    source: usize,
    multiplier: f64,
    offset: f64,
    /// The body moved by the segment, in its aligned frame.
    body: SegmentBody,
}

/// A segment's body in the segment's aligned frame: mass (kg), centre of mass (m), inertia
/// about it (kg·m²), and that inertia's principal spread.
#[derive(Debug, Clone, Copy, PartialEq)]
struct SegmentBody {
    mass: f64,
    com: Vector3<f64>,
    inertia: Matrix3<f64>,
    spread: PrincipalSpread,
}

impl SegmentBody {
    /// The body with its inertia's principal spread; `what` names it in the error when the
    /// spread cannot be computed ([`PrincipalSpread::of`]).
    fn new(body: &RigidBody, what: &str) -> Result<Self, RobotError> {
        let Some(spread) = PrincipalSpread::of(&body.inertia) else {
            return Err(RobotError::BadInertia {
                what: what.to_string(),
                message: format!(
                    "the principal axes of the inertia {:?} could not be computed",
                    body.inertia.as_slice()
                ),
            });
        };
        Ok(Self {
            mass: body.mass,
            com: body.com,
            inertia: body.inertia,
            spread,
        })
    }

    /// The body without its spread.
    fn rigid(&self) -> RigidBody {
        RigidBody::new(self.mass, self.com, self.inertia)
    }
}

/// Four segments' bodies lane by lane, for the CRBA's placement of four bodies at once:
/// lane `l` of group `g` is segment `4g + l` (aligned frame: mass kg, centre of mass m, the
/// inertia's [`PrincipalSpread`]); lanes past the last segment hold empty bodies.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct BodyLanes {
    mass: [f64; 4],
    peak: [f64; 4],
    com: [[f64; 4]; 3],
    axes: [[[f64; 4]; 3]; 2],
}

impl BodyLanes {
    /// Puts `body` in lane `lane`.
    fn set(&mut self, lane: usize, body: &SegmentBody) {
        self.mass[lane] = body.mass;
        self.peak[lane] = body.spread.peak;
        for row in 0..3 {
            self.com[row][lane] = body.com[row];
            for (axes, axis) in self.axes.iter_mut().zip(&body.spread.axes) {
                axes[row][lane] = axis[row];
            }
        }
    }
}

/// Four placed bodies lane by lane (as [`BodyLanes`]), about the base origin along base
/// axes: first moment `h = m c` (kg·m) and the two parts of the rotational inertia about the
/// origin `I_O = κ 1 − P` (kg·m²): `κ` and the upper triangle of `P` (`xx, xy, xz, yy, yz,
/// zz`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct PlacedLanes {
    first_moment: [[f64; 4]; 3],
    scalar: [f64; 4],
    outer: [[f64; 4]; 6],
}

/// A symmetric inertia `I` (kg·m²) written `λ 1 − a aᵀ − b bᵀ`: `λ` its largest principal
/// moment, `a` and `b` its other two principal axes scaled by `√(λ − λᵢ)`. Turned by a
/// rotation `R` it is `λ 1 − (R a)(R a)ᵀ − (R b)(R b)ᵀ`: two matrix–vector products where
/// `R I Rᵀ` takes two matrix products (what the CRBA pays per body and call).
#[derive(Debug, Clone, Copy, PartialEq)]
struct PrincipalSpread {
    peak: f64,
    axes: [Vector3<f64>; 2],
}

impl PrincipalSpread {
    /// The spread of a finite symmetric inertia (its eigen-decomposition, once per body), or
    /// `None` when the decomposition does not converge within a bounded number of iterations
    /// (the file's numbers are untrusted: an unbounded iteration could hang on them).
    fn of(inertia: &Matrix3<f64>) -> Option<Self> {
        const MAX_ITERATIONS: usize = 1_000;
        let eigen = inertia.try_symmetric_eigen(f64::EPSILON, MAX_ITERATIONS)?;
        let mut order = [0, 1, 2];
        order.sort_by(|&i, &j| eigen.eigenvalues[j].total_cmp(&eigen.eigenvalues[i]));
        let peak = eigen.eigenvalues[order[0]];
        let axis = |k: usize| {
            eigen.eigenvectors.column(order[k]) * (peak - eigen.eigenvalues[order[k]]).sqrt()
        };
        Some(Self {
            peak,
            axes: [axis(1), axis(2)],
        })
    }
}

/// The dynamics model of one chain: per moving segment its placement, joint axis and mass
/// properties, the tool frame, the gravity vector and the joints' motion limits. Built by
/// [`Chain::dynamics`]; evaluated with a [`DynamicsData`] workspace.
#[derive(Debug, Clone)]
pub struct Dynamics {
    /// Which model this is (unique per [`Chain::dynamics`] call, kept by clones), so a
    /// workspace made for another model is refused in one comparison.
    id: u64,
    chain: String,
    dof: usize,
    segments: Vec<Segment>,
    /// The FK kernel's link-frame pass over the segments.
    frames: SegmentFrames,
    has_mimic: bool,
    tail_rotation: Matrix3<f64>,
    tail_translation: Vector3<f64>,
    gravity: Vector3<f64>,
    motion_limits: Vec<MotionLimits>,
}

impl PartialEq for Dynamics {
    /// Equal models: the same chain, segments, tool frame, gravity and limits (whichever
    /// `Chain::dynamics` call built them).
    fn eq(&self, other: &Self) -> bool {
        self.chain == other.chain
            && self.dof == other.dof
            && self.segments == other.segments
            && self.frames == other.frames
            && self.has_mimic == other.has_mimic
            && self.tail_rotation == other.tail_rotation
            && self.tail_translation == other.tail_translation
            && self.gravity == other.gravity
            && self.motion_limits == other.motion_limits
    }
}

/// The source of [`Dynamics`] ids.
static NEXT_MODEL_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// The workspace of the dynamics kernels for one model (one per thread): per-segment
/// buffers sized once by [`Dynamics::data`], and the optional payload at the tool.
#[derive(Debug, Clone)]
pub struct DynamicsData {
    /// The id of the model it was made for.
    model: u64,
    payload: Option<RigidBody>,
    /// The last segment's body with the payload joined to it (its aligned frame), when a
    /// payload is attached: the kernels use it in place of the segment's own body.
    loaded_last: Option<SegmentBody>,
    /// The last segment's own body and the tool frame in its aligned frame (rotation,
    /// origin), from the model, to join a payload to it.
    last_segment: Option<SegmentBody>,
    tail_rotation: Matrix3<f64>,
    tail_translation: Vector3<f64>,
    /// Each segment's aligned frame (base frame), from the FK kernel's link-frame pass.
    frames: Vec<IsometryMatrix3<f64>>,
    /// Each segment's motion subspace `S = (ω, v)` (about the base origin).
    motion_w: Vec<Vector3<f64>>,
    motion_v: Vec<Vector3<f64>>,
    /// The segments' bodies four by four (the last one with the payload joined), and their
    /// placement in the CRBA.
    body_lanes: Vec<BodyLanes>,
    placed_lanes: Vec<PlacedLanes>,
    /// Each segment's spatial force `(n, f)` in the RNEA (about the base origin).
    force_n: Vec<Vector3<f64>>,
    force_f: Vec<Vector3<f64>>,
    /// Segment torques, and the segment-level mass matrix for chains with mimic joints.
    segment_tau: Vec<f64>,
    segment_mass: Vec<f64>,
}

impl DynamicsData {
    /// Attaches `payload` (mass properties in the **tool frame**: kg, m, kg·m² about its centre
    /// of mass) rigidly to the tool frame, or removes it with `None`. Every later evaluation
    /// with this workspace includes it.
    pub fn set_payload(&mut self, payload: Option<RigidBody>) -> Result<(), RobotError> {
        if let Some(body) = &payload {
            check_body(body, "payload")?;
        }
        let loaded_last = match (payload, &self.last_segment) {
            (Some(p), Some(last)) => {
                let r = self.tail_rotation;
                let in_last = RigidBody::new(
                    p.mass,
                    r * p.com + self.tail_translation,
                    r * p.inertia * r.transpose(),
                );
                Some(SegmentBody::new(
                    &last.rigid().combined(&in_last),
                    "payload",
                )?)
            }
            _ => None,
        };
        self.payload = payload;
        self.loaded_last = loaded_last;
        if let Some(last) = &self.last_segment {
            let i = self.frames.len() - 1;
            let body = self.loaded_last.as_ref().unwrap_or(last);
            self.body_lanes[i / 4].set(i % 4, body);
        }
        Ok(())
    }

    /// The payload attached to the tool frame, if any.
    pub fn payload(&self) -> Option<&RigidBody> {
        self.payload.as_ref()
    }
}

/// Checks a body's numbers ([`RigidBody::is_valid`]); `what` names it in the error.
fn check_body(body: &RigidBody, what: &str) -> Result<(), RobotError> {
    if body.is_valid() {
        return Ok(());
    }
    Err(RobotError::BadInertia {
        what: what.to_string(),
        message: format!(
            "mass {}, centre of mass {:?}, inertia {:?}: the mass must be finite and non-negative, the inertia finite and symmetric with a non-negative diagonal",
            body.mass,
            body.com.as_slice(),
            body.inertia.as_slice()
        ),
    })
}

impl Chain {
    /// The chain's dynamics model, with gravity 9.81 m/s² along the base's −z.
    ///
    /// Fails with [`RobotError::NoInertia`] when a moving segment carries no inertial data
    /// (none of the links it moves has any), never by assuming a zero mass; with
    /// [`RobotError::BadInertia`] when a segment's data is not a valid body. A segment whose
    /// links give an explicit zero mass is massless, as the file says.
    ///
    /// ```
    /// use graspath::robot::builtin::{baxter, Arm};
    /// use graspath::robot::RigidBody;
    /// use nalgebra::Vector3;
    /// let chain = baxter(Arm::Left);
    /// let dynamics = chain.dynamics()?;
    /// let mut data = dynamics.data();
    /// let (mut empty, mut loaded) = ([0.0; 7], [0.0; 7]);
    /// // The arm stretched out forward: the shoulder (s1) holds it against gravity.
    /// let q = [0.0; 7];
    /// dynamics.gravity_torques_into(&mut data, &q, &mut empty)?;
    /// // 2 kg held 5 cm beyond the gripper's tool frame: the shoulder needs more.
    /// data.set_payload(Some(RigidBody::point(2.0, Vector3::new(0.0, 0.0, 0.05))))?;
    /// dynamics.gravity_torques_into(&mut data, &q, &mut loaded)?;
    /// assert!(loaded[1].abs() > empty[1].abs() + 10.0);
    /// # Ok::<(), graspath::robot::RobotError>(())
    /// ```
    pub fn dynamics(&self) -> Result<Dynamics, RobotError> {
        let layout = self.layout();
        let mut segments = Vec::with_capacity(layout.segments.len());
        for (i, s) in layout.segments.iter().enumerate() {
            let joint = segment_joint_name(self, &layout, i);
            let Some(body) = s.body else {
                return Err(RobotError::NoInertia {
                    source_name: self.source_name().to_string(),
                    chain: self.name(),
                    joint,
                    links: s.links.join(", "),
                });
            };
            check_body(
                &body,
                &format!("chain '{}', segment of joint '{joint}'", self.name()),
            )?;
            segments.push(Segment {
                rotation: s.rotation,
                translation: s.translation,
                kind: s.kind,
                source: s.drive.0,
                multiplier: s.drive.1,
                offset: s.drive.2,
                body: SegmentBody::new(
                    &body,
                    &format!("chain '{}', segment of joint '{joint}'", self.name()),
                )?,
            });
        }
        Ok(Dynamics {
            id: NEXT_MODEL_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            chain: self.name(),
            dof: self.dof(),
            segments,
            frames: self.segment_frames(),
            has_mimic: layout.has_mimic,
            tail_rotation: layout.tail_rotation,
            tail_translation: layout.tail_translation,
            gravity: Vector3::new(0.0, 0.0, -STANDARD_GRAVITY),
            motion_limits: self.motion_limits().to_vec(),
        })
    }
}

/// The joint that moves segment `i`, for messages: its name when the chain has no mimic
/// joints (segment `i` is then joint `i`), else the link it moves (a mimic follower has no
/// entry in `q`).
fn segment_joint_name(chain: &Chain, layout: &super::chain::ChainLayout, i: usize) -> String {
    if !layout.has_mimic {
        if let Some(name) = chain.joint_names().get(i) {
            return name.clone();
        }
    }
    layout.segments[i]
        .links
        .first()
        .map_or_else(|| format!("#{i}"), |link| format!("(moving link '{link}')"))
}

impl Dynamics {
    /// A new workspace for this model (the only allocation; reuse it across calls).
    pub fn data(&self) -> DynamicsData {
        let n = self.segments.len();
        DynamicsData {
            model: self.id,
            payload: None,
            loaded_last: None,
            last_segment: self.segments.last().map(|s| s.body),
            tail_rotation: self.tail_rotation,
            tail_translation: self.tail_translation,
            frames: vec![IsometryMatrix3::identity(); n],
            motion_w: vec![Vector3::zeros(); n],
            motion_v: vec![Vector3::zeros(); n],
            body_lanes: self
                .segments
                .chunks(4)
                .map(|group| {
                    let mut lanes = BodyLanes::default();
                    for (lane, s) in group.iter().enumerate() {
                        lanes.set(lane, &s.body);
                    }
                    lanes
                })
                .collect(),
            placed_lanes: vec![PlacedLanes::default(); n.div_ceil(4)],
            force_n: vec![Vector3::zeros(); n],
            force_f: vec![Vector3::zeros(); n],
            segment_tau: vec![0.0; n],
            segment_mass: if self.has_mimic {
                vec![0.0; n * n]
            } else {
                Vec::new()
            },
        }
    }

    /// The number of independent joints (the length of `q`, `q̇`, `q̈` and `τ`).
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// The gravity vector, base frame (m/s²).
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    /// Sets the gravity vector in the base frame (m/s²); it must be finite.
    pub fn set_gravity(&mut self, gravity: Vector3<f64>) -> Result<(), RobotError> {
        if gravity.iter().any(|v| !v.is_finite()) {
            return Err(RobotError::BadOption {
                name: "gravity",
                message: format!("{:?} is not finite", gravity.as_slice()),
            });
        }
        self.gravity = gravity;
        Ok(())
    }

    /// The model with gravity `gravity` (base frame, m/s²; see [`Dynamics::set_gravity`]).
    pub fn with_gravity(mut self, gravity: Vector3<f64>) -> Result<Self, RobotError> {
        self.set_gravity(gravity)?;
        Ok(self)
    }

    /// Velocity, effort and acceleration limits of the independent joints, in the order of `q`.
    pub fn motion_limits(&self) -> &[MotionLimits] {
        &self.motion_limits
    }

    /// The total mass carried by the moving segments (kg), without the payload.
    pub fn moving_mass(&self) -> f64 {
        self.segments.iter().map(|s| s.body.mass).sum()
    }

    fn check_q(&self, q: &[f64]) -> Result<(), RobotError> {
        if q.len() != self.dof {
            return Err(RobotError::WrongDof {
                chain: self.chain.clone(),
                expected: self.dof,
                got: q.len(),
            });
        }
        if let Some(index) = q.iter().position(|v| !v.is_finite()) {
            return Err(RobotError::NonFiniteJoint { index });
        }
        Ok(())
    }

    fn check_vector(&self, what: &'static str, v: &[f64]) -> Result<(), RobotError> {
        if v.len() != self.dof {
            return Err(RobotError::BadDynamicsInput {
                what,
                message: format!(
                    "has {} values but the chain '{}' has {} joints",
                    v.len(),
                    self.chain,
                    self.dof
                ),
            });
        }
        if let Some(index) = v.iter().position(|x| !x.is_finite()) {
            return Err(RobotError::BadDynamicsInput {
                what,
                message: format!("entry {index} is not a finite number"),
            });
        }
        Ok(())
    }

    fn check_out(&self, len: usize) -> Result<(), RobotError> {
        if len != self.dof {
            return Err(RobotError::BadDynamicsInput {
                what: "tau",
                message: format!(
                    "the output has {len} entries but the chain '{}' has {} joints",
                    self.chain, self.dof
                ),
            });
        }
        Ok(())
    }

    fn check_data(&self, data: &DynamicsData) -> Result<(), RobotError> {
        if data.model != self.id {
            return Err(RobotError::BadDynamicsInput {
                what: "data",
                message: format!(
                    "the workspace was made for another model than chain '{}' (use Dynamics::data)",
                    self.chain
                ),
            });
        }
        Ok(())
    }

    /// The gravity torques `g(q)` (N·m or N) into `tau`: the joint torques that hold the
    /// chain (and the payload of `data`) still at `q` against [`Dynamics::gravity`].
    /// Equals `rnea(q, 0, 0)`. Nothing is allocated.
    pub fn gravity_torques_into(
        &self,
        data: &mut DynamicsData,
        q: &[f64],
        tau: &mut [f64],
    ) -> Result<(), RobotError> {
        self.check_data(data)?;
        self.check_q(q)?;
        self.check_out(tau.len())?;
        self.gravity_unchecked(data, q, tau);
        Ok(())
    }

    /// The gravity torques `g(q)` into `tau` (as [`Dynamics::gravity_torques_into`], with the
    /// payload of `data` if any) and, into `per_kg`, the joint torques that hold **one
    /// kilogram** at `point` (tool frame, m) still against gravity, from one placement of the
    /// segment frames. Gravity torques are linear in a carried mass at a fixed centre of mass:
    /// holding `m` kg there needs `tau + m · per_kg`, so one call gives the torques for every
    /// mass (what a torque check and a payload capacity need). Nothing is allocated.
    pub fn gravity_torques_and_point_load_into(
        &self,
        data: &mut DynamicsData,
        q: &[f64],
        point: &Vector3<f64>,
        tau: &mut [f64],
        per_kg: &mut [f64],
    ) -> Result<(), RobotError> {
        self.check_data(data)?;
        self.check_q(q)?;
        self.check_out(tau.len())?;
        self.check_out(per_kg.len())?;
        if point.iter().any(|v| !v.is_finite()) {
            return Err(RobotError::BadDynamicsInput {
                what: "point",
                message: format!("{:?} is not finite", point.as_slice()),
            });
        }
        self.gravity_and_point_load_unchecked(data, q, point, tau, per_kg);
        Ok(())
    }

    /// The gravity torques `g(q)` into `tau` (as [`Dynamics::gravity_torques_into`]) and the
    /// tool frame's geometric Jacobian into `jacobian` (6 × dof, rows `[v; ω]`, base frame:
    /// the Jacobian of [`Chain::pose_and_jacobian_into`]), from one placement of the segment
    /// frames: what a torque check and a manipulability index need at a sample, at little more
    /// than the cost of either. `jacobian` is resized once if its shape is wrong; with the
    /// right shape nothing is allocated.
    pub fn gravity_torques_and_jacobian_into(
        &self,
        data: &mut DynamicsData,
        q: &[f64],
        tau: &mut [f64],
        jacobian: &mut Matrix6xX<f64>,
    ) -> Result<(), RobotError> {
        self.check_data(data)?;
        self.check_q(q)?;
        self.check_out(tau.len())?;
        if jacobian.ncols() != self.dof {
            *jacobian = Matrix6xX::zeros(self.dof);
        }
        self.gravity_and_jacobian_unchecked(data, q, tau, jacobian.as_mut_slice());
        Ok(())
    }

    /// The torques along a path `q(s)` at `q`, with the path's derivatives `dq = q'(s)` and
    /// `ddq = q''(s)`: `g(q)` into `g`, `M(q) q'` into `a` and `M(q) q'' + C(q, q') q'` into
    /// `b`, so that a motion along the path with path speed `ṡ` and acceleration `s̈` needs
    /// `τ = a s̈ + b ṡ² + g` (what time-optimal timing constrains). One placement of the
    /// segment frames for the three; payload included. Nothing is allocated.
    #[allow(clippy::too_many_arguments)]
    pub fn path_torques_into(
        &self,
        data: &mut DynamicsData,
        q: &[f64],
        dq: &[f64],
        ddq: &[f64],
        g: &mut [f64],
        a: &mut [f64],
        b: &mut [f64],
    ) -> Result<(), RobotError> {
        self.check_data(data)?;
        self.check_q(q)?;
        self.check_vector("dq", dq)?;
        self.check_vector("ddq", ddq)?;
        for out in [&*g, &*a, &*b] {
            self.check_out(out.len())?;
        }
        self.path_torques_unchecked(data, [q, dq, ddq], [g, a, b]);
        Ok(())
    }

    /// Inverse dynamics by the recursive Newton–Euler algorithm: the joint torques
    /// `τ = M(q) q̈ + C(q, q̇) q̇ + g(q)` (N·m or N) into `tau`, payload included.
    /// Nothing is allocated.
    pub fn inverse_dynamics_into(
        &self,
        data: &mut DynamicsData,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        tau: &mut [f64],
    ) -> Result<(), RobotError> {
        self.check_data(data)?;
        self.check_q(q)?;
        self.check_vector("qd", qd)?;
        self.check_vector("qdd", qdd)?;
        self.check_out(tau.len())?;
        self.rnea_unchecked(data, q, qd, qdd, tau);
        Ok(())
    }

    /// The joint-space inertia matrix `M(q)` (dof × dof, symmetric; kg·m² / kg) by the
    /// composite rigid body algorithm, payload included. `out` is resized once if its shape
    /// is wrong; with the right shape nothing is allocated.
    pub fn mass_matrix_into(
        &self,
        data: &mut DynamicsData,
        q: &[f64],
        out: &mut DMatrix<f64>,
    ) -> Result<(), RobotError> {
        self.check_data(data)?;
        self.check_q(q)?;
        if out.shape() != (self.dof, self.dof) {
            *out = DMatrix::zeros(self.dof, self.dof);
        }
        self.crba_unchecked(data, q, out.as_mut_slice());
        Ok(())
    }

    /// `g(q)`, newly allocated, without payload (see [`Dynamics::gravity_torques_into`]).
    pub fn gravity_torques(&self, q: &[f64]) -> Result<Vec<f64>, RobotError> {
        let mut tau = vec![0.0; self.dof];
        self.gravity_torques_into(&mut self.data(), q, &mut tau)?;
        Ok(tau)
    }

    /// `τ(q, q̇, q̈)`, newly allocated, without payload (see [`Dynamics::inverse_dynamics_into`]).
    pub fn inverse_dynamics(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> Result<Vec<f64>, RobotError> {
        let mut tau = vec![0.0; self.dof];
        self.inverse_dynamics_into(&mut self.data(), q, qd, qdd, &mut tau)?;
        Ok(tau)
    }

    /// `M(q)`, newly allocated, without payload (see [`Dynamics::mass_matrix_into`]).
    pub fn mass_matrix(&self, q: &[f64]) -> Result<DMatrix<f64>, RobotError> {
        let mut m = DMatrix::zeros(self.dof, self.dof);
        self.mass_matrix_into(&mut self.data(), q, &mut m)?;
        Ok(m)
    }
}
