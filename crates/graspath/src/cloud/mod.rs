//! Point clouds: reading and writing PLY and PCD files, sampling clouds from meshes and
//! shapes ([`sample_shape`] on a [`crate::geometry::shape::Shape`]), and the surface features of the grasp model (normals, principal curvatures,
//! local frames).
//!
//! Every cloud is expressed in one frame, the **object frame** (metres); normals are unit
//! vectors in that frame. Points with a NaN or infinite coordinate (the invalid points of an
//! organised scan) are dropped when a file is read, and counted ([`CloudReport`]); outliers
//! of real scans can be removed with [`OutlierOptions`] before features are computed.
//!
//! Reading is bounded: every count in a header (PCD `POINTS`, PLY element counts, binary STL
//! triangle counts) and every sampling count is checked against the bytes present and against
//! [`MAX_CLOUD_POINTS`] / [`MAX_MESH_TRIANGLES`] before anything is allocated for it.

mod error;
mod features;
mod filter;
mod io;
mod mesh;
mod neighbours;
mod pcd;
mod ply;
mod sample;
mod shape_source;

pub use error::CloudError;
pub use features::{
    compute_features, estimate_normals, principal_curvatures, surface_frame, Curvature,
    FeatureParams, NormalOrientation, SurfaceFeature,
};
pub use filter::{CloudReport, CropBox, OutlierOptions, StatisticalOutliers};
pub use io::CloudSource;
pub use io::{load_cloud_argument, load_cloud_filtered, read_cloud, write_cloud, CloudFormat};
pub use mesh::{load_collision_mesh, read_mesh, TriangleMesh};
pub use neighbours::PointIndex;
pub use pcd::{pcd_bytes, read_pcd, read_pcd_bytes, write_pcd, PcdEncoding};
pub use ply::{ply_bytes, read_ply, read_ply_bytes, write_ply, PlyEncoding};
pub use sample::{sample_shape, SampleOptions, MAX_SAMPLED_POINTS};
pub use shape_source::{CloudShape, LegacyTShape};

use nalgebra::{Point3, Vector3};

/// The most points a cloud may have (20 million, 480 MB of positions and as much of normals): a PCD `POINTS`,
/// a PLY `vertex` count or a sampling `points` option above it is refused before anything is
/// allocated.
pub const MAX_CLOUD_POINTS: usize = 20_000_000;

/// The most triangles a mesh file may have (20 million).
pub const MAX_MESH_TRIANGLES: usize = 20_000_000;

/// A point cloud in the object frame (metres), optionally with one unit normal per point.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PointCloud {
    /// Point positions (m).
    pub points: Vec<Point3<f64>>,
    /// Unit outward normals, one per point, when known.
    pub normals: Option<Vec<Vector3<f64>>>,
}

impl PointCloud {
    /// A cloud of positions only.
    pub fn from_points(points: Vec<Point3<f64>>) -> Self {
        Self {
            points,
            normals: None,
        }
    }

    /// The number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether the cloud has no point.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The axis-aligned bounds `(min, max)` of the points, or `None` for an empty cloud.
    pub fn bounds(&self) -> Option<(Point3<f64>, Point3<f64>)> {
        let first = self.points.first()?;
        let mut lo = *first;
        let mut hi = *first;
        for p in &self.points {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        Some((lo, hi))
    }

    /// The mean of the points, or `None` for an empty cloud.
    pub fn centroid(&self) -> Option<Point3<f64>> {
        if self.points.is_empty() {
            return None;
        }
        let sum: Vector3<f64> = self.points.iter().map(|p| p.coords).sum();
        Some(Point3::from(sum / self.points.len() as f64))
    }

    /// Drops every point whose position (or normal, when present) is not finite, and
    /// renormalises the normals. Returns how many points were dropped.
    pub fn drop_invalid(&mut self) -> usize {
        let before = self.points.len();
        match self.normals.take() {
            None => self.points.retain(|p| p.iter().all(|c| c.is_finite())),
            Some(normals) => {
                let (points, normals): (Vec<_>, Vec<_>) = self
                    .points
                    .iter()
                    .zip(normals)
                    .filter_map(|(p, n)| {
                        if !(p.iter().all(|c| c.is_finite()) && n.iter().all(|c| c.is_finite())) {
                            return None;
                        }
                        let norm = n.norm();
                        let unit = if norm.is_finite() {
                            (norm > 1e-12).then(|| n / norm)?
                        } else {
                            // A huge normal: scaled by its largest component first, so that
                            // its norm does not overflow.
                            (n / n.amax()).normalize()
                        };
                        Some((*p, unit))
                    })
                    .unzip();
                self.points = points;
                self.normals = Some(normals);
            }
        }
        before - self.points.len()
    }

    /// Checks that the cloud is usable: at least one point, and normals (when present) of the
    /// same count. `source_name` names the cloud in the error.
    pub fn validate(&self, source_name: &str) -> Result<(), CloudError> {
        if self.points.is_empty() {
            return Err(CloudError::Empty {
                source_name: source_name.to_string(),
            });
        }
        if let Some(n) = &self.normals {
            if n.len() != self.points.len() {
                return Err(CloudError::Parse {
                    source_name: source_name.to_string(),
                    location: "normals".into(),
                    message: format!("{} normals for {} points", n.len(), self.points.len()),
                });
            }
        }
        Ok(())
    }

    /// The cloud with every point and normal mapped by `to_from_this` (a rigid transform from
    /// this cloud's frame to another).
    pub fn transformed(&self, to_from_this: &nalgebra::Isometry3<f64>) -> Self {
        Self {
            points: self.points.iter().map(|p| to_from_this * p).collect(),
            normals: self
                .normals
                .as_ref()
                .map(|ns| ns.iter().map(|n| to_from_this * n).collect()),
        }
    }
}

/// Drops invalid points of a cloud just read from `source_name` and counts them; an error when
/// nothing is left.
pub(crate) fn finish_read(
    mut cloud: PointCloud,
    source_name: &str,
) -> Result<(PointCloud, usize), CloudError> {
    let total = cloud.points.len();
    if total == 0 {
        return Err(CloudError::Empty {
            source_name: source_name.to_string(),
        });
    }
    let dropped = cloud.drop_invalid();
    if cloud.points.is_empty() {
        return Err(CloudError::AllInvalid {
            source_name: source_name.to_string(),
            count: dropped,
        });
    }
    Ok((cloud, dropped))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drop_invalid_removes_nan_points_and_normals() {
        let mut cloud = PointCloud {
            points: vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(f64::NAN, 0.0, 0.0),
                Point3::new(1.0, 0.0, 0.0),
            ],
            normals: Some(vec![Vector3::z() * 2.0, Vector3::z(), Vector3::x()]),
        };
        assert_eq!(cloud.drop_invalid(), 1);
        assert_eq!(cloud.len(), 2);
        let normals = cloud.normals.expect("kept");
        assert!((normals[0].norm() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn all_nan_is_an_error() {
        let cloud = PointCloud::from_points(vec![Point3::new(f64::NAN, 0.0, 0.0); 3]);
        let err = finish_read(cloud, "x.ply").unwrap_err();
        assert!(err.to_string().contains("x.ply"), "{err}");
        assert!(matches!(err, CloudError::AllInvalid { count: 3, .. }));
    }
}
