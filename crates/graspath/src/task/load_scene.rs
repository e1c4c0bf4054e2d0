//! The world sections of a task file — `scene`, `collision`, `approach`, `retreat`, `gripper` —
//! turned into builder settings: obstacles read (meshes, clouds), the robot's link geometry
//! read (URDF `<collision>` primitives and meshes, or the built-in model's primitives).

use super::builder::TaskBuilder;
use super::error::TaskError;
use super::file::pose;
use super::file::{GripperFile, StrokeFile, TaskFile};
use super::scene::{Gripper, GripperBodies, SceneSettings, Stroke};
use crate::cloud::{load_collision_mesh, read_cloud, read_mesh};
use crate::collision::{Body, CollisionOptions, LinkShape, Scene, SelfPairs};
use crate::geometry::shape::{Shape, TriMesh};
use crate::grasp::hand::{hand_from_robot, StockGripper};
use crate::robot::{CollisionGeometry, RobotError, RobotModel, RobotSource, Srdf};
use crate::spelling::Spelled;
use nalgebra::{Isometry3, Unit, Vector3};
use std::path::Path;

/// Default samples of an approach or retreat.
pub const STROKE_SAMPLES: usize = 5;

/// Adds the file's world sections to `builder`.
pub(crate) fn add_world(
    mut builder: TaskBuilder,
    file: &TaskFile,
    source: &str,
    base_dir: &Path,
    scene: Option<Scene>,
    model: &RobotModel,
) -> Result<TaskBuilder, TaskError> {
    if let Some(stroke) = &file.approach {
        builder = builder.approach(stroke_from(stroke, source, "approach")?);
    }
    if let Some(stroke) = &file.retreat {
        builder = builder.retreat(stroke_from(stroke, source, "retreat")?);
    }
    if let Some(gripper) = &file.gripper {
        builder = builder.gripper(gripper_from(gripper, source, base_dir, model)?);
    }
    let Some(scene) = scene else {
        return Ok(builder);
    };
    let err = |field: &str, message: String| TaskError::new(source, field, message);
    let c = file.collision.clone().unwrap_or_default();
    let defaults = CollisionOptions::default();
    let options = CollisionOptions {
        margin: c.margin.unwrap_or(defaults.margin),
        self_collision: c.self_collision.unwrap_or(defaults.self_collision),
        between_arms: c.between_arms.unwrap_or(defaults.between_arms),
        touch_tolerance: c.touch_tolerance.unwrap_or(defaults.touch_tolerance),
        resolution: c.resolution.unwrap_or(defaults.resolution),
    };
    let self_pairs = match c.self_pairs.as_deref() {
        None | Some("sampled") => SelfPairs::Sampled,
        Some("all") => SelfPairs::All,
        Some(other) => {
            return Err(err(
                "collision.self_pairs",
                format!("'{other}' is not one of sampled, all"),
            ))
        }
    };
    let robot_shapes =
        robot_link_shapes(model).map_err(|e| TaskError::caused_by(source, "robot", e))?;
    let all_links = model.link_names();
    for (k, [a, b]) in c.disable.iter().enumerate() {
        for link in [a, b] {
            if !all_links.contains(link) {
                return Err(err(
                    &format!("collision.disable[{k}]"),
                    format!("'{link}' is not a link of the robot"),
                ));
            }
        }
    }
    let mut disabled: Vec<(String, String)> = c
        .disable
        .iter()
        .map(|[a, b]| (a.clone(), b.clone()))
        .collect();
    if let Some(path) = &c.srdf {
        let srdf = Srdf::read(&base_dir.join(path))
            .map_err(|e| TaskError::caused_by(source, "collision.srdf", e))?;
        srdf.check_links(&all_links)
            .map_err(|e| TaskError::caused_by(source, "collision.srdf", e))?;
        disabled.extend(srdf.disabled.into_iter().map(|p| (p.link1, p.link2)));
    }
    Ok(builder.scene(SceneSettings {
        scene,
        options,
        robot_shapes,
        self_pairs,
        disabled,
    }))
}

/// The file's `scene` (table and obstacles read), or `None` without one.
pub(crate) fn scene_from_file(
    file: &TaskFile,
    source: &str,
    base_dir: &Path,
) -> Result<Option<Scene>, TaskError> {
    if file.scene.is_none() && file.collision.is_some() {
        return Err(TaskError::new(
            source,
            "collision",
            "collision settings need a scene (give scene: {} for self-collision checks alone)",
        ));
    }
    let Some(scene_file) = &file.scene else {
        return Ok(None);
    };
    let err = |field: &str, message: String| TaskError::new(source, field, message);
    let mut scene = Scene::new();
    if let Some(table) = &scene_file.table {
        let footprint = table
            .size
            .map(|size| (size, table.centre.unwrap_or([0.0, 0.0])));
        if table.size.is_none() && table.centre.is_some() {
            return Err(err("scene.table.centre", "only applies with a size".into()));
        }
        scene = scene
            .with_table(table.height, footprint, table.thickness)
            .map_err(|e| TaskError::caused_by(source, "scene", e))?;
    }
    let mut names: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    for (k, obstacle) in scene_file.obstacles.iter().enumerate() {
        let field = format!("scene.obstacles[{k}]");
        let name = obstacle
            .name
            .clone()
            .unwrap_or_else(|| format!("obstacles[{k}]"));
        // Reports and failures name obstacles: two with one name could not be told apart.
        if let Some(first) = names.insert(name.clone(), k) {
            return Err(TaskError::new(
                source,
                format!("{field}.name"),
                format!(
                    "'{name}' is also the name of scene.obstacles[{first}]; names must be unique"
                ),
            ));
        }
        let world_from_obstacle = obstacle
            .pose
            .as_ref()
            .map(|p| {
                p.to_isometry().map_err(|e| {
                    TaskError::new(source, format!("{field}.pose.{}", e.field), e.message)
                })
            })
            .transpose()?
            .unwrap_or_else(Isometry3::identity);
        let mut given = Vec::new();
        if let Some(s) = obstacle.cuboid {
            given.push(Kind::Shape(Shape::Box(s)));
        }
        if let Some(s) = obstacle.cylinder {
            given.push(Kind::Shape(Shape::Cylinder(s)));
        }
        if let Some(s) = obstacle.sphere {
            given.push(Kind::Shape(Shape::Sphere(s)));
        }
        if let Some(s) = obstacle.capsule {
            given.push(Kind::Shape(Shape::Capsule(s)));
        }
        if let Some(path) = &obstacle.mesh {
            given.push(Kind::Mesh(base_dir.join(path)));
        }
        if let Some(path) = &obstacle.cloud {
            given.push(Kind::Cloud(base_dir.join(path)));
        }
        if obstacle.radius.is_some() && obstacle.cloud.is_none() {
            return Err(err(
                &format!("{field}.radius"),
                "only applies to a cloud".into(),
            ));
        }
        if given.len() != 1 {
            return Err(err(
                &field,
                format!(
                    "give exactly one of box, cylinder, sphere, capsule, mesh or cloud (got {})",
                    given.len()
                ),
            ));
        }
        let label = format!("obstacle {name}");
        scene = match given.remove(0) {
            Kind::Shape(shape) => scene.with_shape(&name, &shape, world_from_obstacle),
            Kind::Mesh(path) => {
                let mesh = read_mesh(&path)
                    .map_err(|e| TaskError::caused_by(source, format!("{field}.mesh"), e))?;
                let mesh = TriMesh::new(mesh.vertices, mesh.triangles)
                    .map_err(|e| TaskError::caused_by(source, format!("{field}.mesh"), e))?;
                scene.with_body(
                    Body::from_shape(label, &Shape::TriangleMesh(mesh)),
                    world_from_obstacle,
                )
            }
            Kind::Cloud(path) => {
                let cloud = read_cloud(&path)
                    .map_err(|e| TaskError::caused_by(source, format!("{field}.cloud"), e))?;
                let radius = obstacle.radius.ok_or_else(|| {
                    err(
                        &format!("{field}.radius"),
                        "a cloud obstacle needs the radius of its points (m)".into(),
                    )
                })?;
                let body = Body::from_points(label, &cloud.points, radius, &field)
                    .map_err(|e| TaskError::caused_by(source, &field, e))?;
                scene.with_body(body, world_from_obstacle)
            }
        };
    }
    Ok(Some(scene))
}

enum Kind {
    Shape(Shape),
    Mesh(std::path::PathBuf),
    Cloud(std::path::PathBuf),
}

/// Every collision shape of a robot's links, meshes read and scaled.
pub fn robot_link_shapes(model: &RobotModel) -> Result<Vec<LinkShape>, RobotError> {
    let mut out = Vec::new();
    for link in model.collisions()? {
        for element in &link.shapes {
            let shape = match &element.geometry {
                CollisionGeometry::Shape(shape) => shape.clone(),
                CollisionGeometry::Mesh(mesh) => Shape::TriangleMesh(load_collision_mesh(mesh)?),
            };
            out.push(LinkShape {
                link: link.link.clone(),
                link_from_shape: element.link_from_collision,
                shape,
            });
        }
    }
    Ok(out)
}

fn stroke_from(stroke: &StrokeFile, source: &str, field: &str) -> Result<Stroke, TaskError> {
    let mut out = Stroke::new(stroke.distance, stroke.samples.unwrap_or(STROKE_SAMPLES));
    if let Some(axis) = stroke.axis {
        let v = Vector3::from(axis);
        if !(v.iter().all(|x| x.is_finite()) && v.norm() > 1e-9) {
            return Err(TaskError::new(
                source,
                format!("{field}.axis"),
                format!("must be a non-zero finite vector, got {axis:?}"),
            ));
        }
        out.axis = Unit::new_normalize(v);
    }
    Ok(out)
}

fn gripper_from(
    gripper: &GripperFile,
    source: &str,
    base_dir: &Path,
    model: &RobotModel,
) -> Result<Gripper, TaskError> {
    let err = |field: &str, message: String| TaskError::new(source, field, message);
    if gripper.urdf.is_some() || gripper.root.is_some() {
        return urdf_gripper(gripper, source, base_dir, model);
    }
    for (field, given) in [
        ("gripper.tool_from_root", gripper.tool_from_root.is_some()),
        ("gripper.fingers", gripper.fingers.is_some()),
        ("gripper.open", gripper.open.is_some()),
    ] {
        if given {
            return Err(err(
                field,
                "belongs to a URDF hand: give urdf and root".into(),
            ));
        }
    }
    let mut out = match (&gripper.builtin, gripper.opening) {
        (Some(name), _) => match StockGripper::from_name(name) {
            Some(StockGripper::Baxter) => Gripper::baxter(),
            Some(stock) => Gripper::stock(stock),
            None => {
                return Err(err(
                    "gripper.builtin",
                    format!(
                        "unknown gripper '{name}' (built in: {})",
                        StockGripper::spellings()
                    ),
                ))
            }
        },
        (None, Some(opening)) => Gripper::parallel(opening),
        (None, None) => {
            return Err(err(
                "gripper",
                format!(
                    "give builtin: NAME ({}), opening: METRES, or a URDF hand (urdf, root)",
                    StockGripper::spellings()
                ),
            ))
        }
    };
    if let GripperBodies::Links(_) = &out.bodies {
        // A stock gripper: the maker's bodies, and a narrower usable stroke at most.
        for (field, given) in [
            ("gripper.finger", gripper.finger.is_some()),
            ("gripper.palm", gripper.palm.is_some()),
        ] {
            if given {
                return Err(err(
                    field,
                    "does not apply to a stock gripper (its bodies are the maker's)".into(),
                ));
            }
        }
        if let Some(opening) = gripper.opening.filter(|o| !(*o > 0.0 && *o <= out.opening)) {
            return Err(err(
                "gripper.opening",
                format!(
                    "{opening} m is not within this gripper's stroke (0, {}] m",
                    out.opening
                ),
            ));
        }
    }
    if let Some(opening) = gripper.opening {
        out.opening = opening;
    }
    if let GripperBodies::Parallel { finger, palm } = &mut out.bodies {
        if let Some(f) = gripper.finger {
            *finger = f;
        }
        if gripper.palm.is_some() {
            *palm = gripper.palm;
        }
    }
    Ok(out)
}

/// A gripper from a URDF hand: the file's `urdf` (or the robot's own URDF), its `root` link,
/// opened at `open` (each joint at its upper limit unless named).
fn urdf_gripper(
    gripper: &GripperFile,
    source: &str,
    base_dir: &Path,
    model: &RobotModel,
) -> Result<Gripper, TaskError> {
    let err = |field: &str, message: String| TaskError::new(source, field, message);
    for (field, given) in [
        ("gripper.builtin", gripper.builtin.is_some()),
        ("gripper.opening", gripper.opening.is_some()),
        ("gripper.finger", gripper.finger.is_some()),
        ("gripper.palm", gripper.palm.is_some()),
    ] {
        if given {
            return Err(err(
                field,
                "does not apply to a URDF hand (its links are its fingers and palm)".into(),
            ));
        }
    }
    let Some(root) = &gripper.root else {
        return Err(err(
            "gripper.root",
            "a URDF hand needs its root link (the hand's frame)".into(),
        ));
    };
    let hand = match &gripper.urdf {
        Some(path) => {
            let hand_model = RobotSource::urdf(base_dir.join(path))
                .load()
                .map_err(|e| TaskError::caused_by(source, "gripper.urdf", e))?;
            hand_from_robot(&hand_model, root)
        }
        None => hand_from_robot(model, root),
    }
    .map_err(|e| TaskError::caused_by(source, "gripper.root", e))?;
    let mut open: Vec<f64> = hand.joints.iter().map(|j| j.upper).collect();
    for (name, value) in gripper.open.iter().flatten() {
        let Some(k) = hand.joints.iter().position(|j| j.name == *name) else {
            return Err(err(
                &format!("gripper.open.{name}"),
                format!(
                    "not a joint of the hand (joints: {})",
                    hand.joints
                        .iter()
                        .map(|j| j.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        };
        let joint = &hand.joints[k];
        if !(value.is_finite() && (joint.lower..=joint.upper).contains(value)) {
            return Err(err(
                &format!("gripper.open.{name}"),
                format!(
                    "{value} is outside the joint's limits [{}, {}]",
                    joint.lower, joint.upper
                ),
            ));
        }
        open[k] = *value;
    }
    let tool_from_root = match &gripper.tool_from_root {
        Some(spec) => pose(spec, source, "gripper.tool_from_root")?,
        None => Isometry3::identity(),
    };
    Gripper::from_hand(
        &hand,
        &tool_from_root,
        &open,
        gripper.fingers.as_deref().unwrap_or_default(),
    )
    .map_err(|(field, message)| err(&field, message))
}
