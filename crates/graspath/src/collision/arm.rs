//! An arm's bodies: the collision shapes of its chain's links and of the hand on its tool, each
//! on its link frame, with the pairs of them that self-collision checks visit.

use super::body::{Body, Placed};
use super::CollisionError;
use crate::geometry::shape::Shape;
use crate::random::{derive_seed, splitmix64};
use crate::robot::{Chain, SweepBound};
use nalgebra::{Isometry3, IsometryMatrix3};

/// One collision shape of a link, as the robot describes it (meshes already read).
#[derive(Debug, Clone)]
pub struct LinkShape {
    /// The link's name.
    pub link: String,
    /// The shape's frame in the link frame (m).
    pub link_from_shape: Isometry3<f64>,
    /// The shape.
    pub shape: Shape,
}

/// A body riding on a link of the chain.
#[derive(Debug, Clone)]
pub(crate) struct LinkBody {
    /// Index in [`Chain::link_names`].
    pub link: usize,
    pub link_from_body: IsometryMatrix3<f64>,
    pub body: Body,
    /// Rigid group: 0 before the first moving joint, `j + 1` for links carried by joint `j`.
    pub group: usize,
    /// The farthest any point of the body is from its link origin (m).
    pub reach: f64,
    /// Part of the hand (may touch the object at the grasp).
    pub hand: bool,
}

/// Where a link is when that does not depend on the configuration.
#[derive(Debug, Clone, Copy)]
pub(crate) enum RigidLink {
    /// Before the first moving joint: `base_from_link`.
    Base(IsometryMatrix3<f64>),
    /// Carried rigidly by the tool (no moving joint between them): `tool_from_link`.
    Tool(IsometryMatrix3<f64>),
    /// Moved by a joint that the tool is not rigid with.
    Moving,
}

/// How self-collision pairs are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SelfPairs {
    /// Every pair of bodies more than two joints apart (a wrist's short middle link puts the
    /// links on either side of it into contact by design: on Baxter the forearm and the wrist
    /// cylinders touch in half of all configurations), except, as MoveIt's setup assistant
    /// does, those in contact at the chain's mid configuration ("default"), those in contact
    /// in at least [`ALWAYS_FRACTION`] of [`SELF_PAIR_SAMPLES`] random configurations
    /// ("always": a modelling overlap) and those whose bounding spheres never meet in any of
    /// them ("never").
    #[default]
    Sampled,
    /// Every pair of bodies on non-adjacent rigid groups.
    All,
    /// No self-collision checks.
    None,
}

/// How many random configurations decide the sampled self-collision pairs.
pub const SELF_PAIR_SAMPLES: usize = 2000;

/// The fraction of sampled configurations in contact that makes a pair "always" in
/// collision (MoveIt's default, 95 %).
pub const ALWAYS_FRACTION: f64 = 0.95;

/// The random stream of the sampled self-collision configurations (fixed: the pairs depend
/// only on the robot).
const SELF_PAIR_STREAM: u64 = 0x5e1f_c011;

/// An arm's bodies and what moves them.
#[derive(Debug, Clone)]
pub struct ArmBodies {
    chain: Chain,
    sweep: SweepBound,
    pub(crate) bodies: Vec<LinkBody>,
    /// The tip link (the last of [`Chain::link_names`]) and the tool on it.
    pub(crate) tip: usize,
    /// The rigid group the tip link moves with (its last moving joint + 1; 0: none): the
    /// bodies of that group and the hand are carried with the object.
    pub(crate) tip_group: usize,
    pub(crate) link_from_tool: IsometryMatrix3<f64>,
    /// Per link (in [`Chain::link_names`] order): where it is when the configuration does
    /// not matter.
    pub(crate) rigid: Vec<RigidLink>,
    pub(crate) self_pairs: Vec<(usize, usize)>,
}

impl ArmBodies {
    /// The bodies of `chain`'s links (from `shapes`, whose links are not on the chain are
    /// skipped) and of a hand whose shapes are given in the tool frame (`tool_from_shape`).
    /// `disabled` lists link pairs never checked against each other (SRDF
    /// `disable_collisions`); a name that is no link of the robot is an error.
    pub fn new(
        chain: &Chain,
        shapes: &[LinkShape],
        hand: &[(String, Isometry3<f64>, Shape)],
        disabled: &[(String, String)],
        self_pairs: SelfPairs,
    ) -> Result<Self, CollisionError> {
        let links = chain.link_names();
        let tip = links.len() - 1;
        let q = chain.mid_configuration();
        let frames = chain.link_frames(&q).map_err(CollisionError::Robot)?;
        let base_from_tool: IsometryMatrix3<f64> = chain.pose(&q).map_err(CollisionError::Robot)?;
        let link_from_tool = frames[tip].inverse() * base_from_tool;
        let group = |link: usize| chain.link_joint(link).map_or(0, |j| j + 1);
        let tool_from_base = base_from_tool.inverse();
        let rigid = (0..links.len())
            .map(|link| match group(link) {
                0 => RigidLink::Base(frames[link]),
                g if g == group(tip) => RigidLink::Tool(tool_from_base * frames[link]),
                _ => RigidLink::Moving,
            })
            .collect();
        let make = |link: usize, link_from_body: IsometryMatrix3<f64>, body: Body, hand: bool| {
            let (centre, radius) = body.bounding_sphere();
            LinkBody {
                link,
                reach: (link_from_body * centre).coords.norm() + radius,
                link_from_body,
                body,
                group: group(link),
                hand,
            }
        };
        let mut bodies = Vec::new();
        for s in shapes {
            let Some(link) = links.iter().position(|l| *l == s.link) else {
                continue;
            };
            let name = format!("link {}", s.link);
            bodies.push(make(
                link,
                nalgebra::convert(s.link_from_shape),
                Body::from_shape(name, &s.shape),
                false,
            ));
        }
        for (name, tool_from_shape, shape) in hand {
            let link_from_body =
                link_from_tool * nalgebra::convert::<_, IsometryMatrix3<f64>>(*tool_from_shape);
            bodies.push(make(
                tip,
                link_from_body,
                Body::from_shape(format!("hand {name}"), shape),
                true,
            ));
        }
        let mut arm = Self {
            chain: chain.clone(),
            sweep: chain.sweep_bound(),
            bodies,
            tip,
            tip_group: group(tip),
            link_from_tool,
            rigid,
            self_pairs: Vec::new(),
        };
        arm.self_pairs = arm.choose_self_pairs(disabled, self_pairs)?;
        Ok(arm)
    }

    /// The chain.
    pub fn chain(&self) -> &Chain {
        &self.chain
    }

    /// How many bodies the arm has (links and hand).
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Every body with the index of the link it rides on (in [`Chain::link_names`]) and its
    /// pose on that link, `link_from_body` (m); hand bodies ride on the tip link.
    pub fn bodies(&self) -> impl Iterator<Item = (usize, &IsometryMatrix3<f64>, &Body)> {
        self.bodies
            .iter()
            .map(|b| (b.link, &b.link_from_body, &b.body))
    }

    /// Whether body `i` (in [`ArmBodies::bodies`] order) moves with the arm (else it stands
    /// with the robot's base, before the first moving joint).
    pub fn moves(&self, i: usize) -> bool {
        self.bodies.get(i).is_some_and(|b| b.group > 0)
    }

    /// The names of the body pairs that self-collision checks visit.
    pub fn self_pair_names(&self) -> Vec<(String, String)> {
        self.self_pairs
            .iter()
            .map(|&(a, b)| {
                (
                    self.bodies[a].body.name().to_string(),
                    self.bodies[b].body.name().to_string(),
                )
            })
            .collect()
    }

    pub(crate) fn sweep(&self) -> &SweepBound {
        &self.sweep
    }

    fn choose_self_pairs(
        &self,
        disabled: &[(String, String)],
        mode: SelfPairs,
    ) -> Result<Vec<(usize, usize)>, CollisionError> {
        let links = self.chain.link_names();
        for (a, b) in disabled {
            for name in [a, b] {
                if !links.contains(name) {
                    return Err(CollisionError::UnknownLink {
                        link: name.clone(),
                        context: format!("disabled collision pair ({a}, {b})"),
                    });
                }
            }
        }
        if mode == SelfPairs::None {
            return Ok(Vec::new());
        }
        let is_disabled = |x: &LinkBody, y: &LinkBody| {
            let (nx, ny) = (&links[x.link], &links[y.link]);
            disabled
                .iter()
                .any(|(a, b)| (a == nx && b == ny) || (a == ny && b == nx))
        };
        let mut pairs = Vec::new();
        for i in 0..self.bodies.len() {
            for j in i + 1..self.bodies.len() {
                let (x, y) = (&self.bodies[i], &self.bodies[j]);
                let apart = x.group.abs_diff(y.group);
                let close = match mode {
                    SelfPairs::Sampled => apart <= 2,
                    _ => apart <= 1,
                };
                if close || is_disabled(x, y) {
                    continue;
                }
                pairs.push((i, j));
            }
        }
        if mode == SelfPairs::All || pairs.is_empty() {
            return Ok(pairs);
        }
        // Sampled: count, per pair, the configurations where the bodies touch and where their
        // bounding spheres meet.
        let n = self.chain.dof();
        let (lower, upper) = (self.chain.lower(), self.chain.upper());
        let mut touching = vec![0usize; pairs.len()];
        let mut near = vec![0usize; pairs.len()];
        let mut frames = vec![IsometryMatrix3::identity(); links.len()];
        let mid = self.chain.mid_configuration();
        self.chain
            .link_frames_into(&mid, &mut frames)
            .map_err(CollisionError::Robot)?;
        let identity = IsometryMatrix3::identity();
        let at_default: Vec<bool> = pairs
            .iter()
            .map(|&(a, b)| {
                self.place(a, &identity, &frames)
                    .distance(&self.place(b, &identity, &frames))
                    <= 0.0
            })
            .collect();
        let mut q = vec![0.0; n];
        for sample in 0..SELF_PAIR_SAMPLES {
            for (j, value) in q.iter_mut().enumerate() {
                let bits = splitmix64(derive_seed(SELF_PAIR_STREAM, sample as u64, j as u64));
                let unit = (bits >> 11) as f64 / (1u64 << 53) as f64;
                // A continuous joint (infinite limits) turns through one full revolution.
                let (low, high) = if lower[j].is_finite() && upper[j].is_finite() {
                    (lower[j], upper[j])
                } else {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                };
                *value = low + unit * (high - low);
            }
            self.chain
                .link_frames_into(&q, &mut frames)
                .map_err(CollisionError::Robot)?;
            for (k, &(a, b)) in pairs.iter().enumerate() {
                let pa = self.place(a, &identity, &frames);
                let pb = self.place(b, &identity, &frames);
                if pa.gap(&pb) <= 0.0 {
                    near[k] += 1;
                    if pa.distance(&pb) <= 0.0 {
                        touching[k] += 1;
                    }
                }
            }
        }
        Ok(pairs
            .into_iter()
            .enumerate()
            .filter(|&(k, _)| {
                near[k] > 0
                    && !at_default[k]
                    && (touching[k] as f64) < ALWAYS_FRACTION * SELF_PAIR_SAMPLES as f64
            })
            .map(|(_, p)| p)
            .collect())
    }

    /// Body `i` placed in the world, given `world_from_base` and the link frames.
    pub(crate) fn place<'a>(
        &'a self,
        i: usize,
        world_from_base: &IsometryMatrix3<f64>,
        frames: &[IsometryMatrix3<f64>],
    ) -> Placed<'a> {
        let b = &self.bodies[i];
        Placed::new(&b.body, world_from_base * frames[b.link] * b.link_from_body)
    }

    /// How far (m) any point of body `i` may move between configurations `qa` and `qb`.
    pub(crate) fn displacement(&self, i: usize, qa: &[f64], qb: &[f64]) -> f64 {
        let b = &self.bodies[i];
        self.sweep.displacement(b.link, b.reach, qa, qb)
    }
}
