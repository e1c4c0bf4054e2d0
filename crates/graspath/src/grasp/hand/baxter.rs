//! The Baxter electric parallel gripper, built in.

use super::{parallel_jaw_hand, Hand, LinkShape, Shape};
use nalgebra::Isometry3;

/// The built-in gripper's name in model files.
pub const BAXTER_GRIPPER_NAME: &str = "baxter_electric_gripper";

/// Distance from the gripper base (`{arm}_gripper_base`) to the tool frame (`{arm}_gripper`)
/// along z in the built-in Baxter chain (m).
pub(super) const BASE_TO_TOOL: f64 = 0.1327;
/// The opening's range (m): the 10–70 mm of the gripper description quoted in the model spec.
pub(super) const OPENING_RANGE: (f64, f64) = (0.01, 0.07);
/// Finger length along the approach axis (m); the finger tips end at the tool frame's
/// `z = 0` plane.
const FINGER_LENGTH: f64 = 0.09;
/// Finger width along x and thickness along y (m).
const FINGER_WIDTH: f64 = 0.02;
const FINGER_THICKNESS: f64 = 0.01;
/// Palm (gripper housing) size along x and y (m); it fills z from the gripper base up to the
/// finger roots.
const PALM_X: f64 = 0.06;
const PALM_Y: f64 = 0.11;

/// A box of the built-in sizes (positive constants, so always valid).
fn cuboid(size: [f64; 3]) -> Shape {
    Shape::cuboid(size).expect("built-in sizes are positive")
}

/// The Baxter electric parallel gripper (approximate dimensions of the standard narrow
/// fingers in a middle slot).
///
/// **Wrist frame = the tool frame `{arm}_gripper`** at the tip of the built-in Baxter chain
/// (`crate::robot::builtin::baxter`): `z` points along the approach (from the palm towards the
/// object), the fingers close along `y`, and `x = y × z`. The origin lies midway between the
/// finger tips.
///
/// Links (all boxes):
/// * `palm`: 60 × 110 mm in x × y, from the gripper base (`z = −0.1327`) to the finger roots
///   (`z = −0.09`);
/// * `l_finger` (on `+y`) and `r_finger` (on `−y`): 20 × 10 × 90 mm (x × y × z), spanning
///   `z ∈ [−0.09, 0]`; their inner faces lie at `y = ±w/2`.
///
/// One hand joint, `opening` `w` (m): the gap between the inner finger faces, in
/// `[0.01, 0.07]` (the 10–70 mm range of the gripper description quoted in the model spec),
/// with a kernel width σ = 1 mm. Each finger link frame sits at the centre of its inner face,
/// `(0, ±w/2, −0.045)`.
pub fn baxter_electric_gripper() -> Hand {
    let half_finger = FINGER_LENGTH / 2.0;
    let palm_depth = BASE_TO_TOOL - FINGER_LENGTH;
    let palm = vec![LinkShape {
        link_from_shape: Isometry3::translation(0.0, 0.0, -FINGER_LENGTH - palm_depth / 2.0),
        shape: cuboid([PALM_X, PALM_Y, palm_depth]),
    }];
    parallel_jaw_hand(
        BAXTER_GRIPPER_NAME,
        palm,
        -half_finger,
        [FINGER_WIDTH, FINGER_THICKNESS, 2.0 * half_finger],
        OPENING_RANGE,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::builtin::{baxter, baxter_spec, Arm};
    use nalgebra::Point3;

    #[test]
    fn inner_faces_are_the_opening_apart_and_the_tips_at_the_tool_frame() {
        let hand = baxter_electric_gripper();
        for w in [0.01, 0.04, 0.07] {
            let poses = hand.link_poses(&[w]);
            let l = hand
                .link_proximity(1, &poses[1], &Point3::new(0.0, 0.0, -0.02))
                .expect("shape");
            let r = hand
                .link_proximity(2, &poses[2], &Point3::new(0.0, 0.0, -0.02))
                .expect("shape");
            assert!((l.signed_distance - w / 2.0).abs() < 1e-12);
            assert!((r.signed_distance - w / 2.0).abs() < 1e-12);
            assert!(l.closest.y > 0.0 && r.closest.y < 0.0);
        }
        let poses = hand.link_poses(&[0.04]);
        let tip = hand
            .link_proximity(1, &poses[1], &Point3::new(0.0, 0.025, 0.01))
            .expect("shape");
        assert!((tip.signed_distance - 0.01).abs() < 1e-12);
    }

    #[test]
    fn the_palm_starts_at_the_chain_gripper_base() {
        // The built-in chain's last fixed joint is gripper_base -> gripper (endpoint).
        let spec = baxter_spec(Arm::Left);
        let endpoint = spec.joints.last().expect("joints").parent_from_joint;
        assert!((endpoint.translation.z - BASE_TO_TOOL).abs() < 1e-12);
        assert_eq!(baxter(Arm::Left).tip_link(), "left_gripper");
        let hand = baxter_electric_gripper();
        let palm = &hand.links[0].shapes[0];
        let Shape::Box(b) = palm.shape else {
            panic!("box")
        };
        let half = b.half_extents();
        assert!((palm.link_from_shape.translation.z - half.z + BASE_TO_TOOL).abs() < 1e-12);
    }
}
