//! The desired object trajectory: waypoints and their sampling in SE(3).

use crate::geometry::interpolate_decoupled;
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

/// One step of an object trajectory, starting from where the previous step ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// Go to an absolute pose `world_from_object` (straight line and slerp).
    Pose(Isometry3<f64>),
    /// Translate by a world-frame vector (m) while turning by `angle` (rad) about a world-frame
    /// `axis` through the object's origin (`lift`, `move`, `place` and `rotate` are special
    /// cases). Angles beyond π are followed the long way, as given.
    Relative {
        /// World-frame translation (m).
        translation: Vector3<f64>,
        /// World-frame unit rotation axis.
        axis: Unit<Vector3<f64>>,
        /// Rotation angle (rad), right-handed about `axis`.
        angle: f64,
    },
}

/// How densely each step is sampled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sampling {
    /// The same number of samples in every step (≥ 1).
    PerStep(usize),
    /// At most this spacing between samples: metres of translation and radians of rotation.
    Spacing {
        /// Largest translation between samples (m).
        translation: f64,
        /// Largest rotation between samples (rad).
        rotation: f64,
    },
    /// This many samples over the whole path (initial pose included), shared among the steps in
    /// proportion to their length (translation in m plus rotation in rad × 0.1 m), at least one
    /// per step.
    Total(usize),
}

/// One sample of the object trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct PathSample {
    /// Time (s) from the start of the task.
    pub time: f64,
    /// The object pose `world_from_object`.
    pub world_from_object: Isometry3<f64>,
    /// Index of the step this sample ends in (0 for the initial pose, which belongs to no step).
    pub step: usize,
}

/// A sampled object trajectory: the initial pose, then each step's samples in order.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectPath {
    /// Samples in time order; the first is the initial (grasp) pose at `t = 0`.
    pub samples: Vec<PathSample>,
    /// The steps' labels (`lift`, `move`, ...), in order.
    pub step_labels: Vec<String>,
}

impl Step {
    /// A pure translation by a world-frame vector (m): `lift`, `move`, `place`.
    pub fn translation(translation: Vector3<f64>) -> Self {
        Step::Relative {
            translation,
            axis: Vector3::z_axis(),
            angle: 0.0,
        }
    }
}

/// A labelled step with its duration (s).
#[derive(Debug, Clone, PartialEq)]
pub struct TimedStep {
    /// A name for reports (`lift`, `rotate`, ...).
    pub label: String,
    /// The motion.
    pub step: Step,
    /// Duration (s), > 0.
    pub duration: f64,
}

impl TimedStep {
    /// A step lasting the default [`STEP_DURATION`](crate::defaults::STEP_DURATION).
    pub fn new(label: impl Into<String>, step: Step) -> Self {
        Self {
            label: label.into(),
            step,
            duration: crate::defaults::STEP_DURATION,
        }
    }
}

/// Why an object path cannot be sampled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PathError {
    /// A step's duration is not a positive number of seconds.
    #[error("step {step} ({label}): duration must be a positive number of seconds")]
    Duration {
        /// The step's index.
        step: usize,
        /// The step's label.
        label: String,
    },
    /// The sampling asks for no sample, or for a spacing that is not positive.
    #[error("{0}")]
    Sampling(&'static str),
    /// `Total(n)` with fewer samples than the steps need.
    #[error("{total} samples cannot cover {steps} steps (need at least {})", steps + 1)]
    TooFewSamples {
        /// The samples asked for.
        total: usize,
        /// The number of steps.
        steps: usize,
    },
    /// The sampling would give more samples than allowed.
    #[error("the path would have {count:.0} samples, more than the limit {limit}; use fewer samples (or raise limits.max_samples)")]
    TooManySamples {
        /// The number of samples asked for (as a float: it may not fit an integer).
        count: f64,
        /// The limit.
        limit: usize,
    },
}

impl PathError {
    /// The task-file field at fault.
    pub fn field(&self) -> String {
        match self {
            PathError::Duration { step, .. } => format!("trajectory.steps[{step}].duration"),
            _ => "trajectory".into(),
        }
    }
}

impl crate::fault::Classify for PathError {
    /// More samples than the limit is [`ErrorKind`](crate::fault::ErrorKind)`::Limit`; everything else
    /// is `Content`. (The field is [`PathError::field`].)
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        Some(match self {
            Self::TooManySamples { .. } => crate::fault::ErrorKind::Limit,
            _ => crate::fault::ErrorKind::Content,
        })
    }
}

struct Segment {
    start: Isometry3<f64>,
    step: Step,
    end: Isometry3<f64>,
    length: f64,
    rotation: f64,
    translation: f64,
}

impl Segment {
    fn new(start: Isometry3<f64>, step: &Step) -> Self {
        let end = match step {
            Step::Pose(pose) => *pose,
            Step::Relative {
                translation,
                axis,
                angle,
            } => Isometry3::from_parts(
                Translation3::from(start.translation.vector + translation),
                UnitQuaternion::from_axis_angle(axis, *angle) * start.rotation,
            ),
        };
        let (translation, rotation) = match step {
            Step::Pose(pose) => (
                (pose.translation.vector - start.translation.vector).norm(),
                start.rotation.angle_to(&pose.rotation),
            ),
            Step::Relative {
                translation, angle, ..
            } => (translation.norm(), angle.abs()),
        };
        Self {
            start,
            step: step.clone(),
            end,
            length: translation + 0.1 * rotation,
            rotation,
            translation,
        }
    }

    fn at(&self, s: f64) -> Isometry3<f64> {
        match &self.step {
            Step::Pose(pose) => interpolate_decoupled(&self.start, pose, s),
            Step::Relative {
                translation,
                axis,
                angle,
            } => Isometry3::from_parts(
                Translation3::from(self.start.translation.vector + translation * s),
                UnitQuaternion::from_axis_angle(axis, angle * s) * self.start.rotation,
            ),
        }
    }
}

impl ObjectPath {
    /// Samples the trajectory that starts at `world_from_object` and performs `steps` in order.
    ///
    /// Errors on a non-positive duration, a zero sample count or spacing, and on more than
    /// `max_samples` samples (checked before anything is allocated).
    pub fn sample(
        world_from_object: Isometry3<f64>,
        steps: &[TimedStep],
        sampling: Sampling,
        max_samples: usize,
    ) -> Result<Self, PathError> {
        let mut segments = Vec::with_capacity(steps.len());
        let mut pose = world_from_object;
        for (k, timed) in steps.iter().enumerate() {
            if !(timed.duration.is_finite() && timed.duration > 0.0) {
                return Err(PathError::Duration {
                    step: k,
                    label: timed.label.clone(),
                });
            }
            let segment = Segment::new(pose, &timed.step);
            pose = segment.end;
            segments.push(segment);
        }
        let counts = sample_counts(&segments, sampling, max_samples)?;
        let mut samples = Vec::with_capacity(1 + counts.iter().sum::<usize>());
        samples.push(PathSample {
            time: 0.0,
            world_from_object,
            step: 0,
        });
        let mut t0 = 0.0;
        for (k, (segment, timed)) in segments.iter().zip(steps).enumerate() {
            let n = counts[k];
            for j in 1..=n {
                let s = j as f64 / n as f64;
                samples.push(PathSample {
                    time: t0 + s * timed.duration,
                    world_from_object: if j == n { segment.end } else { segment.at(s) },
                    step: k,
                });
            }
            t0 += timed.duration;
        }
        Ok(Self {
            samples,
            step_labels: steps.iter().map(|s| s.label.clone()).collect(),
        })
    }

    /// The object poses in time order.
    pub fn poses(&self) -> impl Iterator<Item = &Isometry3<f64>> {
        self.samples.iter().map(|s| &s.world_from_object)
    }

    /// The sample times (s).
    pub fn times(&self) -> Vec<f64> {
        self.samples.iter().map(|s| s.time).collect()
    }

    /// The same path seen from another world frame: every pose premultiplied by
    /// `new_world_from_world`.
    pub fn transformed(&self, new_world_from_world: &Isometry3<f64>) -> Self {
        let mut moved = self.clone();
        for s in &mut moved.samples {
            s.world_from_object = new_world_from_world * s.world_from_object;
        }
        moved
    }
}

/// Samples per segment; the total (initial pose included) is at most `max_samples`.
fn sample_counts(
    segments: &[Segment],
    sampling: Sampling,
    max_samples: usize,
) -> Result<Vec<usize>, PathError> {
    let too_many = |count: f64| PathError::TooManySamples {
        count,
        limit: max_samples,
    };
    match sampling {
        Sampling::PerStep(0) => Err(PathError::Sampling("samples per step must be at least 1")),
        Sampling::PerStep(n) => {
            let count = 1.0 + n as f64 * segments.len() as f64;
            if count > max_samples as f64 {
                return Err(too_many(count));
            }
            Ok(vec![n; segments.len()])
        }
        Sampling::Spacing {
            translation,
            rotation,
        } => {
            if !(translation > 0.0 && rotation > 0.0) {
                return Err(PathError::Sampling(
                    "spacing must be positive (translation in m, rotation in rad)",
                ));
            }
            let counts: Vec<f64> = segments
                .iter()
                .map(|s| {
                    (s.translation / translation)
                        .max(s.rotation / rotation)
                        .ceil()
                        .max(1.0)
                })
                .collect();
            let count = 1.0 + counts.iter().sum::<f64>();
            // NaN (an infinite step over an infinite spacing) is refused too.
            if count.is_nan() || count > max_samples as f64 {
                return Err(too_many(count));
            }
            Ok(counts.into_iter().map(|n| n as usize).collect())
        }
        Sampling::Total(total) => {
            if total > max_samples {
                return Err(too_many(total as f64));
            }
            if total < segments.len() + 1 {
                return Err(PathError::TooFewSamples {
                    total,
                    steps: segments.len(),
                });
            }
            let available = total - 1 - segments.len();
            let total_length: f64 = segments.iter().map(|s| s.length).sum();
            let mut counts: Vec<usize> = vec![1; segments.len()];
            if total_length > 0.0 {
                // Largest-remainder apportionment of the samples beyond the first per step.
                let shares: Vec<f64> = segments
                    .iter()
                    .map(|s| available as f64 * s.length / total_length)
                    .collect();
                for (c, share) in counts.iter_mut().zip(&shares) {
                    *c += share.floor() as usize;
                }
                let mut left = total - 1 - counts.iter().sum::<usize>();
                let mut order: Vec<usize> = (0..segments.len()).collect();
                order.sort_by(|&a, &b| {
                    (shares[b] - shares[b].floor())
                        .total_cmp(&(shares[a] - shares[a].floor()))
                        .then(a.cmp(&b))
                });
                for &k in order.iter().cycle() {
                    if left == 0 {
                        break;
                    }
                    counts[k] += 1;
                    left -= 1;
                }
            } else {
                counts[0] += available;
            }
            Ok(counts)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn lift_move_place() -> Vec<TimedStep> {
        let relative = |label: &str, t: Vector3<f64>| TimedStep {
            label: label.into(),
            step: Step::Relative {
                translation: t,
                axis: Vector3::z_axis(),
                angle: 0.0,
            },
            duration: 1.0,
        };
        vec![
            relative("lift", Vector3::new(0.0, 0.0, 0.2)),
            relative("move", Vector3::new(0.0, 0.3, 0.0)),
            relative("place", Vector3::new(0.0, 0.0, -0.2)),
        ]
    }

    #[test]
    fn total_sampling_gives_the_requested_count_and_ends_at_the_goal() {
        let start = Isometry3::translation(0.7, 0.25, -0.05);
        let path =
            ObjectPath::sample(start, &lift_move_place(), Sampling::Total(50), 1000).unwrap();
        assert_eq!(path.samples.len(), 50);
        let end = path.samples.last().unwrap();
        assert_relative_eq!(
            end.world_from_object.translation.vector,
            Vector3::new(0.7, 0.55, -0.05),
            epsilon = 1e-15
        );
        assert_relative_eq!(end.time, 3.0);
        // Times increase strictly.
        assert!(path.samples.windows(2).all(|w| w[1].time > w[0].time));
        // The longer middle step gets more samples than each vertical one.
        let count = |k| path.samples.iter().skip(1).filter(|s| s.step == k).count();
        assert!(count(1) > count(0) && count(1) > count(2));
        assert_eq!(count(0) + count(1) + count(2), 49);
    }

    #[test]
    fn rotation_beyond_half_a_turn_goes_the_long_way() {
        let steps = vec![TimedStep {
            label: "rotate".into(),
            step: Step::Relative {
                translation: Vector3::zeros(),
                axis: Vector3::z_axis(),
                angle: 270f64.to_radians(),
            },
            duration: 2.0,
        }];
        let path =
            ObjectPath::sample(Isometry3::identity(), &steps, Sampling::PerStep(3), 1000).unwrap();
        let yaw = |k: usize| path.samples[k].world_from_object.rotation.euler_angles().2;
        assert_relative_eq!(yaw(1), 90f64.to_radians(), epsilon = 1e-12);
        assert_relative_eq!(yaw(2), 180f64.to_radians().abs(), epsilon = 1e-9);
        assert_relative_eq!(yaw(3), -90f64.to_radians(), epsilon = 1e-12);
    }

    #[test]
    fn spacing_and_bad_inputs() {
        let path = ObjectPath::sample(
            Isometry3::identity(),
            &lift_move_place(),
            Sampling::Spacing {
                translation: 0.05,
                rotation: 0.1,
            },
            1000,
        )
        .unwrap();
        assert_eq!(path.samples.len(), 1 + 4 + 6 + 4);
        assert!(ObjectPath::sample(
            Isometry3::identity(),
            &lift_move_place(),
            Sampling::PerStep(0),
            1000
        )
        .is_err());
        assert!(ObjectPath::sample(
            Isometry3::identity(),
            &lift_move_place(),
            Sampling::Total(3),
            1000
        )
        .is_err());
        let mut steps = lift_move_place();
        steps[1].duration = 0.0;
        let err = ObjectPath::sample(Isometry3::identity(), &steps, Sampling::PerStep(2), 1000)
            .unwrap_err();
        assert!(err.to_string().contains("step 1 (move)"), "{err}");
        assert_eq!(err.field(), "trajectory.steps[1].duration");
    }

    #[test]
    fn sample_counts_are_bounded_before_anything_is_allocated() {
        // Three steps: PerStep(n) gives 1 + 3n samples, Total(n) n, and a 1e-12 m spacing over
        // the 0.3 m move 3e11 samples: each is refused just above the limit, accepted at it.
        let steps = lift_move_place();
        let start = Isometry3::identity();
        assert_eq!(
            ObjectPath::sample(start, &steps, Sampling::PerStep(3), 10)
                .unwrap()
                .samples
                .len(),
            10
        );
        let refused = [
            Sampling::PerStep(4),
            Sampling::PerStep(1_000_000_000),
            Sampling::Total(11),
            Sampling::Total(usize::MAX),
            Sampling::Spacing {
                translation: 1e-12,
                rotation: 0.1,
            },
        ];
        for sampling in refused {
            let err = ObjectPath::sample(start, &steps, sampling, 10).unwrap_err();
            assert!(
                matches!(err, PathError::TooManySamples { limit: 10, .. }),
                "{err}"
            );
        }
    }
}
