//! The one boundary with parry3d-f64 (glam types): our shapes and nalgebra poses in, parry
//! shapes and poses out. Nothing else in the crate names a parry type.

use crate::geometry::shape::{Shape, Stem};
use nalgebra::{IsometryMatrix3, Point3, UnitQuaternion};
use parry3d_f64::math::{Pose, Rot3, Vector};
use parry3d_f64::shape::SharedShape;

/// A point or vector in parry's type.
pub(crate) fn vector(p: &nalgebra::Vector3<f64>) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// A point in parry's type.
pub(crate) fn point(p: &Point3<f64>) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// A rigid transform given by a rotation matrix (the kinematics' link frames), in parry's type.
pub(crate) fn pose_from_matrix(a_from_b: &IsometryMatrix3<f64>) -> Pose {
    let q = UnitQuaternion::from_rotation_matrix(&a_from_b.rotation).coords;
    Pose::from_parts(
        vector(&a_from_b.translation.vector),
        Rot3::from_xyzw(q.x, q.y, q.z, q.w),
    )
}

/// Our shape as a parry shape and where it sits in our shape's frame. Cylinders are along `z`
/// here and along `y` in parry, hence a quarter turn; a T-shape becomes a compound of its bar
/// and stem; a convex mesh its hull; a triangle mesh a surface (no inside).
pub(crate) fn shape(shape: &Shape) -> (Pose, SharedShape) {
    // parry's y axis onto our z axis.
    let y_onto_z = Pose::from_rotation(Rot3::from_rotation_x(std::f64::consts::FRAC_PI_2));
    let same = match shape {
        Shape::Cylinder(c) => {
            return (
                y_onto_z,
                SharedShape::cylinder(c.length() / 2.0, c.radius()),
            );
        }
        Shape::Box(b) => {
            let h = b.half_extents();
            SharedShape::cuboid(h.x, h.y, h.z)
        }
        Shape::Sphere(s) => SharedShape::ball(s.radius()),
        Shape::Capsule(c) => SharedShape::capsule_z(c.length() / 2.0, c.radius()),
        Shape::TShape(t) => {
            let h = t.bar().half_extents();
            let bar = SharedShape::cuboid(h.x, h.y, h.z);
            let stem_at = Pose::from_translation(Vector::new(0.0, 0.0, t.stem_centre()));
            let stem = match t.stem() {
                Stem::Box(b) => {
                    let h = b.half_extents();
                    (stem_at, SharedShape::cuboid(h.x, h.y, h.z))
                }
                Stem::Cylinder(c) => (
                    stem_at * y_onto_z,
                    SharedShape::cylinder(c.length() / 2.0, c.radius()),
                ),
            };
            SharedShape::compound(vec![(Pose::identity(), bar), stem])
        }
        Shape::ConvexMesh(m) => {
            let points: Vec<Vector> = m.hull_vertices().iter().map(point).collect();
            // The hull was checked to have volume when the mesh was built.
            SharedShape::convex_hull(&points).expect("a convex mesh with volume has a hull")
        }
        Shape::TriangleMesh(m) => {
            let vertices: Vec<Vector> = m.vertices().iter().map(point).collect();
            // Indices were checked against the vertex count when the mesh was built.
            SharedShape::trimesh(vertices, m.triangles().to_vec())
                .expect("a checked triangle mesh converts")
        }
    };
    (Pose::identity(), same)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Isometry3;

    #[test]
    fn converted_shapes_have_the_same_surface() {
        // Oracle: our signed distance (closed forms per primitive) against parry's point
        // projection of the converted shape, at points around each shape.
        let shapes = [
            Shape::cuboid([0.1, 0.2, 0.3]).unwrap(),
            Shape::cylinder(0.05, 0.3).unwrap(),
            Shape::sphere(0.07).unwrap(),
            Shape::capsule(0.04, 0.2).unwrap(),
            serde_json::from_str(
                r#"{"t_shape": {"bar": [0.08, 0.24, 0.03], "stem": {"cylinder": {"radius": 0.02, "length": 0.12}}}}"#,
            )
            .unwrap(),
        ];
        for s in &shapes {
            let (at, converted) = shape(s);
            for i in 0..200 {
                let t = i as f64 * 0.37;
                let p = Point3::new(0.3 * t.sin(), 0.3 * (1.3 * t).cos(), 0.3 * (0.7 * t).sin());
                let ours = s.signed_distance(&p).max(0.0);
                let theirs = converted.distance_to_point(&at, point(&p), true);
                assert!(
                    (ours - theirs).abs() < 1e-9,
                    "{}: at {p}: ours {ours}, parry {theirs}",
                    s.kind()
                );
            }
        }
    }

    #[test]
    fn poses_convert_both_ways_alike() {
        let a_from_b = Isometry3::from_parts(
            nalgebra::Translation3::new(0.1, -0.2, 0.3),
            UnitQuaternion::from_euler_angles(0.3, -1.1, 2.0),
        );
        let p = Point3::new(0.4, 0.5, -0.6);
        let ours = a_from_b * p;
        let converted = pose_from_matrix(&nalgebra::convert(a_from_b));
        assert!((converted * point(&p) - point(&ours)).length() < 1e-12);
    }
}
