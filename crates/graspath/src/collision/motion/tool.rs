//! The check before IK: the bodies whose pose follows from the tool's alone, at every sample
//! of the tool's commanded motion.

use super::*;

impl ArmInScene<'_> {
    /// Checks, at every sample of the tool's commanded motion, the bodies whose pose follows
    /// from the tool's alone — the hand, the links rigid with the tool, the carried object —
    /// against the scene, the standing object and the links rigid with the base, with the
    /// pairs and distances of [`ArmInScene::check`]. No IK is needed, so a grasp whose hand
    /// would hit something is refused before the arm is solved; the samples are the commanded
    /// poses (the arm's reach them to the IK tolerance), and what happens between samples is
    /// left to [`ArmInScene::check`] on the solved motion.
    pub fn check_tool_poses(&self, motion: &ToolMotion<'_>) -> Option<CollisionHit> {
        let arm = self.arm;
        let slots = Slots::new(*self, &motion.object);
        let mut frames = vec![IsometryMatrix3::identity(); arm.rigid.len()];
        let mut placed: Vec<Option<Placed<'_>>> = Vec::new();
        for (at, samples) in motion.object.stretches(motion.base_from_tool.len()) {
            let pairs: Vec<Pair> = slots
                .pairs(at)
                .into_iter()
                .filter(|p| slots.follows_tool(p.a) && slots.follows_tool(p.b))
                .collect();
            if pairs.is_empty() {
                continue;
            }
            // Only the slots these pairs name are placed.
            let mut used = vec![false; slots.object_slot() + 1];
            for p in &pairs {
                used[p.a] = true;
                used[p.b] = true;
            }
            for s in samples {
                let base_from_tool: IsometryMatrix3<f64> =
                    nalgebra::convert(motion.base_from_tool[s]);
                for (frame, rigid) in frames.iter_mut().zip(&arm.rigid) {
                    match rigid {
                        RigidLink::Base(base_from_link) => *frame = *base_from_link,
                        RigidLink::Tool(tool_from_link) => *frame = base_from_tool * tool_from_link,
                        RigidLink::Moving => {}
                    }
                }
                placed.clear();
                placed.extend(
                    used.iter()
                        .enumerate()
                        .map(|(i, &u)| u.then(|| slots.slot(i, &frames, at))),
                );
                for pair in &pairs {
                    let (Some(x), Some(y)) = (&placed[pair.a], &placed[pair.b]) else {
                        continue;
                    };
                    let k = measure(pair, x, y, Level::Sphere);
                    if pair.violated_by(k.value) {
                        return Some(hit(pair, x, y, k.value, s, false));
                    }
                }
            }
        }
        None
    }
}
