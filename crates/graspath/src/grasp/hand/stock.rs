//! Stock parallel grippers, built in and usable on any arm: the Robotiq 2F-85 and 2F-140, the
//! Franka Hand and Baxter's electric gripper.
//!
//! **Frames.** As for [`super::baxter_electric_gripper`], a hand's frame is its **tool centre
//! point** (TCP): `z` along the approach (from the palm towards the object), the fingers close
//! along `y`, `x = y × z`, the origin midway between the finger pads at full opening. The arm's
//! flange (the mounting face the gripper, or its coupling, is bolted to) lies at `z =
//! −`[`StockGripper::flange_to_tcp`].
//!
//! **Geometry** (collision boxes, and a cylinder for a coupling), measured from the mounting
//! face of the gripper along its approach axis, from the makers' published models:
//! * Robotiq 2F-85 and 2F-140: ROS-Industrial's `robotiq` description
//!   (`robotiq_arg2f_85_model_macro.xacro`, `robotiq_arg2f_140_model_macro.xacro`) and its
//!   collision meshes' extents: the base 75 × 85 mm, 90 mm tall; each finger (outer finger,
//!   inner finger and pad) one box at full opening, 27 × 31 × 104 mm from 44.8 mm up (2F-85)
//!   and 30 × 37 × 167 mm from 45 mm up (2F-140; its fingers splay when open, so the box
//!   encloses them); pad centres 130.3 mm and 177 mm from the mounting face; the stroke 85
//!   and 140 mm (the datasheets'). Robotiq's 11 mm coupling for the UR e-Series (PickNik's
//!   `ur_to_robotiq_adapter`, 75 mm across) sits between the flange and the gripper.
//! * Franka Hand: `franka_description` (`franka_hand.xacro`): flange to TCP 0.1034 m (the
//!   pads' centre); the housing 63 × 204 mm, 66 mm tall above the flange (its collision
//!   mesh's extent; the two ends that reach 26 mm below the flange plane beside the arm are
//!   left out); each finger 22 × 26.4 mm from 58.4 to 112.9 mm; 80 mm stroke. Bolted
//!   directly to the flange.
//! * Baxter: [`super::baxter_electric_gripper`] (its gripper base 0.1327 m behind the TCP).
//!
//! The fingers are modelled as two boxes sliding along `±y` (the Robotiq linkages also raise
//! the pads by 14–24 mm as they close; the task's checks use the hand open).

use super::baxter;
use super::{baxter_electric_gripper, parallel_jaw_hand, Hand, LinkShape, Shape};
use crate::spelling::spelled;
use crate::spelling::Spelled;
use nalgebra::Isometry3;

/// A stock gripper: its geometry and its tool centre point, from the makers' models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StockGripper {
    /// Baxter's electric parallel gripper (`baxter`).
    Baxter,
    /// Robotiq 2F-85 on its 11 mm coupling (`robotiq_2f_85`).
    Robotiq2F85,
    /// Robotiq 2F-140 on its 11 mm coupling (`robotiq_2f_140`).
    Robotiq2F140,
    /// The Franka Hand of the Panda and the FR3 (`franka_hand`).
    FrankaHand,
}

/// A parallel gripper's dimensions from its mounting face along the approach `z` (m).
struct ParallelDimensions {
    /// The body (housing) box, `x × y`, from the mounting face to this height.
    body: [f64; 2],
    body_height: f64,
    /// One finger box at full opening: width along `x`, thickness along `y`, and its bottom
    /// and top along `z`.
    finger: [f64; 4],
    /// The stroke: the largest gap between the pads.
    opening: f64,
    /// Mounting face to the pads' centre.
    tcp: f64,
    /// A coupling between the flange and the mounting face: its diameter and thickness.
    coupling: Option<[f64; 2]>,
}

/// Robotiq 2F-85 ([module documentation](self)).
const ROBOTIQ_2F_85: ParallelDimensions = ParallelDimensions {
    body: [0.075, 0.085],
    body_height: 0.090,
    finger: [0.027, 0.031, 0.0448, 0.1491],
    opening: 0.085,
    tcp: 0.1303,
    coupling: Some([0.075, 0.011]),
};

/// Robotiq 2F-140 ([module documentation](self)).
const ROBOTIQ_2F_140: ParallelDimensions = ParallelDimensions {
    body: [0.075, 0.085],
    body_height: 0.090,
    finger: [0.030, 0.037, 0.045, 0.212],
    opening: 0.140,
    tcp: 0.177,
    coupling: Some([0.075, 0.011]),
};

/// The Franka Hand ([module documentation](self)).
const FRANKA_HAND: ParallelDimensions = ParallelDimensions {
    body: [0.063, 0.204],
    body_height: 0.066,
    finger: [0.022, 0.0264, 0.0584, 0.1129],
    opening: 0.080,
    tcp: 0.1034,
    coupling: None,
};

spelled!(StockGripper {
    Baxter => "baxter",
    Robotiq2F85 => "robotiq_2f_85",
    Robotiq2F140 => "robotiq_2f_140",
    FrankaHand => "franka_hand",
});

impl StockGripper {
    fn dimensions(self) -> Option<&'static ParallelDimensions> {
        match self {
            Self::Baxter => None,
            Self::Robotiq2F85 => Some(&ROBOTIQ_2F_85),
            Self::Robotiq2F140 => Some(&ROBOTIQ_2F_140),
            Self::FrankaHand => Some(&FRANKA_HAND),
        }
    }

    /// The distance (m) from the arm's flange to the TCP along the flange's `z`, the coupling
    /// included: the tool offset `tip_from_tool = Tz(d)` of an arm whose chain ends at its
    /// flange.
    pub fn flange_to_tcp(self) -> f64 {
        match self.dimensions() {
            None => baxter::BASE_TO_TOOL,
            Some(d) => d.tcp + d.coupling.map_or(0.0, |[_, thickness]| thickness),
        }
    }

    /// The largest gap between the finger pads (m).
    pub fn opening(self) -> f64 {
        match self.dimensions() {
            None => baxter::OPENING_RANGE.1,
            Some(d) => d.opening,
        }
    }

    /// The hand, in its TCP frame, with one joint `opening` (the gap between the pads, m) and
    /// the finger links `l_finger` (`+y`) and `r_finger` (`−y`).
    pub fn hand(self) -> Hand {
        match self.dimensions() {
            None => baxter_electric_gripper(),
            Some(d) => parallel_hand(self.as_str(), d),
        }
    }
}

/// A box of built-in sizes (positive constants, so always valid).
fn cuboid(size: [f64; 3]) -> Shape {
    Shape::cuboid(size).expect("built-in sizes are positive")
}

/// The hand of `d` in its TCP frame: the body (and coupling) on the root link `palm`, two
/// finger boxes whose inner faces lie at `y = ±opening/2`.
fn parallel_hand(name: &str, d: &ParallelDimensions) -> Hand {
    // Heights from the mounting face become TCP-frame z by subtracting the TCP's height.
    let z = |height: f64| height - d.tcp;
    let [width, thickness, bottom, top] = d.finger;
    let mut palm = vec![LinkShape {
        link_from_shape: Isometry3::translation(0.0, 0.0, z(0.5 * d.body_height)),
        shape: cuboid([d.body[0], d.body[1], d.body_height]),
    }];
    if let Some([diameter, thickness]) = d.coupling {
        palm.push(LinkShape {
            link_from_shape: Isometry3::translation(0.0, 0.0, z(-0.5 * thickness)),
            shape: Shape::cylinder(diameter / 2.0, thickness).expect("built-in sizes are positive"),
        });
    }
    parallel_jaw_hand(
        name,
        palm,
        z(0.5 * (bottom + top)),
        [width, thickness, top - bottom],
        (0.0, d.opening),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Point3, Vector3};

    /// The lowest and highest `z` (TCP frame) any shape of the hand reaches at `opening`,
    /// by the shapes' support points.
    fn z_extent(hand: &Hand, opening: f64) -> (f64, f64) {
        let poses = hand.link_poses(&[opening]);
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        for (link, pose) in hand.links.iter().zip(&poses) {
            for s in &link.shapes {
                let placed = pose * s.link_from_shape;
                for dir in [Vector3::z(), -Vector3::z()] {
                    let local = placed.inverse_transform_vector(&dir);
                    let p = placed * s.shape.support(&local);
                    low = low.min(p.z);
                    high = high.max(p.z);
                }
            }
        }
        (low, high)
    }

    #[test]
    fn pads_are_the_opening_apart_around_the_tcp_and_the_flange_is_behind_it() {
        for gripper in StockGripper::ALL {
            let hand = gripper.hand();
            let open = gripper.opening();
            assert_eq!(hand.joints[0].upper, open, "{gripper:?}");
            let poses = hand.link_poses(&[open]);
            // Oracle: a point on the closing axis at the TCP is half the opening from each
            // finger's inner face, on its own side.
            for (k, side) in [(1, 1.0), (2, -1.0)] {
                let prox = hand
                    .link_proximity(k, &poses[k], &Point3::origin())
                    .expect("a finger shape");
                assert!(
                    (prox.signed_distance - open / 2.0).abs() < 1e-12,
                    "{gripper:?}"
                );
                assert!(prox.closest.y * side > 0.0);
            }
            // Nothing of the hand reaches behind the flange, and the fingertips reach
            // beyond the TCP (the pads straddle it).
            let (low, high) = z_extent(&hand, open);
            assert!(
                (low + gripper.flange_to_tcp()).abs() < 1e-12,
                "{gripper:?}: lowest {low}"
            );
            assert!(
                (0.0..0.05).contains(&high),
                "{gripper:?}: fingertips at {high}"
            );
        }
    }

    #[test]
    fn the_flange_to_tcp_distances_are_the_makers() {
        // Franka's published TCP (franka_description: 0.1034 m); Robotiq's pad centres
        // (130.3 and 177 mm) on the 11 mm coupling.
        let cases = [
            (StockGripper::FrankaHand, 0.1034),
            (StockGripper::Robotiq2F85, 0.1413),
            (StockGripper::Robotiq2F140, 0.188),
            (StockGripper::Baxter, 0.1327),
        ];
        for (gripper, d) in cases {
            assert!((gripper.flange_to_tcp() - d).abs() < 1e-12, "{gripper:?}");
            assert_eq!(StockGripper::from_name(gripper.as_str()), Some(gripper));
        }
        assert_eq!(StockGripper::from_name("robotiq"), None);
    }
}
