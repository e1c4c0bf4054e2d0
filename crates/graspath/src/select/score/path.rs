//! Path metrics (paper eq. 8–14): the object's motion shared by every candidate, the wrist
//! trajectory and tangent of one grasp, and the index series along a joint path with its norms.

use crate::geometry::se3_log;
use crate::manipulability::{Direction, DynamicManipulability, PathNorms, SampleIndex};
use crate::manipulability::{JacobianRows, NormSamples, RankedIndex};
use crate::robot::Chain;
use crate::task::ObjectPath;
use nalgebra::{Isometry3, Matrix6xX, Rotation3, Vector3, Vector6};

/// The object's body twists between consecutive samples, `log(O_i⁻¹ O_{i+1})`, shared by every
/// candidate: a wrist rigidly attached at `object_from_wrist = (R, p)` moves with the twist
/// `Ad_{W⁻¹} ξ`, so its base-frame tangent is `R_base_object · (v + ω × p, ω)`.
pub(super) struct ObjectMotion {
    /// Per sample: the object's body twist of the interval that defines its tangent.
    twists: Vec<Vector6<f64>>,
    /// Per sample: `base_from_object` rotation.
    rotations: Vec<Rotation3<f64>>,
}

impl ObjectMotion {
    pub(super) fn new(path: &ObjectPath, base_from_world: &Isometry3<f64>) -> Self {
        let poses: Vec<Isometry3<f64>> = path.poses().copied().collect();
        let n = poses.len();
        let twists = (0..n)
            .map(|i| {
                // Forward difference; the last sample takes the backward difference.
                let (a, b) = if i + 1 < n {
                    (i, i + 1)
                } else {
                    (i.saturating_sub(1), i)
                };
                if a == b {
                    Vector6::zeros()
                } else {
                    se3_log(&(poses[a].inverse() * poses[b]))
                }
            })
            .collect();
        let rotations = poses
            .iter()
            .map(|p| (base_from_world * p).rotation.to_rotation_matrix())
            .collect();
        Self { twists, rotations }
    }

    /// The unit tangent direction at sample `i` for a wrist at `object_from_wrist`.
    pub(super) fn tangent(
        &self,
        i: usize,
        object_from_wrist: &Isometry3<f64>,
        mode: JacobianRows,
    ) -> Option<Direction> {
        let xi = &self.twists[i];
        let v = Vector3::new(xi[0], xi[1], xi[2]);
        let w = Vector3::new(xi[3], xi[4], xi[5]);
        let p = object_from_wrist.translation.vector;
        let r = &self.rotations[i];
        let linear = r * (v + w.cross(&p));
        let angular = r * w;
        mode.direction(&linear, &angular)
    }
}

/// The wrist poses `base_from_wrist` along the path for one candidate and arm.
pub fn wrist_trajectory(
    path: &ObjectPath,
    world_from_base: &Isometry3<f64>,
    object_from_wrist: &Isometry3<f64>,
) -> Vec<Isometry3<f64>> {
    let base_from_world = world_from_base.inverse();
    path.poses()
        .map(|world_from_object| base_from_world * world_from_object * object_from_wrist)
        .collect()
}

/// The per-sample indices along one joint path (`None` where the object is still).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct IndexSeries {
    /// `M_T` (eq. 13).
    pub(super) m_t: Vec<Option<f64>>,
    /// The ranked index, when it is not `M_T` itself.
    pub(super) ranked: Option<Vec<Option<f64>>>,
}

impl IndexSeries {
    /// The values the norms are taken of.
    fn ranked(&self) -> &[Option<f64>] {
        self.ranked.as_deref().unwrap_or(&self.m_t)
    }

    /// The norms of the ranked values at the path samples marked in `counted` (`times`: the
    /// samples' times, s).
    pub(super) fn norms(&self, times: &[f64], counted: &[bool]) -> PathNorms {
        let samples: Vec<SampleIndex> = self
            .ranked()
            .iter()
            .zip(times)
            .zip(counted)
            .filter(|(_, counted)| **counted)
            .map(|((&value, &time), _)| SampleIndex { time, value })
            .collect();
        PathNorms::of(&samples)
    }
}

/// Which path samples the norms are taken over ([`NormSamples`]): all of them, or the
/// initial pose and the last sample of each step.
pub(super) fn counted_samples(path: &ObjectPath, over: NormSamples) -> Vec<bool> {
    let samples = &path.samples;
    (0..samples.len())
        .map(|i| match over {
            NormSamples::All => true,
            NormSamples::Waypoints => {
                i == 0 || i + 1 == samples.len() || samples[i + 1].step != samples[i].step
            }
        })
        .collect()
}

/// `M_T` and the ranked index at every sample along one joint path; `dynamic` evaluates the
/// dynamic measure (the arm holding the object).
pub(super) fn index_along(
    chain: &Chain,
    motion: &ObjectMotion,
    object_from_wrist: &Isometry3<f64>,
    joints: &[Vec<f64>],
    (mode, ranked): (JacobianRows, RankedIndex),
    jacobian: &mut Matrix6xX<f64>,
    mut dynamic: Option<&mut DynamicManipulability<'_>>,
) -> IndexSeries {
    let mut m_t = Vec::with_capacity(joints.len());
    let mut values = Vec::with_capacity(joints.len());
    for (i, q) in joints.iter().enumerate() {
        let at = motion
            .tangent(i, object_from_wrist, mode)
            .filter(|_| chain.pose_and_jacobian_into(q, jacobian).is_ok());
        m_t.push(at.map(|d| mode.task_relevant(jacobian, &d)));
        if !ranked.series_is_m_t() {
            values.push(at.map(|d| {
                ranked.value(
                    mode,
                    jacobian,
                    &d,
                    [q, chain.lower(), chain.upper()],
                    dynamic.as_deref_mut(),
                )
            }));
        }
    }
    IndexSeries {
        m_t,
        ranked: (!ranked.series_is_m_t()).then_some(values),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manipulability::wrist_tangent;
    use crate::task::{Sampling, Step, TimedStep};
    use nalgebra::{Translation3, UnitQuaternion};

    #[test]
    fn shared_object_twists_give_the_wrist_tangent_by_definition() {
        // Oracle: `wrist_tangent` on the explicit wrist poses (log of wrist_i⁻¹ wrist_{i+1}).
        let steps = vec![
            TimedStep {
                label: "lift+rotate".into(),
                step: Step::Relative {
                    translation: Vector3::new(0.0, 0.1, 0.2),
                    axis: nalgebra::Unit::new_normalize(Vector3::new(0.2, 0.3, 1.0)),
                    angle: 1.2,
                },
                duration: 1.0,
            },
            TimedStep {
                label: "move".into(),
                step: Step::Relative {
                    translation: Vector3::new(0.0, 0.3, 0.0),
                    axis: Vector3::z_axis(),
                    angle: 0.0,
                },
                duration: 1.0,
            },
        ];
        let start = Isometry3::from_parts(
            Translation3::new(0.7, 0.2, -0.05),
            UnitQuaternion::from_euler_angles(0.1, -0.2, 0.7),
        );
        let path = ObjectPath::sample(start, &steps, Sampling::PerStep(5), 1000).unwrap();
        let world_from_base = Isometry3::from_parts(
            Translation3::new(0.1, -0.3, 0.9),
            UnitQuaternion::from_euler_angles(0.0, 0.1, -0.4),
        );
        let object_from_wrist = Isometry3::from_parts(
            Translation3::new(0.03, -0.08, 0.05),
            UnitQuaternion::from_euler_angles(3.0, 0.2, 1.0),
        );
        let motion = ObjectMotion::new(&path, &world_from_base.inverse());
        let wrists = wrist_trajectory(&path, &world_from_base, &object_from_wrist);
        for mode in [
            JacobianRows::Twist { length_scale: 0.3 },
            JacobianRows::Translation,
            JacobianRows::Rotation,
        ] {
            for i in 0..wrists.len() {
                let (a, b) = if i + 1 < wrists.len() {
                    (i, i + 1)
                } else {
                    (i - 1, i)
                };
                let expected = wrist_tangent(&wrists[a], &wrists[b], mode).map(|d| d.as_full());
                let got = motion
                    .tangent(i, &object_from_wrist, mode)
                    .map(|d| d.as_full());
                match (expected, got) {
                    (Some(e), Some(g)) => {
                        assert!((e - g).norm() < 1e-9, "{mode:?} sample {i}: {e} vs {g}");
                    }
                    (None, None) => assert!(
                        matches!(mode, JacobianRows::Rotation),
                        "only a rotation-free interval is still"
                    ),
                    other => panic!("{mode:?} sample {i}: only one side is still: {other:?}"),
                }
            }
        }
    }
}
