//! Checking a whole motion — approach, grasp, the object's path, retreat — for collisions at
//! every sample and between samples, and measuring its clearance.
//!
//! **Between samples** the arm moves along the straight line in joint space. For two bodies at
//! distances `d_a` and `d_b` at the ends of an interval, where no point of either moves more
//! than `B_1` and `B_2` along it ([`crate::robot::SweepBound`], taken near the configurations
//! at the interval's ends, where the joint axes and the bodies are known), the distance inside
//! the interval is at least `(d_a + d_b − B_1 − B_2) / 2`. When that exceeds the required
//! distance the interval is clear; otherwise it is halved (each half's bound taken near the
//! middle configuration) and the middle checked, until the bound is below
//! [`CollisionOptions::resolution`]. So no collision deeper than half the resolution can hide
//! between checked configurations, and every reported collision has a witness configuration.
//! Distances are first bounded below by bounding spheres, then by sphere covers ([`Body`]'s
//! few spheres along a box, cylinder or capsule, against the other body's closed-form point
//! distance), then by the separation along box face normals; the exact distance (parry3d) is
//! computed only where no bound decides. Any lower bound serves in the interval bound above,
//! so only hits need exact distances.
//!
//! **Which pairs** (the required distance in brackets):
//! * every moving arm and hand body against every scene body (`margin`); the links before the
//!   arm's first moving joint (a pedestal, a torso) stand where the robot was placed and are
//!   not checked against the scene;
//! * before the grasp and after the release, the object (where it stands) against the arm's
//!   links (touching is a collision) and the hand (touching allowed, pressing deeper than
//!   `touch_tolerance` not);
//! * from the grasp to the place, the carried object against the scene (`margin`; against the
//!   table and any body it stands on at the pick or the place — within the margin of it there
//!   — resting is allowed) and against the arm's links outside the hand's rigid group;
//! * the arm's self-collision pairs ([`super::ArmBodies`]), touching is a collision.

use super::arm::{ArmBodies, RigidLink};
use super::body::{Body, Placed};
use super::scene::Scene;
use crate::robot::{JointAxes, JointAxis};
use nalgebra::{Isometry3, IsometryMatrix3};
use std::ops::Range;

mod tool;
mod whole;

/// Collision settings. In a task file: `collision: { margin, self, between_arms,
/// touch_tolerance, resolution }`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CollisionOptions {
    /// The clearance the robot, its hand and the carried object keep from the scene (m).
    pub margin: f64,
    /// Check the arm against itself.
    pub self_collision: bool,
    /// Check two arms against each other.
    pub between_arms: bool,
    /// How deep an allowed contact (fingers on the object, the object on the table) may press
    /// before it is a collision (m).
    pub touch_tolerance: f64,
    /// The continuous check's resolution (m): nothing penetrates deeper than half of it
    /// undetected between checked configurations.
    pub resolution: f64,
}

impl Default for CollisionOptions {
    /// 1 cm margin, self and arm–arm checks on, 1 mm touch tolerance, 0.1 mm resolution.
    fn default() -> Self {
        Self {
            margin: 0.01,
            self_collision: true,
            between_arms: true,
            touch_tolerance: 0.001,
            resolution: 1e-4,
        }
    }
}

/// Where the object is along a motion's samples: standing until the grasp, carried by the
/// tool from the grasp to the place, standing again after it.
#[derive(Debug, Clone)]
pub struct ObjectAlong<'a> {
    /// The samples of the object's path: `path.start` is the grasp, `path.end − 1` the place.
    pub path: Range<usize>,
    /// The object's pose at the grasp, world frame.
    pub world_from_object_start: &'a Isometry3<f64>,
    /// The object's pose at the place, world frame.
    pub world_from_object_end: &'a Isometry3<f64>,
    /// The grasp: the tool pose in the object frame.
    pub object_from_wrist: &'a Isometry3<f64>,
}

impl ObjectAlong<'_> {
    /// The stretches of a motion of `n` samples where the object stands, is carried and
    /// stands again (the grasp and the place samples belong to both stretches they join).
    fn stretches(&self, n: usize) -> [(ObjectAt, Range<usize>); 3] {
        let grasp = self.path.start.min(n.saturating_sub(1));
        let place = self.path.end.saturating_sub(1).max(grasp);
        [
            (ObjectAt::Start, 0..grasp + 1),
            (ObjectAt::Carried, grasp..place + 1),
            (ObjectAt::End, place..n),
        ]
    }
}

/// A whole motion of one arm and where the object is along it.
#[derive(Debug, Clone)]
pub struct WholeMotion<'a> {
    /// Every configuration in order, approach → path → retreat (rad / m).
    pub q: &'a [Vec<f64>],
    /// Where the object is.
    pub object: ObjectAlong<'a>,
}

/// The motion the task commands the tool to make, before any IK: its pose at every sample.
#[derive(Debug, Clone)]
pub struct ToolMotion<'a> {
    /// `base_from_tool` at every sample in order, approach → path → retreat (m).
    pub base_from_tool: &'a [Isometry3<f64>],
    /// Where the object is.
    pub object: ObjectAlong<'a>,
}

/// The first collision found along a motion.
#[derive(Debug, Clone, PartialEq)]
pub struct CollisionHit {
    /// The sample (index into [`WholeMotion::q`]) at which, or just after which, it happens.
    pub sample: usize,
    /// Whether the witness configuration lies between `sample` and `sample + 1`.
    pub between: bool,
    /// The two bodies.
    pub bodies: [String; 2],
    /// Their distance at the witness (m; negative: penetration depth, where known).
    pub distance: f64,
    /// The distance they had to keep (m).
    pub required: f64,
}

/// The outcome of checking a motion.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionCheck {
    /// The first collision, if any.
    pub hit: Option<CollisionHit>,
    /// The smallest distance between the robot (with hand and carried object) and the scene
    /// at any sample (m), allowed contacts excluded; `None` with an empty scene.
    pub clearance: Option<f64>,
}

/// Where the object is during a stretch of the motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ObjectAt {
    Start,
    Carried,
    End,
}

/// One pair to check: two slots and the distance they must keep.
#[derive(Debug, Clone, Copy)]
struct Pair {
    a: usize,
    b: usize,
    required: f64,
    /// Counts towards the clearance.
    scene: bool,
}

/// How a distance was obtained, cheapest first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Level {
    /// The bounding spheres' gap: a lower bound.
    Sphere,
    /// The covers' bound ([`Placed::lower_bound`]): a tighter lower bound.
    Cover,
    /// The larger of the covers' bound and the separation along a box's face normals
    /// ([`Placed::separation`]): tighter again where a box faces a flat obstacle.
    Separation,
    /// The exact distance.
    Exact,
}

impl Level {
    fn next(self) -> Self {
        match self {
            Self::Sphere => Self::Cover,
            Self::Cover => Self::Separation,
            _ => Self::Exact,
        }
    }
}

/// A distance known at a configuration: exact, or a lower bound.
#[derive(Debug, Clone, Copy)]
struct Known {
    value: f64,
    level: Level,
}

/// An arm, its place in the world, the scene and the object: everything a motion is checked
/// against.
#[derive(Debug, Clone, Copy)]
pub struct ArmInScene<'a> {
    /// The arm's bodies.
    pub arm: &'a ArmBodies,
    /// Where the arm's base is, `world_from_base`.
    pub world_from_base: &'a Isometry3<f64>,
    /// The scene.
    pub scene: &'a Scene,
    /// The object's body (object frame), when its shape is known.
    pub object: Option<&'a Body>,
    /// Settings.
    pub options: &'a CollisionOptions,
}

/// Slots: arm bodies `0..A`, scene bodies `A..A+S`, the object `A+S`.
struct Slots<'a> {
    setup: ArmInScene<'a>,
    world_from_base: IsometryMatrix3<f64>,
    scene: Vec<Placed<'a>>,
    arm_count: usize,
    /// The carried object on the tip link, `link_from_object`.
    link_from_object: IsometryMatrix3<f64>,
    object_reach: f64,
    /// The object where it stands before the grasp and after the place, world frame.
    world_from_object_start: IsometryMatrix3<f64>,
    world_from_object_end: IsometryMatrix3<f64>,
    /// Per scene body: the object rests on it (the table, or a body within the margin of
    /// the object where it stands at the pick or the place), so touching it is allowed.
    supports: Vec<bool>,
}

impl<'a> Slots<'a> {
    fn new(setup: ArmInScene<'a>, object: &ObjectAlong<'_>) -> Self {
        let arm = setup.arm;
        let wrist_from_object: IsometryMatrix3<f64> =
            nalgebra::convert(object.object_from_wrist.inverse());
        let link_from_object = arm.link_from_tool * wrist_from_object;
        let object_reach = setup.object.map_or(0.0, |o| {
            let (centre, radius) = o.bounding_sphere();
            (link_from_object * centre).coords.norm() + radius
        });
        let mut slots = Slots {
            setup,
            world_from_base: nalgebra::convert(*setup.world_from_base),
            scene: setup
                .scene
                .bodies()
                .iter()
                .map(|(body, pose)| Placed::new(body, nalgebra::convert(*pose)))
                .collect(),
            arm_count: arm.bodies.len(),
            link_from_object,
            object_reach,
            world_from_object_start: nalgebra::convert(*object.world_from_object_start),
            world_from_object_end: nalgebra::convert(*object.world_from_object_end),
            supports: Vec::new(),
        };
        slots.supports = slots.find_supports();
        slots
    }

    /// Which scene bodies the object rests on ([`Slots::supports`]).
    fn find_supports(&self) -> Vec<bool> {
        let table = self.setup.scene.table().is_some();
        let margin = self.setup.options.margin;
        self.scene
            .iter()
            .enumerate()
            .map(|(k, body)| {
                // The table is the scene's first body.
                (k == 0 && table)
                    || self.setup.object.is_some_and(|object| {
                        [self.world_from_object_start, self.world_from_object_end]
                            .into_iter()
                            .any(|pose| {
                                let placed = Placed::new(object, pose);
                                placed.gap(body) < margin && placed.distance(body) < margin
                            })
                    })
            })
            .collect()
    }

    fn object_slot(&self) -> usize {
        self.arm_count + self.scene.len()
    }

    fn pairs(&self, at: ObjectAt) -> Vec<Pair> {
        let arm = self.setup.arm;
        let options = self.setup.options;
        let a = self.arm_count;
        let mut pairs = Vec::new();
        // The arm's fixed links (before its first moving joint) stand where the robot was
        // placed; only moving bodies are checked against the scene.
        for i in (0..a).filter(|&i| arm.bodies[i].group > 0) {
            for k in 0..self.scene.len() {
                pairs.push(Pair {
                    a: i,
                    b: a + k,
                    required: options.margin,
                    scene: true,
                });
            }
        }
        if self.setup.object.is_some() {
            let o = self.object_slot();
            let tip_group = arm.tip_group;
            match at {
                ObjectAt::Start | ObjectAt::End => {
                    for (i, b) in arm.bodies.iter().enumerate() {
                        let required = if b.hand {
                            -options.touch_tolerance
                        } else {
                            0.0
                        };
                        pairs.push(Pair {
                            a: i,
                            b: o,
                            required,
                            scene: false,
                        });
                    }
                }
                ObjectAt::Carried => {
                    for k in 0..self.scene.len() {
                        let resting = self.supports[k];
                        pairs.push(Pair {
                            a: o,
                            b: a + k,
                            required: if resting {
                                -options.touch_tolerance
                            } else {
                                options.margin
                            },
                            scene: !resting,
                        });
                    }
                    for (i, b) in arm.bodies.iter().enumerate() {
                        if b.group != tip_group && !b.hand {
                            pairs.push(Pair {
                                a: i,
                                b: o,
                                required: 0.0,
                                scene: false,
                            });
                        }
                    }
                }
            }
        }
        if options.self_collision {
            pairs.extend(arm.self_pairs.iter().map(|&(i, j)| Pair {
                a: i,
                b: j,
                required: 0.0,
                scene: false,
            }));
        }
        pairs
    }

    /// Slot `i` placed at the configuration with link `frames`.
    fn slot(&self, i: usize, frames: &[IsometryMatrix3<f64>], at: ObjectAt) -> Placed<'a> {
        if i < self.arm_count {
            return self.setup.arm.place(i, &self.world_from_base, frames);
        }
        if let Some(placed) = self.scene.get(i - self.arm_count) {
            return *placed;
        }
        let object = self
            .setup
            .object
            .expect("the object slot exists only with an object");
        let world_from_object: IsometryMatrix3<f64> = match at {
            ObjectAt::Start => self.world_from_object_start,
            ObjectAt::End => self.world_from_object_end,
            ObjectAt::Carried => {
                self.world_from_base * frames[self.setup.arm.tip] * self.link_from_object
            }
        };
        Placed::new(object, world_from_object)
    }

    /// Every slot placed at the configuration with link `frames`, into `placed` (cleared).
    fn place_into(
        &self,
        frames: &[IsometryMatrix3<f64>],
        at: ObjectAt,
        placed: &mut Vec<Placed<'a>>,
    ) {
        placed.clear();
        let count = self.object_slot() + usize::from(self.setup.object.is_some());
        placed.extend((0..count).map(|i| self.slot(i, frames, at)));
    }

    /// Whether slot `i`'s pose follows from the tool's pose alone (a scene body, the object,
    /// or an arm body on a link rigid with the base or the tool).
    fn follows_tool(&self, i: usize) -> bool {
        i >= self.arm_count || {
            let arm = self.setup.arm;
            !matches!(arm.rigid[arm.bodies[i].link], RigidLink::Moving)
        }
    }

    /// How far slot `i` may move between `qa` and `qb` (0 for fixed slots), bounded near the
    /// configuration where the slot is `placed` and the joint axes are `axes` (world frame);
    /// never more than the static bound.
    fn displacement(
        &self,
        i: usize,
        at: ObjectAt,
        placed: &Placed<'_>,
        axes: &[JointAxis],
        (qa, qb): (&[f64], &[f64]),
    ) -> f64 {
        let arm = self.setup.arm;
        let (link, reach) = if i < self.arm_count {
            let b = &arm.bodies[i];
            (b.link, b.reach)
        } else if i == self.object_slot() && at == ObjectAt::Carried {
            (arm.tip, self.object_reach)
        } else {
            return 0.0;
        };
        let sphere = (&placed.centre, placed.body.bounding_sphere().1);
        arm.sweep()
            .displacement_near(link, reach, sphere, axes, qa, qb)
    }

    /// How far each slot may move between the configurations `ends` (0 for fixed slots), into
    /// `out`: the near bound from whichever end gives the smaller one.
    fn displacements_into(
        &self,
        at: ObjectAt,
        (placed_a, axes_a): (&[Placed<'_>], &[JointAxis]),
        (placed_b, axes_b): (&[Placed<'_>], &[JointAxis]),
        ends: (&[f64], &[f64]),
        out: &mut Vec<f64>,
    ) {
        out.clear();
        out.extend(
            placed_a
                .iter()
                .zip(placed_b)
                .enumerate()
                .map(|(i, (a, b))| {
                    let near_a = self.displacement(i, at, a, axes_a, ends);
                    near_a.min(self.displacement(i, at, b, axes_b, ends))
                }),
        );
    }
}

impl Pair {
    /// Whether a distance breaks the pair's requirement: closer than required, or touching
    /// (an unsigned distance of 0 hides any overlap) where touching is not allowed.
    fn violated_by(&self, distance: f64) -> bool {
        distance < self.required || (self.required >= 0.0 && distance <= 0.0)
    }
}

/// The distance of a pair at one configuration, refined no less than `at_least`: the
/// bounding spheres' gap, then the covers' bound, then the separation along box faces (both
/// only when positive: a lower bound says nothing of a penetration depth), then the exact
/// distance — each only when the cheaper one is below what `at_least` asks for or breaks the
/// pair's requirement.
fn measure(pair: &Pair, x: &Placed<'_>, y: &Placed<'_>, at_least: Level) -> Known {
    if at_least == Level::Sphere {
        let gap = x.gap(y);
        if !pair.violated_by(gap) {
            return Known {
                value: gap,
                level: Level::Sphere,
            };
        }
    }
    if at_least <= Level::Separation {
        let cover = x.lower_bound(y);
        if at_least <= Level::Cover && cover > 0.0 && !pair.violated_by(cover) {
            return Known {
                value: cover,
                level: Level::Cover,
            };
        }
        let bound = cover.max(x.separation(y));
        if bound > 0.0 && !pair.violated_by(bound) {
            return Known {
                value: bound,
                level: Level::Separation,
            };
        }
    }
    let value = if pair.required < 0.0 {
        x.signed_distance(y)
    } else {
        x.distance(y)
    };
    Known {
        value,
        level: Level::Exact,
    }
}

/// Whether two bodies at their poses (any common frame) keep at least `required` (m) apart —
/// touching counts as closer when `required ≥ 0`; with `required < 0`, overlap is allowed
/// up to that depth — decided as the motion checks decide every pair at every sample: the
/// bounding spheres, then the covers' bound, and the exact distance only when neither
/// settles it.
pub fn keeps_apart(
    a: &Body,
    frame_from_a: &Isometry3<f64>,
    b: &Body,
    frame_from_b: &Isometry3<f64>,
    required: f64,
) -> bool {
    let pair = Pair {
        a: 0,
        b: 1,
        required,
        scene: false,
    };
    let x = Placed::new(a, nalgebra::convert(*frame_from_a));
    let y = Placed::new(b, nalgebra::convert(*frame_from_b));
    !pair.violated_by(measure(&pair, &x, &y, Level::Sphere).value)
}

fn hit(
    pair: &Pair,
    x: &Placed<'_>,
    y: &Placed<'_>,
    distance: f64,
    sample: usize,
    between: bool,
) -> CollisionHit {
    CollisionHit {
        sample,
        between,
        bodies: [x.body.name().to_string(), y.body.name().to_string()],
        distance,
        required: pair.required,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::distance;
    use crate::geometry::shape::Shape;
    use nalgebra::{Translation3, UnitQuaternion};
    use rand::{rngs::StdRng, RngExt, SeedableRng};

    #[test]
    fn keeps_apart_agrees_with_the_exact_distance() {
        // Oracle: the exact distance (parry) compared with the margin.
        let shapes = [
            Shape::cuboid([0.04, 0.4, 0.5]).unwrap(),
            Shape::cylinder(0.06, 0.273).unwrap(),
            Shape::capsule(0.03, 0.3).unwrap(),
            Shape::sphere(0.05).unwrap(),
        ];
        let bodies: Vec<Body> = shapes.iter().map(|s| Body::from_shape("s", s)).collect();
        let mut rng = StdRng::seed_from_u64(5);
        let pose = |rng: &mut StdRng| {
            Isometry3::from_parts(
                Translation3::new(
                    rng.random_range(-0.3..0.3),
                    rng.random_range(-0.3..0.3),
                    rng.random_range(-0.3..0.3),
                ),
                UnitQuaternion::from_euler_angles(
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-1.5..1.5),
                    rng.random_range(-3.0..3.0),
                ),
            )
        };
        let (mut apart, mut close) = (0, 0);
        for _ in 0..3000 {
            let a = &bodies[rng.random_range(0..bodies.len())];
            let b = &bodies[rng.random_range(0..bodies.len())];
            let (pa, pb) = (pose(&mut rng), pose(&mut rng));
            let margin = rng.random_range(0.0..0.05);
            let d = distance(a, &pa, b, &pb);
            let expected = d >= margin && d > 0.0;
            assert_eq!(
                keeps_apart(a, &pa, b, &pb, margin),
                expected,
                "d {d}, margin {margin}"
            );
            if expected {
                apart += 1;
            } else {
                close += 1;
            }
        }
        assert!(apart > 300 && close > 300, "{apart} apart, {close} close");
    }
}
