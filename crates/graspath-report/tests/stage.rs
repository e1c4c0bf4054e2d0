//! The 3D view's staging: the box the camera is fitted to holds exactly the robot (bases, link
//! frames and tips at rest and along the motion shown on load) and the object along its path —
//! recomputed here from forward kinematics and the box's corners — and the camera placed as the
//! page places it sees every corner of that box within its field of view.

use graspath::select::select;
use graspath::task::Task;
use graspath_report::{stage, VIEW_ASPECT, VIEW_AZIMUTH, VIEW_ELEVATION, VIEW_FILL, VIEW_FOV_DEG};
use nalgebra::{Point3, Vector3};
use std::path::PathBuf;
use std::sync::Arc;

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// The box of the robot and the task from FK: each arm's base, every link frame's origin and
/// the tip at rest and along the shown (best pair's, else best) trajectory; the object box's
/// eight corners at every path pose.
fn oracle_box(task: &Task) -> (Point3<f64>, Point3<f64>) {
    let selection = select(task, &|| {}).unwrap();
    let mut points: Vec<Point3<f64>> = Vec::new();
    for (k, setup) in task.arms().iter().enumerate() {
        let arm = &selection.arms[k];
        let shown = match selection.pairs.first() {
            Some(p) => {
                let c = if k == 0 { &p.first } else { &p.second };
                task.candidates()
                    .held()
                    .expect("held candidates")
                    .iter()
                    .position(|t| Arc::ptr_eq(t, c))
            }
            None => arm.best(),
        };
        let mut qs = vec![setup.chain.mid_configuration()];
        if let Some(i) = shown {
            qs.extend(arm.scores[i].joint_trajectory.iter().cloned());
        }
        points.push(Point3::from(setup.world_from_base.translation.vector));
        for q in &qs {
            for frame in setup.chain.link_frames(q).unwrap() {
                let p = Point3::from(frame.translation.vector);
                points.push(setup.world_from_base * p);
            }
            let tip = setup.chain.pose(q).unwrap();
            points.push(setup.world_from_base * Point3::from(tip.translation.vector));
        }
    }
    let graspath::geometry::shape::Shape::Box(cuboid) = task.shape().unwrap() else {
        panic!("a box object")
    };
    let h = Vector3::from(cuboid.size()) / 2.0;
    for world_from_object in task.path().poses() {
        for m in 0..8 {
            let corner = Point3::new(
                if m & 1 == 0 { -h.x } else { h.x },
                if m & 2 == 0 { -h.y } else { h.y },
                if m & 4 == 0 { -h.z } else { h.z },
            );
            points.push(world_from_object * corner);
        }
    }
    let mut min = points[0];
    let mut max = points[0];
    for p in &points {
        min = min.inf(p);
        max = max.sup(p);
    }
    (min, max)
}

#[test]
fn the_camera_is_fitted_to_the_robot_and_the_object_path() {
    for name in ["pick_and_place_both.yaml", "pick_and_place_left.yaml"] {
        let task = Task::load(&example(name)).unwrap();
        let selection = select(&task, &|| {}).unwrap();
        let s = stage(&task, &selection);
        let (min, max) = oracle_box(&task);
        assert!(
            (s.min - min).norm() < 1e-9 && (s.max - max).norm() < 1e-9,
            "{name}: staged box {:?}..{:?}, FK box {min:?}..{max:?}",
            s.min,
            s.max
        );
        assert!((s.target - nalgebra::center(&min, &max)).norm() < 1e-9);
        // The camera as the page places it: at `distance` from the target, looking at it.
        let (a, e) = (VIEW_AZIMUTH, VIEW_ELEVATION);
        let eye =
            s.target + s.distance * Vector3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin());
        let forward = (s.target - eye).normalize();
        let right = forward.cross(&Vector3::z()).normalize();
        let up = right.cross(&forward);
        let tan_v = (VIEW_FOV_DEG.to_radians() / 2.0).tan();
        let tan_h = tan_v * VIEW_ASPECT;
        let mut reach: f64 = 0.0;
        for m in 0..8 {
            let corner = Point3::new(
                if m & 1 == 0 { min.x } else { max.x },
                if m & 2 == 0 { min.y } else { max.y },
                if m & 4 == 0 { min.z } else { max.z },
            );
            let d = corner - eye;
            let depth = d.dot(&forward);
            assert!(depth > 0.0, "{name}: a corner is behind the camera");
            let x = d.dot(&right).abs() / depth / tan_h;
            let y = d.dot(&up).abs() / depth / tan_v;
            assert!(
                x <= 1.0 && y <= 1.0,
                "{name}: corner {m} out of view ({x}, {y})"
            );
            reach = reach.max(x).max(y);
        }
        // Not lost in the distance: the farthest-out corner is at the stated fill.
        assert!(
            (reach - VIEW_FILL).abs() < 1e-9,
            "{name}: the box reaches {reach} of the view, not {VIEW_FILL}"
        );
        // The torso stands under the bases and reaches the highest of them.
        let top = s
            .bases
            .iter()
            .map(|b| b.z)
            .fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(s.torso.top, top);
        assert!(s.torso.bottom <= s.torso.top);
        // No scene: a table is drawn under the object's start.
        assert!(task.collisions().is_none() && s.table.is_some());
    }
}
