//! The mass properties of a solid of uniform density, in the shape's own frame: its volume,
//! its centroid and its inertia per unit density. Closed forms for the primitives; for a mesh,
//! the exact volume integrals of its triangles (each triangle and the origin span a signed
//! tetrahedron; their sums are the solid's integrals, whatever the origin).

use super::{Shape, ShapeError, Stem};
use nalgebra::{Matrix3, Point3, Vector3};
use std::f64::consts::PI;

/// The mass properties of a solid of density 1 (shape frame): multiply `inertia` by the
/// density (kg/m³), or by `mass / volume`, for a body's inertia.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidMass {
    /// Volume (m³), positive.
    pub volume: f64,
    /// The centroid (m): the centre of mass at uniform density.
    pub centroid: Vector3<f64>,
    /// Rotational inertia about the centroid at density 1, along the shape's axes (m⁵:
    /// kg·m² per kg/m³).
    pub inertia: Matrix3<f64>,
}

impl SolidMass {
    /// A solid's properties from its volume and its inertia about its centroid at `centroid`.
    fn at(volume: f64, centroid: Vector3<f64>, inertia: Matrix3<f64>) -> Self {
        Self {
            volume,
            centroid,
            inertia,
        }
    }

    /// The inertia (kg·m², about the centroid) of the solid with total mass `mass` (kg).
    pub fn inertia_for_mass(&self, mass: f64) -> Matrix3<f64> {
        self.inertia * (mass / self.volume)
    }

    /// The union of two solids that do not overlap.
    fn joined(&self, other: &Self) -> Self {
        let volume = self.volume + other.volume;
        let centroid = (self.centroid * self.volume + other.centroid * other.volume) / volume;
        let about = |s: &Self| s.inertia + parallel_axis(s.volume, &(s.centroid - centroid));
        Self::at(volume, centroid, about(self) + about(other))
    }
}

/// The inertia a point of mass `mass` at `d` adds about the origin (Steiner).
fn parallel_axis(mass: f64, d: &Vector3<f64>) -> Matrix3<f64> {
    mass * (Matrix3::identity() * d.norm_squared() - d * d.transpose())
}

/// A box of edge lengths `size`, centred.
fn cuboid(size: [f64; 3]) -> SolidMass {
    let [a, b, c] = size;
    let volume = a * b * c;
    let inertia =
        Matrix3::from_diagonal(&Vector3::new(b * b + c * c, a * a + c * c, a * a + b * b))
            * (volume / 12.0);
    SolidMass::at(volume, Vector3::zeros(), inertia)
}

/// A cylinder along `z`, centred.
fn cylinder(radius: f64, length: f64) -> SolidMass {
    let volume = PI * radius * radius * length;
    let side = volume * (3.0 * radius * radius + length * length) / 12.0;
    let axial = volume * radius * radius / 2.0;
    SolidMass::at(
        volume,
        Vector3::zeros(),
        Matrix3::from_diagonal(&Vector3::new(side, side, axial)),
    )
}

/// A capsule along `z`, centred: a cylinder of `length` and two half balls.
fn capsule(radius: f64, length: f64) -> SolidMass {
    let (r, h) = (radius, length);
    let cylinder_volume = PI * r * r * h;
    let ball_volume = 4.0 / 3.0 * PI * r * r * r;
    let side = cylinder_volume * (h * h / 12.0 + r * r / 4.0)
        + ball_volume * (2.0 * r * r / 5.0 + h * h / 4.0 + 3.0 * h * r / 8.0);
    let axial = cylinder_volume * r * r / 2.0 + ball_volume * 2.0 * r * r / 5.0;
    SolidMass::at(
        cylinder_volume + ball_volume,
        Vector3::zeros(),
        Matrix3::from_diagonal(&Vector3::new(side, side, axial)),
    )
}

/// The solid bounded by closed triangles (consistently wound, either way round).
fn closed_triangles(
    triangles: impl Iterator<Item = [Point3<f64>; 3]>,
    field: &str,
) -> Result<SolidMass, ShapeError> {
    let (mut volume, mut first) = (0.0, Vector3::zeros());
    let mut second = Matrix3::zeros();
    for [a, b, c] in triangles {
        let (a, b, c) = (a.coords, b.coords, c.coords);
        let det = a.dot(&b.cross(&c));
        volume += det / 6.0;
        let sum = a + b + c;
        first += sum * (det / 24.0);
        second +=
            (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose())
                * (det / 120.0);
    }
    // Inward winding gives the negated integrals.
    let sign = volume.signum();
    let (volume, first, second) = (volume * sign, first * sign, second * sign);
    if !(volume > 0.0 && volume.is_finite()) {
        return Err(ShapeError::BadMesh {
            field: field.into(),
            message: "encloses no volume: its mass properties are undefined".into(),
        });
    }
    let centroid = first / volume;
    let about_origin = Matrix3::identity() * second.trace() - second;
    let inertia = about_origin - parallel_axis(volume, &centroid);
    Ok(SolidMass::at(
        volume,
        centroid,
        (inertia + inertia.transpose()) / 2.0,
    ))
}

impl Shape {
    /// The mass properties of the shape as a solid of density 1, in its own frame. An open
    /// triangle mesh (a surface, not a solid) has none.
    pub fn solid_mass(&self) -> Result<SolidMass, ShapeError> {
        Ok(match self {
            Shape::Box(b) => cuboid(b.size()),
            Shape::Cylinder(c) => cylinder(c.radius(), c.length()),
            Shape::Sphere(s) => {
                let r = s.radius();
                let volume = 4.0 / 3.0 * PI * r * r * r;
                SolidMass::at(
                    volume,
                    Vector3::zeros(),
                    Matrix3::identity() * (0.4 * volume * r * r),
                )
            }
            Shape::Capsule(c) => capsule(c.radius(), c.length()),
            Shape::TShape(t) => {
                let bar = t.bar().size();
                let stem_centre = Vector3::new(0.0, 0.0, bar[2] / 2.0 + t.stem().length() / 2.0);
                let mut stem = match t.stem() {
                    Stem::Cylinder(c) => cylinder(c.radius(), c.length()),
                    Stem::Box(b) => cuboid(b.size()),
                };
                stem.centroid = stem_centre;
                cuboid(bar).joined(&stem)
            }
            Shape::ConvexMesh(m) => closed_triangles(m.hull_triangles(), "convex_mesh")?,
            Shape::TriangleMesh(m) => {
                if !m.is_closed() {
                    return Err(ShapeError::BadMesh {
                        field: "triangle_mesh".into(),
                        message: "is not closed (an edge has no opposite triangle): a surface \
                                  has no volume, so give the object's mass and centre of mass"
                            .into(),
                    });
                }
                let vertices = m.vertices();
                closed_triangles(
                    m.triangles()
                        .iter()
                        .map(|t| t.map(|i| vertices[i as usize])),
                    "triangle_mesh",
                )?
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::shape::{ConvexMesh, TriMesh};

    fn close(a: &Matrix3<f64>, b: &Matrix3<f64>, tol: f64) -> bool {
        (a - b).amax() <= tol * b.amax().max(1e-300)
    }

    /// The eight corners and twelve outward triangles of a box of `size`, centred at `at`.
    fn box_mesh(size: [f64; 3], at: Vector3<f64>) -> TriMesh {
        let h = Vector3::from(size) / 2.0;
        let vertices: Vec<Point3<f64>> = (0..8)
            .map(|i| {
                let s = |bit: usize| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
                Point3::from(at + Vector3::new(s(0) * h.x, s(1) * h.y, s(2) * h.z))
            })
            .collect();
        let faces: [[u32; 4]; 6] = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles = faces
            .iter()
            .flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]])
            .collect();
        TriMesh::new(vertices, triangles).unwrap()
    }

    #[test]
    fn primitives_have_their_textbook_inertias() {
        // Oracles: the closed forms of a solid box, cylinder and ball (e.g. Meriam & Kraige).
        let b = Shape::cuboid([0.1, 0.2, 0.4])
            .unwrap()
            .solid_mass()
            .unwrap();
        assert!((b.volume - 0.008).abs() < 1e-15);
        let m = 0.008;
        let expected = Matrix3::from_diagonal(&Vector3::new(
            m * (0.04 + 0.16) / 12.0,
            m * (0.01 + 0.16) / 12.0,
            m * (0.01 + 0.04) / 12.0,
        ));
        assert!(close(&b.inertia, &expected, 1e-12));
        let c = Shape::cylinder(0.05, 0.3).unwrap().solid_mass().unwrap();
        let m = PI * 0.0025 * 0.3;
        assert!((c.volume - m).abs() < 1e-15);
        assert!((c.inertia[(2, 2)] - m * 0.0025 / 2.0).abs() < 1e-15);
        assert!((c.inertia[(0, 0)] - m * (3.0 * 0.0025 + 0.09) / 12.0).abs() < 1e-15);
        let s = Shape::sphere(0.2).unwrap().solid_mass().unwrap();
        let m = 4.0 / 3.0 * PI * 0.008;
        assert!((s.inertia[(1, 1)] - 0.4 * m * 0.04).abs() < 1e-15);
    }

    #[test]
    fn a_closed_mesh_matches_the_primitive_it_describes() {
        let at = Vector3::new(0.3, -0.2, 0.5);
        let mesh = box_mesh([0.1, 0.2, 0.4], at);
        let solid = Shape::TriangleMesh(mesh.clone()).solid_mass().unwrap();
        let primitive = Shape::cuboid([0.1, 0.2, 0.4])
            .unwrap()
            .solid_mass()
            .unwrap();
        assert!((solid.volume - primitive.volume).abs() < 1e-15);
        assert!((solid.centroid - at).norm() < 1e-14);
        assert!(close(&solid.inertia, &primitive.inertia, 1e-10));
        // Wound the other way round: the same solid.
        let flipped: Vec<[u32; 3]> = mesh
            .triangles()
            .iter()
            .map(|t| [t[0], t[2], t[1]])
            .collect();
        let inward = TriMesh::new(mesh.vertices().to_vec(), flipped).unwrap();
        let again = Shape::TriangleMesh(inward).solid_mass().unwrap();
        assert!((again.volume - solid.volume).abs() < 1e-15);
        assert!(close(&again.inertia, &solid.inertia, 1e-12));
        // The convex hull of the corners too.
        let hull = ConvexMesh::new(mesh.vertices().to_vec()).unwrap();
        let hull = Shape::ConvexMesh(hull).solid_mass().unwrap();
        assert!((hull.volume - primitive.volume).abs() < 1e-14);
        assert!(close(&hull.inertia, &primitive.inertia, 1e-10));
    }

    #[test]
    fn a_fine_mesh_of_a_cylinder_approaches_the_closed_form() {
        // A prism of 720 sides: its volume and inertia are within the polygon's area error.
        let (r, h, n) = (0.05, 0.3, 720);
        let ring = |z: f64| {
            (0..n).map(move |k| {
                let a = 2.0 * PI * f64::from(k) / f64::from(n);
                Point3::new(r * a.cos(), r * a.sin(), z)
            })
        };
        let mut vertices: Vec<Point3<f64>> = ring(-h / 2.0).chain(ring(h / 2.0)).collect();
        vertices.push(Point3::new(0.0, 0.0, -h / 2.0));
        vertices.push(Point3::new(0.0, 0.0, h / 2.0));
        let (bottom, top) = (2 * n, 2 * n + 1);
        let mut triangles = Vec::new();
        for k in 0..n {
            let j = (k + 1) % n;
            triangles.push([bottom, j, k]);
            triangles.push([top, n + k, n + j]);
            triangles.push([k, j, n + j]);
            triangles.push([k, n + j, n + k]);
        }
        let mesh = TriMesh::new(vertices, triangles).unwrap();
        let solid = Shape::TriangleMesh(mesh).solid_mass().unwrap();
        let exact = Shape::cylinder(r, h).unwrap().solid_mass().unwrap();
        assert!((solid.volume / exact.volume - 1.0).abs() < 1e-4);
        assert!(close(&solid.inertia, &exact.inertia, 1e-4));
    }

    #[test]
    fn a_t_shape_is_its_bar_and_stem_and_a_capsule_its_cylinder_and_ball() {
        let t = Shape::TShape(
            crate::geometry::shape::TShape::new(
                [0.4, 0.06, 0.04],
                Stem::Box(crate::geometry::shape::Cuboid::new([0.04, 0.04, 0.2]).unwrap()),
            )
            .unwrap(),
        );
        let solid = t.solid_mass().unwrap();
        // Oracle: the two boxes as one closed mesh each, joined by the mesh integrals.
        let bar = box_mesh([0.4, 0.06, 0.04], Vector3::zeros());
        let stem = box_mesh([0.04, 0.04, 0.2], Vector3::new(0.0, 0.0, 0.12));
        let offset = bar.vertices().len() as u32;
        let vertices = [bar.vertices(), stem.vertices()].concat();
        let triangles = bar
            .triangles()
            .iter()
            .copied()
            .chain(stem.triangles().iter().map(|t| t.map(|i| i + offset)))
            .collect();
        let both = closed_triangles(
            TriMesh::new(vertices.clone(), triangles)
                .unwrap()
                .triangles()
                .iter()
                .map(|t| t.map(|i| vertices[i as usize])),
            "test",
        )
        .unwrap();
        assert!((solid.volume - both.volume).abs() < 1e-15);
        assert!((solid.centroid - both.centroid).norm() < 1e-14);
        assert!(close(&solid.inertia, &both.inertia, 1e-10));
        // A capsule of zero length is a ball.
        let ball = capsule(0.1, 0.0);
        let exact = Shape::sphere(0.1).unwrap().solid_mass().unwrap();
        assert!((ball.volume - exact.volume).abs() < 1e-15);
        assert!(close(&ball.inertia, &exact.inertia, 1e-12));
    }

    #[test]
    fn an_open_mesh_has_no_mass_properties() {
        let mesh = box_mesh([0.1, 0.1, 0.1], Vector3::zeros());
        let open = TriMesh::new(mesh.vertices().to_vec(), mesh.triangles()[1..].to_vec()).unwrap();
        assert!(Shape::TriangleMesh(open).solid_mass().is_err());
    }
}
