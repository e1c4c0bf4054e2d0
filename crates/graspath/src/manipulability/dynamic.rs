//! The dynamic task-relevant manipulability: how fast the arm can *accelerate* the wrist along
//! the direction of motion with the torque its joints have left after holding the arm and the
//! carried object against gravity — Yoshikawa's dynamic manipulability ellipsoid projected on
//! the tangent `u`, as the paper projects the kinematic one (eq. 13).
//!
//! **Definition.** From rest, `M(q) q̈ = τ − g(q)` and the wrist's acceleration is `J q̈`. With
//! each joint's torque inside its headroom, `τ = g(q) + H τ̂` with `‖τ̂‖ ≤ 1` and
//! `H = diag(hⱼ)`, `hⱼ = max(τ_max,j − |gⱼ(q)|, 0)` (the effort limit less what gravity already
//! takes, payload included), the reachable accelerations form the ellipsoid
//! `{J M⁻¹ H τ̂ : ‖τ̂‖ ≤ 1}`, whose matrix is `A Aᵀ` with `A = J' M⁻¹ H` (`J'` the rows the task
//! measures, as for `M_T`). Projected on the unit tangent `u`:
//!
//! `M_D = uᵀ A Aᵀ u = ‖H M⁻¹ J'ᵀ u‖²`,
//!
//! the square of the largest acceleration along `u` (m/s², or rad/s² for the rotation rows)
//! the torques can produce, exactly as `√M_T = ‖J'ᵀ u‖` is the largest speed along `u` a unit
//! joint velocity produces. Velocity-dependent terms (Coriolis, `J̇ q̇`) are left out, as in
//! Yoshikawa's measure; they are the timing's business (`crate::timing`).
//!
//! Frames: `J` in the chain's base frame (rows `[v; ω]`, `v` the tool origin's velocity), `M`,
//! `g` and `τ` in joint space (N·m or N), the payload in the tool frame.

use super::settings::JacobianRows;
use crate::robot::{Dynamics, DynamicsData, RigidBody, RobotError};
use nalgebra::{DMatrix, DVector, Dim, Matrix, Storage, U6};

use super::indices::Direction;

/// The workspace that evaluates `M_D` for one arm, one payload, one thread: the dynamics
/// model's data, the effort limits and the buffers (allocated once).
#[derive(Debug, Clone)]
pub struct DynamicManipulability<'a> {
    dynamics: &'a Dynamics,
    data: DynamicsData,
    /// `τ_max,j` (N·m or N) per independent joint.
    effort: Vec<f64>,
    /// `g(q)` of the last evaluation.
    gravity: Vec<f64>,
    /// `M(q)` of the last evaluation, then its Cholesky factor.
    mass: DMatrix<f64>,
    /// `J'ᵀ u`, then `M⁻¹ J'ᵀ u`.
    solution: DVector<f64>,
}

impl<'a> DynamicManipulability<'a> {
    /// A workspace for `dynamics` with `payload` (mass properties in the **tool frame**) held
    /// at the tool. Fails when a joint has no effort limit (the measure weighs each joint by
    /// its torque), or the payload is not a valid body.
    pub fn new(dynamics: &'a Dynamics, payload: Option<RigidBody>) -> Result<Self, RobotError> {
        let effort = dynamics
            .motion_limits()
            .iter()
            .enumerate()
            .map(|(j, limits)| {
                limits
                    .effort
                    .filter(|e| e.is_finite() && *e > 0.0)
                    .ok_or_else(|| RobotError::BadDynamicsInput {
                        what: "effort limits",
                        message: format!(
                            "joint {j} has no effort limit; the dynamic manipulability weighs \
                             every joint by its torque"
                        ),
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut data = dynamics.data();
        data.set_payload(payload)?;
        let dof = dynamics.dof();
        Ok(Self {
            dynamics,
            data,
            effort,
            gravity: vec![0.0; dof],
            mass: DMatrix::zeros(dof, dof),
            solution: DVector::zeros(dof),
        })
    }

    /// Replaces the payload held at the tool (tool frame; `None` for none).
    pub fn set_payload(&mut self, payload: Option<RigidBody>) -> Result<(), RobotError> {
        self.data.set_payload(payload)
    }

    /// `M_D = ‖H M⁻¹ J'ᵀ u‖²` at configuration `q` with Jacobian `jacobian` (base frame,
    /// rows `[v; ω]`, at `q`) along the unit `direction` measured in `rows` (see the module
    /// doc). 0 when no joint has headroom; NaN when `q` is not a configuration of the chain or
    /// `M(q)` is not positive definite (a massless chain).
    pub fn task_relevant<C: Dim, S: Storage<f64, U6, C>>(
        &mut self,
        rows: JacobianRows,
        jacobian: &Matrix<f64, U6, C, S>,
        direction: &Direction,
        q: &[f64],
    ) -> f64 {
        let evaluated = self
            .dynamics
            .gravity_torques_into(&mut self.data, q, &mut self.gravity)
            .and_then(|()| {
                self.dynamics
                    .mass_matrix_into(&mut self.data, q, &mut self.mass)
            });
        if evaluated.is_err() || jacobian.ncols() != self.effort.len() {
            return f64::NAN;
        }
        rows.projection_into(jacobian, direction, self.solution.as_mut_slice());
        // The Cholesky factor takes `M`'s storage and gives it back: nothing is allocated.
        let mass = std::mem::replace(&mut self.mass, DMatrix::zeros(0, 0));
        let Some(factor) = mass.cholesky() else {
            self.mass = DMatrix::zeros(self.effort.len(), self.effort.len());
            return f64::NAN;
        };
        factor.solve_mut(&mut self.solution);
        self.mass = factor.unpack();
        self.solution
            .iter()
            .zip(&self.effort)
            .zip(&self.gravity)
            .map(|((x, effort), g)| {
                let headroom = (effort - g.abs()).max(0.0);
                (headroom * x).powi(2)
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::builtin::{BuiltinRobot, ARM_CHAIN};
    use crate::robot::Chain;
    use nalgebra::{Matrix6xX, Vector3, Vector6};
    use rand::rngs::Xoshiro256PlusPlus;
    use rand::{RngExt, SeedableRng};

    fn builtin(robot: BuiltinRobot) -> Chain {
        Chain::from_spec(&robot.chain_spec(ARM_CHAIN).unwrap()).unwrap()
    }

    /// Oracle: the largest acceleration along `u` over torques inside the headroom, by brute
    /// force over random unit `τ̂` and at the analytic maximiser, with `M` inverted by an LU
    /// decomposition and the wrist acceleration `J q̈` from `q̈ = M⁻¹ (τ − g)`.
    #[test]
    fn the_index_is_the_largest_acceleration_along_the_tangent_within_the_headroom() {
        for (robot, seed) in [(BuiltinRobot::Panda, 1_u64), (BuiltinRobot::Ur5, 2)] {
            let chain = builtin(robot);
            let dynamics = chain.dynamics().unwrap();
            let payload = RigidBody::point(1.5, Vector3::new(0.02, -0.01, 0.08));
            let mut index = DynamicManipulability::new(&dynamics, Some(payload)).unwrap();
            let mut data = dynamics.data();
            data.set_payload(Some(payload)).unwrap();
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            for _ in 0..20 {
                let q: Vec<f64> = (0..chain.dof())
                    .map(|j| rng.random_range(chain.lower()[j]..chain.upper()[j]))
                    .collect();
                let mut jacobian = Matrix6xX::zeros(chain.dof());
                chain.pose_and_jacobian_into(&q, &mut jacobian).unwrap();
                let u = Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0)).normalize();
                let rows = JacobianRows::Twist { length_scale: 1.0 };
                let m_d = index.task_relevant(rows, &jacobian, &Direction::Full(u), &q);

                let mut g = vec![0.0; chain.dof()];
                dynamics
                    .gravity_torques_into(&mut data, &q, &mut g)
                    .unwrap();
                let mut mass = DMatrix::zeros(chain.dof(), chain.dof());
                dynamics.mass_matrix_into(&mut data, &q, &mut mass).unwrap();
                let inverse = mass.clone().lu().try_inverse().unwrap();
                let limits = dynamics.motion_limits();
                let headroom = DMatrix::from_diagonal(&DVector::from_iterator(
                    chain.dof(),
                    (0..chain.dof()).map(|j| (limits[j].effort.unwrap() - g[j].abs()).max(0.0)),
                ));
                // The wrist acceleration along u per unit τ̂: a row vector.
                let gain = u.transpose() * &jacobian * &inverse * &headroom;
                let best = gain.norm();
                assert!(
                    ((best * best - m_d) / m_d).abs() < 1e-9,
                    "closed form {} vs index {m_d}",
                    best * best
                );
                // No random unit τ̂ does better, and the maximiser reaches it.
                for k in 0..200 {
                    let mut tau_hat =
                        DVector::from_fn(chain.dof(), |_, _| rng.random_range(-1.0..1.0));
                    tau_hat /= tau_hat.norm();
                    assert!((&gain * &tau_hat)[0] <= best * (1.0 + 1e-12), "trial {k}");
                }
                let maximiser = gain.transpose() / best;
                let tau = DVector::from_column_slice(&g) + &headroom * &maximiser;
                let qdd = &inverse * (tau - DVector::from_column_slice(&g));
                let along = (u.transpose() * &jacobian * qdd)[0];
                assert!((along - best).abs() < 1e-9 * best.max(1.0));
            }
        }
    }

    /// Closed form: one horizontal link turning about a vertical axis, a point mass `m` at
    /// `l`: gravity takes no torque, `M = m l²`, the tip's tangential acceleration is
    /// `τ_max / (m l)`.
    #[test]
    fn a_point_mass_on_a_vertical_axis_accelerates_at_the_torque_over_its_lever() {
        let urdf = r#"<robot name="r">
            <link name="base"/>
            <link name="arm"><inertial><mass value="2.0"/><origin xyz="0.5 0 0"/>
              <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
            <link name="tip"/>
            <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
              <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
            <joint name="t" type="fixed"><parent link="arm"/><child link="tip"/>
              <origin xyz="0.5 0 0"/></joint>
            </robot>"#;
        let chain = crate::robot::parse_urdf_chain(urdf, "test", "base", "tip").unwrap();
        let dynamics = chain.dynamics().unwrap();
        let mut index = DynamicManipulability::new(&dynamics, None).unwrap();
        let q = [0.3];
        let mut jacobian = Matrix6xX::zeros(1);
        chain.pose_and_jacobian_into(&q, &mut jacobian).unwrap();
        // The tip moves along (−sin q, cos q, 0).
        let u = Vector3::new(-q[0].sin(), q[0].cos(), 0.0);
        let m_d = index.task_relevant(
            JacobianRows::Translation,
            &jacobian,
            &Direction::Translation(u),
            &q,
        );
        let expected: f64 = 10.0 / (2.0 * 0.5);
        assert!(
            (m_d.sqrt() - expected).abs() < 1e-12,
            "{} vs {expected}",
            m_d.sqrt()
        );
        // Across the tangent, nothing.
        let across = Vector3::new(q[0].cos(), q[0].sin(), 0.0);
        let m_across = index.task_relevant(
            JacobianRows::Translation,
            &jacobian,
            &Direction::Translation(across),
            &q,
        );
        assert!(m_across.abs() < 1e-24);
    }

    /// `‖J'ᵀ u‖²` is `M_T` in every mode (the projection the dynamic index solves with).
    #[test]
    fn the_projection_s_squared_norm_is_the_task_relevant_index() {
        let chain = builtin(BuiltinRobot::Panda);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
        let q: Vec<f64> = (0..chain.dof())
            .map(|_| rng.random_range(-1.0..1.0))
            .collect();
        let mut jacobian = Matrix6xX::zeros(chain.dof());
        chain.pose_and_jacobian_into(&q, &mut jacobian).unwrap();
        let linear = Vector3::new(0.3, -0.2, 0.5);
        let angular = Vector3::new(-0.4, 0.9, 0.1);
        for rows in [
            JacobianRows::Twist { length_scale: 0.3 },
            JacobianRows::Translation,
            JacobianRows::Rotation,
        ] {
            let direction = rows.direction(&linear, &angular).unwrap();
            let mut projection = vec![0.0; chain.dof()];
            rows.projection_into(&jacobian, &direction, &mut projection);
            let squared: f64 = projection.iter().map(|p| p * p).sum();
            let m_t = rows.task_relevant(&jacobian, &direction);
            assert!(
                (squared - m_t).abs() < 1e-12 * m_t,
                "{rows:?}: {squared} vs {m_t}"
            );
        }
    }

    #[test]
    fn a_joint_without_an_effort_limit_is_refused() {
        let urdf = r#"<robot name="r">
            <link name="base"/>
            <link name="arm"><inertial><mass value="1.0"/>
              <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
            <joint name="j" type="continuous"><parent link="base"/><child link="arm"/>
              <axis xyz="0 0 1"/></joint>
            </robot>"#;
        let chain = crate::robot::parse_urdf_chain(urdf, "test", "base", "arm").unwrap();
        let dynamics = chain.dynamics().unwrap();
        let error = DynamicManipulability::new(&dynamics, None).unwrap_err();
        assert!(
            error.to_string().contains("joint 0 has no effort limit"),
            "{error}"
        );
    }
}
