//! How the report's 3D view is staged on load: the box it is fitted to (the robot and the task),
//! the camera that sees all of it, the robot's torso and base drawn under the arms, and a table
//! under the object when the task's scene gives none.
//!
//! Frames and units: world frame, metres. The camera looks at [`Stage::target`] from
//! [`Stage::distance`] along the view's opening direction (azimuth [`VIEW_AZIMUTH`], elevation
//! [`VIEW_ELEVATION`], rad, `z` up), with the vertical field of view [`VIEW_FOV_DEG`] on a
//! canvas of aspect [`VIEW_ASPECT`].

use graspath::select::Selection;
use graspath::task::Task;
use nalgebra::{Isometry3, Point3, Vector3};
use serde_json::{json, Value};

/// The 3D view's vertical field of view (degrees).
pub const VIEW_FOV_DEG: f64 = 40.0;
/// The 3D view's canvas width / height.
pub const VIEW_ASPECT: f64 = 760.0 / 520.0;
/// The camera's initial azimuth about world `z`, from `+x` (rad).
pub const VIEW_AZIMUTH: f64 = 0.75;
/// The camera's initial elevation above the horizontal (rad).
pub const VIEW_ELEVATION: f64 = 0.5;

/// The part of the view's half-size the box's farthest-out corner reaches on load.
pub const VIEW_FILL: f64 = 0.9;

/// The view's staging: bounds, camera, torso and table (world frame, m).
#[derive(Debug, Clone, PartialEq)]
pub struct Stage {
    /// The smallest corner of the box holding the robot's arms (their bases, their rest
    /// configuration and the motion shown on load) and the object along its whole path.
    pub min: Point3<f64>,
    /// The largest corner of that box.
    pub max: Point3<f64>,
    /// The point the camera looks at: the box's centre.
    pub target: Point3<f64>,
    /// The camera's distance from the target: the nearest at which every corner of the box is
    /// within [`VIEW_FILL`] of the view's half-width and half-height (and 5 cm before the
    /// camera).
    pub distance: f64,
    /// The arms' base origins (`world_from_base` of each arm).
    pub bases: Vec<Point3<f64>>,
    /// The torso: a vertical column under the bases' centre, from `floor` up to the highest base.
    pub torso: Torso,
    /// A table under the object's start when the task's scene has none: top height `z` (m),
    /// centre `[x, y]` and size `[x, y]` of its footprint; `None` when the scene has a table.
    pub table: Option<([f64; 2], [f64; 2], f64)>,
}

/// The robot's torso as drawn: a vertical cylinder (world frame, m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Torso {
    /// The column's axis position `[x, y]`.
    pub centre: [f64; 2],
    /// Its radius.
    pub radius: f64,
    /// The bottom's height `z`: the table top (the scene's, or the one drawn under the object).
    pub bottom: f64,
    /// The top's height `z`: the highest arm base.
    pub top: f64,
}

/// The points the view is fitted to: every arm's base origin and joint origins at rest and along
/// the motion shown on load (the best pair's, else each arm's selected candidate's), and the
/// object's bounding box (or origin, without a shape) at every sample of its path.
fn fitted_points(task: &Task, selection: &Selection) -> Vec<Point3<f64>> {
    let mut points = Vec::new();
    let shown: Vec<Option<usize>> = match selection.pairs.first() {
        Some(pair) => [&pair.first, &pair.second]
            .iter()
            .map(|c| {
                // Every arm scores every candidate, in candidate order.
                selection.arms[0]
                    .scores
                    .iter()
                    .position(|s| std::sync::Arc::ptr_eq(&s.candidate, c))
            })
            .collect(),
        None => selection
            .arms
            .iter()
            .map(graspath::select::ArmResult::best)
            .collect(),
    };
    for (k, setup) in task.arms().iter().enumerate() {
        let world_from_base = setup.world_from_base;
        points.push(Point3::from(world_from_base.translation.vector));
        let chain = &setup.chain;
        let mut configurations = vec![chain.mid_configuration()];
        if let (Some(arm), Some(Some(i))) = (selection.arms.get(k), shown.get(k)) {
            configurations.extend(arm.scores[*i].joint_trajectory.iter().cloned());
        }
        for q in &configurations {
            if let Ok(origins) = chain.joint_origins(q) {
                points.extend(origins.iter().map(|p| world_from_base * p));
            }
        }
    }
    for world_from_object in task.path().poses() {
        match task.shape() {
            Some(shape) => {
                let b = shape.aabb_at(world_from_object);
                points.push(b.min);
                points.push(b.max);
            }
            None => points.push(Point3::from(world_from_object.translation.vector)),
        }
    }
    points
}

/// The camera's unit axes (forward, right, up) for the opening direction, world frame.
fn camera_axes() -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let (a, e) = (VIEW_AZIMUTH, VIEW_ELEVATION);
    // The camera sits at `target + d · toward`, looking back at the target, `z` up.
    let toward = Vector3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin());
    let forward = -toward;
    let right = forward.cross(&Vector3::z()).normalize();
    let up = right.cross(&forward);
    (forward, right, up)
}

/// The nearest distance from `target` at which the box's corners fit the view (see
/// [`Stage::distance`]): a corner at offset `v` from the target is at depth `v·f + d`, and
/// needs `|v·r| ≤ fill · tan(h/2) · depth` and `|v·u| ≤ fill · tan(v/2) · depth`.
fn fitted_distance(min: &Point3<f64>, max: &Point3<f64>, target: &Point3<f64>) -> f64 {
    let (forward, right, up) = camera_axes();
    let tan_v = (VIEW_FOV_DEG.to_radians() / 2.0).tan();
    let tan_h = tan_v * VIEW_ASPECT;
    let mut distance: f64 = 0.1;
    for m in 0..8 {
        let corner = Point3::new(
            if m & 1 == 0 { min.x } else { max.x },
            if m & 2 == 0 { min.y } else { max.y },
            if m & 4 == 0 { min.z } else { max.z },
        );
        let v = corner - target;
        let ahead = v.dot(&forward);
        distance = distance
            .max(v.dot(&right).abs() / (VIEW_FILL * tan_h) - ahead)
            .max(v.dot(&up).abs() / (VIEW_FILL * tan_v) - ahead)
            .max(0.05 - ahead);
    }
    distance
}

fn bounds(points: &[Point3<f64>]) -> (Point3<f64>, Point3<f64>) {
    let mut min = Point3::from(Vector3::repeat(f64::INFINITY));
    let mut max = Point3::from(Vector3::repeat(f64::NEG_INFINITY));
    for p in points
        .iter()
        .filter(|p| p.coords.iter().all(|v| v.is_finite()))
    {
        min = min.inf(p);
        max = max.sup(p);
    }
    if !min.x.is_finite() {
        return (Point3::origin(), Point3::origin());
    }
    (min, max)
}

/// The view's staging for a task and its selection.
pub fn stage(task: &Task, selection: &Selection) -> Stage {
    let (min, max) = bounds(&fitted_points(task, selection));
    let target = nalgebra::center(&min, &max);
    let distance = fitted_distance(&min, &max, &target);
    let bases: Vec<Point3<f64>> = task
        .arms()
        .iter()
        .map(|a| Point3::from(a.world_from_base.translation.vector))
        .collect();
    let scene_table = task
        .collisions()
        .as_ref()
        .and_then(|c| c.scene.table())
        .map(|t| t.height);
    let start = task
        .path()
        .poses()
        .next()
        .copied()
        .unwrap_or_else(Isometry3::identity);
    let object_bottom = match task.shape() {
        Some(shape) => shape.aabb_at(&start).min.z,
        None => start.translation.vector.z,
    };
    let table = scene_table.is_none().then(|| {
        // Under the object's start, as wide as the object's path plus 0.15 m each side.
        let pad = 0.15;
        let (lo, hi) = path_xy_bounds(task);
        (
            [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0],
            [hi[0] - lo[0] + 2.0 * pad, hi[1] - lo[1] + 2.0 * pad],
            object_bottom,
        )
    });
    let floor = scene_table.unwrap_or(object_bottom);
    let n = bases.len().max(1) as f64;
    let centre = bases.iter().fold(Vector3::zeros(), |s, b| s + b.coords) / n;
    let spread = bases
        .iter()
        .map(|b| (b.coords - centre).xy().norm())
        .fold(0.0, f64::max);
    let top = bases.iter().map(|b| b.z).fold(f64::NEG_INFINITY, f64::max);
    let top = if top.is_finite() { top } else { floor };
    let torso = Torso {
        centre: [centre.x, centre.y],
        radius: (0.6 * spread).clamp(0.08, 0.2),
        bottom: floor.min(top),
        top,
    };
    Stage {
        min,
        max,
        target,
        distance,
        bases,
        torso,
        table,
    }
}

fn path_xy_bounds(task: &Task) -> ([f64; 2], [f64; 2]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for world_from_object in task.path().poses() {
        let b = match task.shape() {
            Some(shape) => shape.aabb_at(world_from_object),
            None => {
                let p = Point3::from(world_from_object.translation.vector);
                graspath::geometry::shape::Aabb { min: p, max: p }
            }
        };
        for k in 0..2 {
            lo[k] = lo[k].min(b.min[k]);
            hi[k] = hi[k].max(b.max[k]);
        }
    }
    if !lo[0].is_finite() {
        return ([0.0; 2], [0.0; 2]);
    }
    (lo, hi)
}

fn r(v: f64) -> f64 {
    crate::world::round(v)
}

fn p3(p: &Point3<f64>) -> Value {
    json!([r(p.x), r(p.y), r(p.z)])
}

/// The staging as the page reads it (`fit` in `report.html`; positions rounded to 0.1 mm).
pub(crate) fn stage_json(stage: &Stage) -> Value {
    json!({
        "min": p3(&stage.min),
        "max": p3(&stage.max),
        "target": p3(&stage.target),
        "distance": r(stage.distance),
        "azimuth": VIEW_AZIMUTH,
        "elevation": VIEW_ELEVATION,
        "fov_deg": VIEW_FOV_DEG,
        "bases": stage.bases.iter().map(p3).collect::<Vec<_>>(),
        "torso": {
            "centre": [r(stage.torso.centre[0]), r(stage.torso.centre[1])],
            "radius": r(stage.torso.radius),
            "bottom": r(stage.torso.bottom),
            "top": r(stage.torso.top),
        },
        "table": stage.table.map(|(centre, size, height)| json!({
            "centre": [r(centre[0]), r(centre[1])],
            "size": [r(size[0]), r(size[1])],
            "height": r(height),
        })),
    })
}
