//! A chain's flattened layout as plain data: every moving segment's placement, drive, body and
//! links, every link's place on the segments, and the tail to the tool ([`Chain::layout`]), from
//! which the dynamics kernels and the physics writer build their models; and the segment frames
//! ([`SegmentFrames`]) whose link-frame pass the dynamics kernels run.
//!
//! Frames and units as in [`Chain`]: each segment's aligned frame has the joint axis as `z`;
//! translations in m.

use super::{forward, Chain, LinkSlot, MotionKind, Segment};
use crate::robot::spec::RigidBody;
use nalgebra::{Matrix3, Vector3};

impl Chain {
    /// The flattened layout: per moving segment its placement at `q = 0` (rotation,
    /// translation, kind), its drive `(source, multiplier, offset)`, its body (aligned frame)
    /// and the names of the links it carries; every link's place on the segments; then the
    /// tail (last aligned frame to tool). The dynamics kernels copy it, and a physics model
    /// written from it has the chain's kinematics and mass properties exactly.
    pub fn layout(&self) -> ChainLayout {
        let segments = self
            .segments
            .iter()
            .enumerate()
            .map(|(i, segment)| {
                let drive = match &self.drives {
                    None => (i, 1.0, 0.0),
                    Some(d) => (d[i].source, d[i].multiplier, d[i].offset),
                };
                let links = self
                    .link_slots
                    .iter()
                    .zip(&self.link_names)
                    .filter(|(slot, _)| slot.segment == Some(i))
                    .map(|(_, name)| name.clone())
                    .collect();
                SegmentLayout {
                    rotation: segment.rotation,
                    translation: segment.translation,
                    kind: segment.kind,
                    drive,
                    body: self.segment_bodies[i],
                    links,
                }
            })
            .collect();
        let links = self
            .link_slots
            .iter()
            .zip(&self.link_names)
            .map(|(slot, name)| LinkPlacement {
                name: name.clone(),
                segment: slot.segment,
                rotation: slot.rotation,
                translation: slot.translation,
            })
            .collect();
        ChainLayout {
            segments,
            links,
            has_mimic: self.drives.is_some(),
            tail_rotation: self.tail_rotation,
            tail_translation: self.tail_translation,
        }
    }

    /// The segments with one identity slot each (see [`SegmentFrames`]).
    pub(in crate::robot) fn segment_frames(&self) -> SegmentFrames {
        let slots = (0..self.segments.len())
            .map(|i| LinkSlot {
                segment: Some(i),
                rotation: Matrix3::identity(),
                translation: Vector3::zeros(),
                identity: true,
            })
            .collect();
        SegmentFrames {
            segments: self.segments.clone(),
            slots,
        }
    }
}

/// The moving segments of a chain and one identity slot per segment: the link-frame pass
/// over them writes each segment's aligned frame (after its motion; its `z` is the joint axis),
/// with the AVX2 kernel when the processor has it.
#[derive(Debug, Clone, PartialEq)]
pub(in crate::robot) struct SegmentFrames {
    segments: Vec<Segment>,
    slots: Vec<LinkSlot>,
}

impl SegmentFrames {
    /// `out[i]` = segment `i`'s aligned frame in the base frame, segment `i` moved by
    /// `joint_value(i)` (rad or m). `out` has one entry per segment.
    #[inline(always)]
    pub(in crate::robot) fn frames_into(
        &self,
        joint_value: impl Fn(usize) -> f64,
        out: &mut [nalgebra::IsometryMatrix3<f64>],
    ) {
        forward::link_frames(&self.segments, &self.slots, joint_value, out);
    }
}

/// One moving segment as [`Chain::layout`] gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentLayout {
    /// The segment's aligned frame at `q = 0` (its `z` axis is the joint axis) in the previous
    /// segment's aligned frame, or in the chain's base frame for the first segment: rotation.
    pub rotation: Matrix3<f64>,
    /// ... and translation (m).
    pub translation: Vector3<f64>,
    /// How the joint moves the segment (about or along the aligned `z`).
    pub kind: MotionKind,
    /// What drives it, `(source, multiplier, offset)`: the joint value is
    /// `multiplier · q[source] + offset` (rad or m); `(i, 1, 0)` without mimic joints.
    pub drive: (usize, f64, f64),
    /// The mass properties of everything the segment carries, in its aligned frame after the
    /// joint motion; `None` when no link of it has inertial data.
    pub body: Option<RigidBody>,
    /// The links the segment carries, in chain order.
    pub links: Vec<String>,
}

/// Where one link of the chain sits ([`Chain::layout`]).
#[derive(Debug, Clone, PartialEq)]
pub struct LinkPlacement {
    /// The link's name.
    pub name: String,
    /// The segment it rides on (`None`: the base, before the first moving joint).
    pub segment: Option<usize>,
    /// The link frame in that segment's aligned frame (after its motion), or in the base
    /// frame: rotation ...
    pub rotation: Matrix3<f64>,
    /// ... and translation (m).
    pub translation: Vector3<f64>,
}

/// A chain's flattened layout ([`Chain::layout`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ChainLayout {
    /// The moving segments, base first.
    pub segments: Vec<SegmentLayout>,
    /// Every link, in [`Chain::link_names`] order.
    pub links: Vec<LinkPlacement>,
    /// Whether a segment follows another joint (a mimic joint).
    pub has_mimic: bool,
    /// The tool frame in the last segment's aligned frame (the base frame without moving
    /// joints): rotation ...
    pub tail_rotation: Matrix3<f64>,
    /// ... and translation (m).
    pub tail_translation: Vector3<f64>,
}
