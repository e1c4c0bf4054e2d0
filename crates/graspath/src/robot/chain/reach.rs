//! Proofs that a tip pose is out of reach, from the chain's geometry alone.
//!
//! The base fixes where the first joints' origins can be; the tip pose fixes where the last
//! joints' origins are. If some such pair of points is farther apart than the links between
//! them can span (the sum of their lengths and prismatic travels, by the triangle inequality),
//! no configuration puts the tip at the pose, inside the joint limits or not. The search then
//! need not run.
//!
//! The points, in chain order (`bᵢ`: joint `i`'s origin, `aᵢ`: the same after its own motion,
//! equal to `bᵢ` for a revolute joint):
//! * from the base: `b₀`, fixed; `b₁`, on a circle about joint 0's axis when joint 0 is
//!   revolute (its distance to `b₀` along the axis and from it are constant);
//! * from the tip pose: the tip; `aₙ₋₁`, the last joint's frame, at a constant offset from the
//!   tip; and when the last joint is revolute, `aₙ₋₂`, on a circle about its axis, whose
//!   centre is at a constant offset from the tip. On most arms (a wrist whose last two joint
//!   origins lie on the last axis) that circle is a point: the wrist centre.
//!
//! Every pair is tried, and the one that misses by most is reported. The reach sphere about
//! the first joint (the tip against `b₀`) is one of the pairs.

use super::{Chain, MotionKind};
use nalgebra::{Matrix3, Vector3};
use std::fmt;

/// A tip pose no configuration reaches: the pose puts `to` at `distance` from `from`, more
/// than the links between them can span.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct OutOfReach {
    from: String,
    to: String,
    /// Distance (m) the pose puts between the two points; to a circle, its nearest point.
    pub distance: f64,
    /// Largest distance (m) the links between the two points can span.
    pub span: f64,
}

impl fmt::Display for OutOfReach {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "out of reach: the target puts {} {:.4} m from {}; the links between them span at most {:.4} m",
            self.to, self.distance, self.from, self.span
        )
    }
}

/// A circle smaller than this (m) is named in a proof as the point it is, up to rounding.
const NAMED_AS_POINT: f64 = 1e-9;

/// Where a point the base fixes can be: a point (`radius` 0) or a circle, base frame (m).
pub(super) struct BaseAnchor {
    pub(super) centre: Vector3<f64>,
    /// The circle's unit normal (any unit vector for a point).
    normal: Vector3<f64>,
    pub(super) radius: f64,
    /// Index of the point in chain order (see [`Chain::span`]).
    pub(super) index: usize,
}

impl BaseAnchor {
    /// Distance (m) from `point` to the anchor's nearest point.
    pub(super) fn distance(&self, point: &Vector3<f64>) -> f64 {
        let w = point - self.centre;
        let along = w.dot(&self.normal);
        let across = (w - along * self.normal).norm();
        (across - self.radius).hypot(along)
    }
}

/// A point the tip pose fixes, at `offset` in the tip frame (m); `slack` (m) is how far the
/// chain point may be from it (the radius of its circle, 0 for a fixed point).
pub(super) struct TipAnchor {
    pub(super) offset: Vector3<f64>,
    pub(super) slack: f64,
    /// Index of the point in chain order (see [`Chain::span`]).
    pub(super) index: usize,
}

impl Chain {
    /// Proves that no configuration puts the tip at (`position`, `rotation`) (base frame, m),
    /// or returns `None`. A pose within `position_tolerance` (m) and `rotation_tolerance`
    /// (rad) of a reachable one is never called out of reach.
    pub(crate) fn out_of_reach(
        &self,
        position: &Vector3<f64>,
        rotation: &Matrix3<f64>,
        position_tolerance: f64,
        rotation_tolerance: f64,
    ) -> Option<OutOfReach> {
        let mut worst: Option<(f64, OutOfReach)> = None;
        for base in self.base_anchors() {
            for tip in self.tip_anchors() {
                if base.index >= tip.index {
                    continue;
                }
                let point = position + rotation * tip.offset;
                let distance = base.distance(&point);
                let span = self.span(base.index, tip.index) + tip.slack;
                // A pose off by the tolerances moves the point by at most this much; the last
                // term covers the rounding of the sums above.
                let margin = position_tolerance
                    + rotation_tolerance * tip.offset.norm()
                    + 1e-12 * (1.0 + span + distance);
                let excess = distance - span - margin;
                if excess > 0.0 && worst.as_ref().is_none_or(|(e, _)| excess > *e) {
                    let proof = OutOfReach {
                        from: self.base_label(&base),
                        to: self.tip_label(&tip),
                        distance,
                        span,
                    };
                    worst = Some((excess, proof));
                }
            }
        }
        worst.map(|(_, proof)| proof)
    }

    /// How a segment is named in a proof: its joint, or for a mimic joint its child link.
    fn segment_label(&self, i: usize) -> String {
        match &self.drives {
            None => format!("joint '{}'", self.joint_names[i]),
            Some(_) => {
                let child = self
                    .link_slots
                    .iter()
                    .position(|slot| slot.segment == Some(i))
                    .map_or("?", |l| self.link_names[l].as_str());
                format!("the joint before link '{child}'")
            }
        }
    }

    /// How a proof names a point the base fixes.
    fn base_label(&self, anchor: &BaseAnchor) -> String {
        match anchor.index {
            0 => format!("{}'s origin", self.segment_label(0)),
            _ if anchor.radius <= NAMED_AS_POINT => format!("{}'s origin", self.segment_label(1)),
            _ => format!(
                "the circle on which {}'s origin turns about {}'s axis",
                self.segment_label(1),
                self.segment_label(0)
            ),
        }
    }

    /// How a proof names a point the tip pose fixes.
    fn tip_label(&self, anchor: &TipAnchor) -> String {
        let n = self.segments.len();
        if anchor.index == 2 * n {
            return "the tip".into();
        }
        let i = (anchor.index - 1) / 2;
        if anchor.slack <= NAMED_AS_POINT {
            format!("{}'s origin", self.segment_label(i))
        } else {
            format!(
                "the centre of the circle on which {}'s origin turns about {}'s axis",
                self.segment_label(i),
                self.segment_label(i + 1)
            )
        }
    }

    /// `b₀`, and `b₁` on its circle when joint 0 is revolute.
    pub(super) fn base_anchors(&self) -> Vec<BaseAnchor> {
        let Some(first) = self.segments.first() else {
            return Vec::new();
        };
        let mut anchors = vec![BaseAnchor {
            centre: first.translation,
            normal: Vector3::z(),
            radius: 0.0,
            index: 0,
        }];
        if let (MotionKind::Revolute, Some(second)) = (first.kind, self.segments.get(1)) {
            let axis = first.rotation.column(2).into_owned();
            let t = second.translation;
            anchors.push(BaseAnchor {
                centre: first.translation + t.z * axis,
                normal: axis,
                radius: t.x.hypot(t.y),
                index: 2,
            });
        }
        anchors
    }

    /// The tip, `aₙ₋₁`, and the centre of `aₙ₋₂`'s circle when the last joint is revolute.
    pub(super) fn tip_anchors(&self) -> Vec<TipAnchor> {
        let n = self.segments.len();
        let tip_index = 2 * n;
        let mut anchors = vec![TipAnchor {
            offset: Vector3::zeros(),
            slack: 0.0,
            index: tip_index,
        }];
        let Some(last) = self.segments.last() else {
            return anchors;
        };
        // The last joint's frame, in the tip frame.
        let tip_from_last = self.tail_rotation.transpose();
        let last_offset = -(tip_from_last * self.tail_translation);
        anchors.push(TipAnchor {
            offset: last_offset,
            slack: 0.0,
            index: tip_index - 1,
        });
        if last.kind == MotionKind::Revolute && n >= 2 {
            // From the previous frame to the last joint's origin, in the last joint's frame:
            // turning about z keeps its z part and the length of the rest.
            let v = last.rotation.transpose() * last.translation;
            anchors.push(TipAnchor {
                offset: last_offset - tip_from_last * Vector3::new(0.0, 0.0, v.z),
                slack: v.x.hypot(v.y),
                index: tip_index - 3,
            });
        }
        anchors
    }

    /// Largest distance (m) between chain points `from < to`, indexed in chain order: `bᵢ` is
    /// `2i`, `aᵢ` is `2i + 1`, the tip is `2n`. From `bᵢ` to `aᵢ` the joint's travel (0 for a
    /// revolute joint, `+∞` unbounded); from `aᵢ` to `bᵢ₊₁` the link's length; from `aₙ₋₁`
    /// to the tip the tool offset's.
    fn span(&self, from: usize, to: usize) -> f64 {
        (from..to)
            .map(|step| {
                let i = step / 2;
                if step % 2 == 0 {
                    self.travel(i)
                } else if let Some(next) = self.segments.get(i + 1) {
                    next.translation.norm()
                } else {
                    self.tail_translation.norm()
                }
            })
            .sum()
    }
}
