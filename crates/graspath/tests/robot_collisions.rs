//! Link collision geometry: URDF `<collision>` elements (primitives, capsules, meshes found
//! through each kind of search path, read on request) and the built-in Baxter's primitives
//! against the published description placed by the URDF chain.

mod common;

use graspath::geometry::shape::Shape;
use graspath::robot::builtin::baxter_collisions;
use graspath::robot::{CollisionGeometry, MeshResolver, RobotSource, UrdfRobot};
use nalgebra::{Isometry3, Point3, Vector3};
use rand::{rngs::StdRng, RngExt, SeedableRng};
use std::path::Path;

const CUBE_OBJ: &str = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

fn robot(uri: &str) -> UrdfRobot {
    UrdfRobot::from_xml(
        &format!(
            r#"<robot name="m"><link name="base">
              <collision name="body"><origin xyz="0.1 0.2 0.3" rpy="0 0 1.5707963267948966"/><geometry><box size="0.1 0.2 0.3"/></geometry></collision>
              <collision><geometry><capsule radius="0.05" length="0.2"/></geometry></collision>
              <collision><geometry><mesh filename="{uri}" scale="0.5 0.5 0.5"/></geometry></collision>
            </link></robot>"#
        ),
        "m.urdf",
    )
    .unwrap()
}

#[test]
fn primitives_meshes_and_every_kind_of_search_path() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let empty = MeshResolver::default();
    let cases = [
        (
            "package://pkg/meshes/cube.obj",
            root.join("extra/pkg/meshes/cube.obj"),
            MeshResolver {
                search_paths: vec![root.join("extra")],
                ..empty.clone()
            },
        ),
        (
            "package://pkg/meshes/cube.obj",
            root.join("ros/pkg/meshes/cube.obj"),
            MeshResolver {
                ros_package_path: vec![root.join("ros")],
                ..empty.clone()
            },
        ),
        (
            "model://pkg/meshes/cube.obj",
            root.join("ament/share/pkg/meshes/cube.obj"),
            MeshResolver {
                ament_prefix_path: vec![root.join("ament")],
                ..empty.clone()
            },
        ),
        (
            "package://pkg/meshes/cube.obj",
            root.join("src/pkg/meshes/cube.obj"),
            MeshResolver {
                base_dir: root.join("src/pkg/urdf"),
                ..empty.clone()
            },
        ),
        (
            "meshes/cube.obj",
            root.join("plain/meshes/cube.obj"),
            MeshResolver {
                base_dir: root.join("plain"),
                ..empty.clone()
            },
        ),
    ];
    for (uri, file, resolver) in cases {
        write(&file, CUBE_OBJ);
        let links = robot(uri).collisions(&resolver).unwrap();
        assert_eq!(links.len(), 1);
        let shapes = &links[0].shapes;
        assert_eq!(shapes[0].name.as_deref(), Some("body"));
        let expected = Isometry3::new(
            Vector3::new(0.1, 0.2, 0.3),
            Vector3::z() * std::f64::consts::FRAC_PI_2,
        );
        assert!(
            (shapes[0].link_from_collision.to_homogeneous() - expected.to_homogeneous())
                .abs()
                .max()
                < 1e-15
        );
        assert_eq!(
            shapes[0].geometry,
            CollisionGeometry::Shape(Shape::cuboid([0.1, 0.2, 0.3]).unwrap())
        );
        assert_eq!(
            shapes[1].geometry,
            CollisionGeometry::Shape(Shape::capsule(0.05, 0.2).unwrap())
        );
        let CollisionGeometry::Mesh(mesh) = &shapes[2].geometry else {
            panic!("mesh")
        };
        assert_eq!(mesh.path, file, "{uri}");
        let tri = graspath::cloud::load_collision_mesh(mesh).unwrap();
        assert!(tri.is_closed());
        // The 2 m cube scaled by ½: a 1 m cube, centre 0.5 m deep.
        let sd = Shape::TriangleMesh(tri);
        assert!((sd.signed_distance(&Point3::origin()) + 0.5).abs() < 1e-12);
        assert!((sd.signed_distance(&Point3::new(0.0, 0.0, 2.0)) - 1.5).abs() < 1e-12);
        std::fs::remove_file(&file).unwrap();
    }
    // file:// URIs are absolute paths.
    let file = root.join("abs/cube.obj");
    write(&file, CUBE_OBJ);
    let links = robot(&format!("file://{}", file.display()))
        .collisions(&empty)
        .unwrap();
    assert!(matches!(&links[0].shapes[2].geometry, CollisionGeometry::Mesh(m) if m.path == file));
    // A found file that is not a mesh fails on reading, naming the link and the file.
    write(&file, "not a mesh");
    let links = robot(&format!("file://{}", file.display()))
        .collisions(&empty)
        .unwrap();
    let CollisionGeometry::Mesh(mesh) = &links[0].shapes[2].geometry else {
        panic!("mesh")
    };
    let err = graspath::cloud::load_collision_mesh(mesh)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("m.urdf: link 'base', collision mesh") && err.contains("cube.obj"),
        "{err}"
    );
}

/// The end points of a cylinder's axis and its radius, in the base frame.
fn axis_of(
    world_from_link: &Isometry3<f64>,
    link_from_collision: &Isometry3<f64>,
    shape: &Shape,
) -> (Point3<f64>, Point3<f64>, f64) {
    let Shape::Cylinder(c) = shape else {
        panic!("a cylinder")
    };
    let pose = world_from_link * link_from_collision;
    let half = c.length() / 2.0;
    (
        pose * Point3::new(0.0, 0.0, -half),
        pose * Point3::new(0.0, 0.0, half),
        c.radius(),
    )
}

#[test]
fn builtin_baxter_primitives_sit_where_the_description_puts_them() {
    let Some(path) = common::shared_file("robots/baxter.urdf") else {
        return;
    };
    let urdf = UrdfRobot::from_file(&path).unwrap();
    // The description's two meshes exist somewhere: give placeholders so that resolution succeeds.
    let dir = tempfile::tempdir().unwrap();
    for mesh in [
        "torso/base_link_collision.DAE",
        "base/pedestal_link_collision.DAE",
    ] {
        write(
            &dir.path()
                .join("example-robot-data/robots/baxter_description/meshes")
                .join(mesh),
            "",
        );
    }
    let resolver = MeshResolver {
        search_paths: vec![dir.path().to_path_buf()],
        ..MeshResolver::default()
    };
    let published = urdf.collisions(&resolver).unwrap();
    let model = RobotSource::builtin("baxter").load().unwrap();
    let builtin = model.collisions().unwrap();
    assert_eq!(builtin, baxter_collisions());
    let mut rng = StdRng::seed_from_u64(4);
    let mut compared = 0;
    for side in ["left", "right"] {
        let chain = model.named_chain(side, None).unwrap();
        for _ in 0..10 {
            let q: Vec<f64> = chain
                .lower()
                .iter()
                .zip(chain.upper())
                .map(|(lo, hi)| lo + rng.random::<f64>() * (hi - lo))
                .collect();
            let frames = chain.link_frames(&q).unwrap();
            for link in &builtin {
                let Some(k) = chain.link_index(&link.link) else {
                    continue;
                };
                let world_from_link: Isometry3<f64> = nalgebra::convert(frames[k]);
                for shape in &link.shapes {
                    let CollisionGeometry::Shape(s @ Shape::Cylinder(_)) = &shape.geometry else {
                        continue;
                    };
                    // The published element: on the link of the same name (with `_link` for
                    // hand and gripper base), or on the `_visual` link.
                    let name = shape.name.as_deref().unwrap();
                    let urdf_link = published
                        .iter()
                        .find(|l| {
                            l.link == format!("{side}_{name}")
                                || l.link == format!("{side}_{name}_link")
                        })
                        .unwrap_or_else(|| panic!("{side}_{name}"));
                    let urdf_chain = urdf.chain("base", &urdf_link.link, None).unwrap();
                    let world_from_urdf_link: Isometry3<f64> =
                        nalgebra::convert(urdf_chain.pose(&q[..urdf_chain.dof()]).unwrap());
                    let CollisionGeometry::Shape(p) = &urdf_link.shapes[0].geometry else {
                        panic!("primitive")
                    };
                    let (a0, a1, ar) = axis_of(&world_from_link, &shape.link_from_collision, s);
                    let (b0, b1, br) = axis_of(
                        &world_from_urdf_link,
                        &urdf_link.shapes[0].link_from_collision,
                        p,
                    );
                    // Ends may swap (a cylinder turned half a revolution is the same solid).
                    let d = ((a0 - b0).norm() + (a1 - b1).norm())
                        .min((a0 - b1).norm() + (a1 - b0).norm());
                    assert!(d < 1e-9 && (ar - br).abs() < 1e-15, "{side}_{name}: {d}");
                    compared += 1;
                }
            }
        }
    }
    assert_eq!(compared, 2 * 10 * 11);
    // The head spheres: the description's, moved from collision_head_link_1/2 onto base.
    for (k, name) in ["collision_head_link_1", "collision_head_link_2"]
        .iter()
        .enumerate()
    {
        let frame = urdf.chain("base", name, None).unwrap().pose(&[]).unwrap();
        let element = &published.iter().find(|l| l.link == *name).unwrap().shapes[0];
        let centre = nalgebra::convert::<_, Isometry3<f64>>(frame)
            * element.link_from_collision
            * Point3::origin();
        let ours = builtin[0].shapes[k].link_from_collision * Point3::origin();
        assert!((centre - ours).norm() < 1e-15);
        assert_eq!(builtin[0].shapes[k].geometry, element.geometry);
    }
}

#[test]
fn hand_meshes_resolve_through_the_robot_source() {
    use graspath::grasp::hand::hand_from_robot;
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("share/pkg/cube.obj"), CUBE_OBJ);
    let urdf = dir.path().join("hand/hand.urdf");
    write(
        &urdf,
        r#"<robot name="h"><link name="palm"><collision><geometry><mesh filename="package://pkg/cube.obj"/></geometry></collision></link></robot>"#,
    );
    let source = RobotSource::Urdf {
        path: urdf.clone(),
        search_paths: vec![dir.path().join("share")],
        xacro_args: Default::default(),
    };
    let hand = hand_from_robot(&source.load().unwrap(), "palm").unwrap();
    assert!(matches!(
        hand.links[0].shapes[0].shape,
        Shape::ConvexMesh(_)
    ));
    // Without the search path the error names the hand file, the link and the paths tried.
    let err = hand_from_robot(&RobotSource::urdf(&urdf).load().unwrap(), "palm")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("hand.urdf: link 'palm', collision mesh 'package://pkg/cube.obj': not found"),
        "{err}"
    );
    let err = hand_from_robot(&RobotSource::builtin("baxter").load().unwrap(), "palm")
        .unwrap_err()
        .to_string();
    assert!(err.contains("built-in"), "{err}");
}
