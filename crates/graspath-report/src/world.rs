//! The world of the 3D view, for tasks that describe one (a scene, an approach or retreat, or a
//! gripper): the scene's bodies (the table and every obstacle) in the world frame, each arm's
//! collision bodies on their links, and the link frames that move those bodies along a motion.
//!
//! Frames and units: scene bodies carry `world_from_body`; arm bodies carry `link_from_body`
//! and ride on the link frames `world_from_link = world_from_base · base_from_link` given per
//! sample. Poses are `[x, y, z, qx, qy, qz, qw]` (m), positions rounded to 0.1 mm, sizes to
//! 1 µm. Geometry is in the body frame:
//!
//! * `{"type": "box", "size": [x, y, z]}` centred; `cylinder` and `capsule` `{radius, length}`
//!   along `z`, centred (a capsule's `length` is its segment's, without the caps); `sphere`
//!   `{radius}`;
//! * `{"type": "mesh", "vertices": [[x, y, z], ...], "triangles": [[i, j, k], ...]}` (a convex
//!   mesh as its hull; a mesh of more than [`MAX_VIEW_TRIANGLES`] triangles as its bounding
//!   box, `{"type": "aabb", "min", "max"}`);
//! * `{"type": "compound", "parts": [{"pose", "geometry"}, ...]}` (a T-shape: bar and stem);
//! * `{"type": "half_space", "height"}`: everything below `z = height` (an infinite table);
//! * `{"type": "points", "radius", "points": [...], "total"}`: a cloud, each point the centre
//!   of a sphere; at most [`MAX_VIEW_POINTS`] are listed (every k-th), `total` counts them all.

use graspath::collision::{ArmBodies, Body, BodyKind};
use graspath::geometry::shape::{Shape, Stem};
use graspath::robot::Chain;
use graspath::task::{ArmSetup, Task};
use nalgebra::{Isometry3, IsometryMatrix3, Point3};
use serde_json::{json, Value};

/// The most points of a cloud obstacle listed in the view (every k-th point beyond).
pub const MAX_VIEW_POINTS: usize = 20_000;

/// The most triangles of a mesh drawn as such (larger meshes are drawn as their bounding box).
pub const MAX_VIEW_TRIANGLES: usize = 100_000;

pub(crate) fn round(v: f64) -> f64 {
    if v.is_finite() {
        (v * 1e4).round() / 1e4
    } else {
        0.0
    }
}

pub(crate) fn round6(v: f64) -> f64 {
    if v.is_finite() {
        (v * 1e6).round() / 1e6
    } else {
        0.0
    }
}

pub(crate) fn point(p: &Point3<f64>) -> Value {
    json!([round(p.x), round(p.y), round(p.z)])
}

/// A pose as `[x, y, z, qx, qy, qz, qw]`.
pub(crate) fn pose(p: &Isometry3<f64>) -> Value {
    let t = &p.translation.vector;
    let q = p.rotation.coords;
    json!([
        round(t.x),
        round(t.y),
        round(t.z),
        round6(q.x),
        round6(q.y),
        round6(q.z),
        round6(q.w)
    ])
}

/// A rotation-matrix pose as `[x, y, z, qx, qy, qz, qw]`.
pub(crate) fn matrix_pose(p: &IsometryMatrix3<f64>) -> Value {
    pose(&nalgebra::convert(*p))
}

fn sizes(values: &[f64]) -> Value {
    Value::Array(values.iter().map(|&v| json!(round6(v))).collect())
}

fn mesh_json(vertices: &[Point3<f64>], triangles: &[[u32; 3]]) -> Value {
    json!({
        "type": "mesh",
        "vertices": vertices.iter().map(point).collect::<Vec<_>>(),
        "triangles": triangles,
    })
}

/// The geometry of a shape, body frame (see the module documentation).
fn shape_geometry(shape: &Shape) -> Value {
    match shape {
        Shape::Box(b) => json!({"type": "box", "size": sizes(&b.size())}),
        Shape::Cylinder(c) => json!({
            "type": "cylinder",
            "radius": round6(c.radius()),
            "length": round6(c.length()),
        }),
        Shape::Sphere(s) => json!({"type": "sphere", "radius": round6(s.radius())}),
        Shape::Capsule(c) => json!({
            "type": "capsule",
            "radius": round6(c.radius()),
            "length": round6(c.length()),
        }),
        Shape::TShape(t) => {
            let stem = match t.stem() {
                Stem::Cylinder(c) => json!({
                    "type": "cylinder",
                    "radius": round6(c.radius()),
                    "length": round6(c.length()),
                }),
                Stem::Box(b) => json!({"type": "box", "size": sizes(&b.size())}),
            };
            json!({
                "type": "compound",
                "parts": [
                    {"pose": pose(&Isometry3::identity()), "geometry": {"type": "box", "size": sizes(&t.bar().size())}},
                    {"pose": pose(&Isometry3::translation(0.0, 0.0, t.stem_centre())), "geometry": stem},
                ],
            })
        }
        Shape::ConvexMesh(m) => {
            let corners: Vec<[Point3<f64>; 3]> = m.hull_triangles().collect();
            if corners.len() > MAX_VIEW_TRIANGLES {
                return aabb_geometry(shape);
            }
            let vertices: Vec<Point3<f64>> = corners.iter().flatten().copied().collect();
            let triangles: Vec<[u32; 3]> = (0..corners.len() as u32)
                .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
                .collect();
            mesh_json(&vertices, &triangles)
        }
        Shape::TriangleMesh(m) => {
            if m.triangles().len() > MAX_VIEW_TRIANGLES {
                return aabb_geometry(shape);
            }
            mesh_json(m.vertices(), m.triangles())
        }
    }
}

fn aabb_geometry(shape: &Shape) -> Value {
    let aabb = shape.aabb();
    json!({"type": "aabb", "min": point(&aabb.min), "max": point(&aabb.max)})
}

/// The geometry of a body, body frame (see the module documentation).
pub(crate) fn body_geometry(body: &Body) -> Value {
    match body.kind() {
        BodyKind::Solid(shape) | BodyKind::Surface(shape) => shape_geometry(shape),
        BodyKind::HalfSpace { height } => json!({"type": "half_space", "height": round6(*height)}),
        BodyKind::Points { points, radius } => {
            let stride = points.len().div_ceil(MAX_VIEW_POINTS).max(1);
            json!({
                "type": "points",
                "radius": round6(*radius),
                "points": points.iter().step_by(stride).map(point).collect::<Vec<_>>(),
                "total": points.len(),
            })
        }
    }
}

/// Whether the task describes its world (a scene, an approach or retreat, or a gripper): only
/// then does the view carry the world's data, so the report of a task that says nothing about
/// its world is the same as before scenes existed.
pub(crate) fn has_world(task: &Task) -> bool {
    task.collisions().is_some()
        || task.approach().is_some()
        || task.retreat().is_some()
        || task.gripper().is_some()
}

/// The scene's bodies (the table first, then the obstacles), world frame.
pub(crate) fn scene_bodies(task: &Task) -> Vec<Value> {
    let Some(collisions) = task.collisions() else {
        return Vec::new();
    };
    collisions
        .scene
        .bodies()
        .iter()
        .map(|(body, world_from_body)| {
            json!({
                "name": body.name(),
                "pose": pose(world_from_body),
                "geometry": body_geometry(body),
            })
        })
        .collect()
}

/// The links of a chain that carry bodies, in [`Chain::link_names`] order.
pub(crate) fn body_links(bodies: &ArmBodies) -> Vec<usize> {
    let mut links: Vec<usize> = bodies.bodies().map(|(link, _, _)| link).collect();
    links.sort_unstable();
    links.dedup();
    links
}

/// An arm's bodies: `{"links": [names], "bodies": [{name, link, pose, moves, geometry}]}`,
/// where `link` indexes `links` and `pose` is `link_from_body`.
pub(crate) fn arm_bodies_json(chain: &Chain, bodies: &ArmBodies) -> Value {
    let links = body_links(bodies);
    let names = chain.link_names();
    let list: Vec<Value> = bodies
        .bodies()
        .enumerate()
        .map(|(i, (link, link_from_body, body))| {
            json!({
                "name": body.name(),
                "link": links.iter().position(|&l| l == link),
                "pose": matrix_pose(link_from_body),
                "moves": bodies.moves(i),
                "geometry": body_geometry(body),
            })
        })
        .collect();
    json!({
        "links": links.iter().map(|&l| names[l].as_str()).collect::<Vec<_>>(),
        "bodies": list,
    })
}

/// The frames `world_from_link` of the body-carrying `links` at configuration `q`, or `None`
/// when the chain refuses `q`.
pub(crate) fn link_frames(setup: &ArmSetup, links: &[usize], q: &[f64]) -> Option<Vec<Value>> {
    let frames = setup.chain.link_frames(q).ok()?;
    let world_from_base: IsometryMatrix3<f64> = nalgebra::convert(setup.world_from_base);
    Some(
        links
            .iter()
            .map(|&l| matrix_pose(&(world_from_base * frames[l])))
            .collect(),
    )
}

/// The joint origins (world) at configuration `q`, or `None` when the chain refuses `q`.
pub(crate) fn joint_origins(setup: &ArmSetup, q: &[f64]) -> Option<Value> {
    let origins = setup.chain.joint_origins(q).ok()?;
    Some(Value::Array(
        origins
            .iter()
            .map(|p| point(&(setup.world_from_base * p)))
            .collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_large_cloud_lists_every_kth_point_and_counts_them_all() {
        let n = 2 * MAX_VIEW_POINTS + 1;
        let points: Vec<Point3<f64>> = (0..n).map(|i| Point3::new(i as f64, 0.0, 0.0)).collect();
        let body = Body::from_points("obstacle scan", &points, 0.01, "scan").unwrap();
        let g = body_geometry(&body);
        assert_eq!(g["total"], n);
        let listed = g["points"].as_array().unwrap();
        // Stride ⌈n / max⌉ = 3: points 0, 3, 6, ...
        assert_eq!(listed.len(), n.div_ceil(3));
        assert!(listed.len() <= MAX_VIEW_POINTS);
        assert_eq!(listed[1][0], 3.0);
    }

    #[test]
    fn a_t_shape_is_its_bar_and_its_stem_above_it() {
        let t = Shape::TShape(
            graspath::geometry::shape::TShape::with_round_stem([0.2, 0.04, 0.02], 0.01, 0.1)
                .unwrap(),
        );
        let g = shape_geometry(&t);
        assert_eq!(g["type"], "compound");
        // The stem's centre: half the bar's height plus half the stem's length.
        let z = g["parts"][1]["pose"][2].as_f64().unwrap();
        assert!((z - (0.01 + 0.05)).abs() < 1e-12, "{z}");
        assert_eq!(g["parts"][1]["geometry"]["length"], 0.1);
    }
}
