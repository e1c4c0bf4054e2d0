//! Manipulability indices at one configuration and their norms along a path.
//!
//! Pinned definitions (paper eq. 11–17):
//! * Yoshikawa `w = sqrt(det(J Jᵀ))` of the full `J`, its translational rows `Jv` or its
//!   rotational rows `Jω`;
//! * inverse condition number, both as `σmin/σmax` of `J` and as `λmin/λmax` of `J Jᵀ` (its
//!   square, the form printed in the paper);
//! * task-relevant manipulability `M_T = Σ_j λ_j (v_j·u)² = uᵀ J Jᵀ u = ‖Jᵀ u‖²` for a unit
//!   direction `u` (3-D for `Jv` or `Jω`, 6-D for the full `J`);
//! * the velocity transmission ratio `1/sqrt(uᵀ (J Jᵀ)⁻¹ u)`;
//! * the distance to the nearest joint limit and Tsai's joint-limit penalty
//!   `P(q) = 1 − exp(−k Π (q−l)(u−q)/(u−l)²)`, a multiplier of any of the above;
//! * the dynamic task-relevant manipulability `M_D = ‖H M⁻¹ J'ᵀ u‖²`: the square of the largest
//!   acceleration along `u` with each joint's torque within its headroom after gravity
//!   ([`DynamicManipulability`]; not in the paper);
//! * over a path: `μ_l2 = ‖M‖₂`, `μ_l∞ = max_i 1/M_i`, `μ_l1 = ½ Σ (M_i + M_{i+1}) Δt_i`.
//!
//! The settings that choose among them — [`JacobianRows`], [`IndexMeasure`], [`RankedIndex`],
//! [`NormSamples`], [`Norm`] — are here too, with their spellings; tasks carry them.

mod dynamic;
mod indices;
mod limits;
mod norms;
mod settings;
mod tangent;

pub use dynamic::DynamicManipulability;
pub use indices::{
    classical_indices, inverse_condition, inverse_condition_squared, singular_values,
    task_relevant, velocity_transmission_ratio, yoshikawa, ClassicalIndices, Direction,
    JacobianPart,
};
pub use limits::{joint_limit_penalty, limit_distance};
pub use norms::{PathNorms, SampleIndex};
pub use settings::{IndexMeasure, JacobianRows, Norm, NormSamples, RankedIndex};
pub use tangent::{wrist_tangent, STILL_TWIST_TOLERANCE};
