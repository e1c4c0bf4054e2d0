//! Surface features of the grasp model: normals by PCA within a radius (oriented to a
//! viewpoint), principal curvatures (PCL's `PrincipalCurvaturesEstimation`), and the local
//! frame of each point.
//!
//! All computations are per point and independent, run in parallel with rayon, and give the
//! same bits at any thread count.

use super::{neighbours::PointIndex, CloudError, PointCloud};
use nalgebra::{Matrix3, Point3, Rotation3, SymmetricEigen, UnitQuaternion, Vector3};
use rayon::prelude::*;

/// How normals without a known orientation are flipped.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NormalOrientation {
    /// Towards a sensor origin (object frame, m): `n · (viewpoint − p) > 0`.
    Viewpoint([f64; 3]),
    /// Away from the cloud's centroid (right for convex objects seen from all sides).
    AwayFromCentroid,
}

/// Radii and options of the feature pipeline.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FeatureParams {
    /// Neighbourhood radius for normal estimation (m); 15 mm by default.
    pub normal_radius: f64,
    /// Neighbourhood radius for principal curvatures (m); 15 mm by default.
    pub curvature_radius: f64,
    /// How estimated normals are oriented.
    pub orientation: NormalOrientation,
    /// Recompute normals even when the cloud has them.
    pub recompute_normals: bool,
}

impl Default for FeatureParams {
    fn default() -> Self {
        Self {
            normal_radius: 0.015,
            curvature_radius: 0.015,
            orientation: NormalOrientation::AwayFromCentroid,
            recompute_normals: false,
        }
    }
}

/// The principal curvatures of one point (PCL definition, dimensionless, `pc1 ≥ pc2 ≥ 0`) and
/// the principal direction (unit, object frame; its sign is arbitrary).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Curvature {
    /// Largest eigenvalue of the covariance of projected neighbour normals, divided by the
    /// neighbour count.
    pub pc1: f64,
    /// The second eigenvalue, divided by the neighbour count.
    pub pc2: f64,
    /// The eigenvector of `pc1`: the direction in which the normal varies most.
    pub direction: Vector3<f64>,
}

/// One surface feature `x = (p, q, r)`: position, local frame and curvature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceFeature {
    /// Position (object frame, m).
    pub position: Point3<f64>,
    /// Unit normal (object frame), the frame's `z` axis.
    pub normal: Vector3<f64>,
    /// `object_from_feature` rotation: `z` = normal, `x` ≈ principal direction.
    pub frame: UnitQuaternion<f64>,
    /// `(pc1, pc2)`.
    pub curvature: [f64; 2],
}

impl SurfaceFeature {
    /// `object_from_feature` as a rigid transform.
    pub fn pose(&self) -> nalgebra::Isometry3<f64> {
        nalgebra::Isometry3::from_parts(self.position.coords.into(), self.frame)
    }
}

/// Unit normals by PCA of all neighbours within `radius` (the eigenvector of the smallest
/// eigenvalue of their covariance), oriented as asked. A point with fewer than three neighbours
/// gets the direction away from the centroid of its neighbourhood or of the cloud.
pub fn estimate_normals(
    points: &[Point3<f64>],
    index: &PointIndex,
    radius: f64,
    orientation: NormalOrientation,
) -> Vec<Vector3<f64>> {
    let centroid = if points.is_empty() {
        Point3::origin()
    } else {
        Point3::from(points.iter().map(|p| p.coords).sum::<Vector3<f64>>() / points.len() as f64)
    };
    points
        .par_iter()
        .map(|p| {
            let mut sum = Vector3::zeros();
            let mut outer = Matrix3::zeros();
            let mut count = 0usize;
            index.for_each_within(p, radius, |j, _| {
                let d = points[j] - p;
                sum += d;
                outer += d * d.transpose();
                count += 1;
            });
            let fallback = {
                let away = p - centroid;
                if away.norm() > 1e-12 {
                    away.normalize()
                } else {
                    Vector3::z()
                }
            };
            let mut normal = if count < 3 {
                fallback
            } else {
                let mean = sum / count as f64;
                let covariance = outer / count as f64 - mean * mean.transpose();
                smallest_eigenvector(&covariance).unwrap_or(fallback)
            };
            let towards = match orientation {
                NormalOrientation::Viewpoint(v) => Point3::from(v) - p,
                NormalOrientation::AwayFromCentroid => p - centroid,
            };
            if normal.dot(&towards) < 0.0 {
                normal = -normal;
            }
            normal
        })
        .collect()
}

fn sorted_eigen(m: &Matrix3<f64>) -> Option<([f64; 3], [Vector3<f64>; 3])> {
    if m.iter().any(|v| !v.is_finite()) {
        return None;
    }
    // Bounded: an unbounded iteration can fail to end on some inputs (nalgebra#1025), and a
    // cloud is untrusted input.
    let eigen = SymmetricEigen::try_new(*m, f64::EPSILON, 1_000)?;
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
    let values = order.map(|i| eigen.eigenvalues[i]);
    let vectors = order.map(|i| eigen.eigenvectors.column(i).normalize());
    Some((values, vectors))
}

fn smallest_eigenvector(m: &Matrix3<f64>) -> Option<Vector3<f64>> {
    sorted_eigen(m).map(|(_, v)| v[2])
}

/// Principal curvatures of every point (PCL's definition): with `m_j = (I − n nᵀ) n_j` the
/// neighbour normals (the point included, within `radius`) projected on the tangent plane, and
/// `C = Σ (m_j − m̄)(m_j − m̄)ᵀ` with eigenvalues `λ1 ≥ λ2 ≥ λ3`: `pc1 = λ1/|N|`,
/// `pc2 = λ2/|N|`, direction = eigenvector of `λ1`.
pub fn principal_curvatures(
    points: &[Point3<f64>],
    normals: &[Vector3<f64>],
    index: &PointIndex,
    radius: f64,
) -> Vec<Curvature> {
    points
        .par_iter()
        .zip(normals.par_iter())
        .map(|(p, n)| {
            let projector = Matrix3::identity() - n * n.transpose();
            let mut sum = Vector3::zeros();
            let mut outer = Matrix3::zeros();
            let mut count = 0usize;
            index.for_each_within(p, radius, |j, _| {
                let m = projector * normals[j];
                sum += m;
                outer += m * m.transpose();
                count += 1;
            });
            let flat = Curvature {
                pc1: 0.0,
                pc2: 0.0,
                direction: any_perpendicular(n),
            };
            if count == 0 {
                return flat;
            }
            let k = count as f64;
            let mean = sum / k;
            let scatter = outer - mean * mean.transpose() * k;
            match sorted_eigen(&scatter) {
                Some((values, vectors)) => Curvature {
                    pc1: values[0].max(0.0) / k,
                    pc2: values[1].max(0.0) / k,
                    direction: vectors[0],
                },
                None => flat,
            }
        })
        .collect()
}

fn any_perpendicular(n: &Vector3<f64>) -> Vector3<f64> {
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    n.cross(&helper).normalize()
}

/// The local frame `[x y z]` of a feature: `z = n`, `y = z × d / ‖z × d‖`, `x = y × z`.
/// When `d` is (nearly) parallel to `n`, any perpendicular direction stands in for it.
pub fn surface_frame(normal: &Vector3<f64>, direction: &Vector3<f64>) -> UnitQuaternion<f64> {
    let z = normal.normalize();
    let mut y = z.cross(direction);
    if y.norm() < 1e-9 {
        y = z.cross(&any_perpendicular(&z));
    }
    let y = y.normalize();
    let x = y.cross(&z);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(Matrix3::from_columns(
        &[x, y, z],
    )))
}

/// The features of every point of a cloud: normals (the cloud's own unless asked to
/// recompute), principal curvatures and local frames. `source_name` names the cloud in errors.
pub fn compute_features(
    cloud: &PointCloud,
    params: &FeatureParams,
    source_name: &str,
) -> Result<Vec<SurfaceFeature>, CloudError> {
    cloud.validate(source_name)?;
    for (field, value) in [
        ("normal_radius", params.normal_radius),
        ("curvature_radius", params.curvature_radius),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(CloudError::BadOption {
                field: field.into(),
                message: format!("must be a positive length in metres, got {value}"),
            });
        }
    }
    let index = PointIndex::new(&cloud.points);
    let normals = match (&cloud.normals, params.recompute_normals) {
        (Some(n), false) => n.clone(),
        _ => estimate_normals(
            &cloud.points,
            &index,
            params.normal_radius,
            params.orientation,
        ),
    };
    let curvatures = principal_curvatures(&cloud.points, &normals, &index, params.curvature_radius);
    Ok(cloud
        .points
        .par_iter()
        .zip(normals.par_iter())
        .zip(curvatures.par_iter())
        .map(|((p, n), c)| SurfaceFeature {
            position: *p,
            normal: *n,
            frame: surface_frame(n, &c.direction),
            curvature: [c.pc1, c.pc2],
        })
        .collect())
}
