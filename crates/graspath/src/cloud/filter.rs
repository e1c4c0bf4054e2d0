//! Outlier handling for clouds from real sensors: a crop box, a maximum range from the sensor
//! origin and statistical outlier removal, applied in that order after invalid (NaN or
//! infinite) points have been skipped, and before surface features are computed.
//!
//! All positions are in the cloud's frame (the object frame, metres). With the default
//! options nothing is removed.

use super::{CloudError, PointCloud, PointIndex};
use nalgebra::{Point3, Vector3};
use rayon::prelude::*;

/// An axis-aligned box in the cloud's frame (m): points with `min ≤ p ≤ max` on every axis
/// are kept.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CropBox {
    /// The lower corner (m).
    pub min: [f64; 3],
    /// The upper corner (m).
    pub max: [f64; 3],
}

/// Statistical outlier removal (as PCL's `StatisticalOutlierRemoval`): for every point the
/// mean distance `d̄` to its `neighbours` nearest other points; with `μ` and `σ` the mean and
/// the (population) standard deviation of `d̄` over the cloud, a point is removed when
/// `d̄ > μ + std_ratio·σ`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StatisticalOutliers {
    /// k, the number of nearest neighbours (20 by default; at least 1).
    pub neighbours: usize,
    /// α, in standard deviations (2.0 by default; finite, may be negative).
    pub std_ratio: f64,
}

impl Default for StatisticalOutliers {
    fn default() -> Self {
        Self {
            neighbours: 20,
            std_ratio: 2.0,
        }
    }
}

/// How outliers are removed from a cloud before grasp generation. Every field is optional;
/// the default removes nothing (invalid points are always skipped when a file is read).
///
/// In a task or options file (JSON/YAML), e.g.
/// `{"crop_box": {"min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1]}, "max_range": 1.5,
/// "sensor_origin": [0, 0, 1.2], "statistical": {"neighbours": 20, "std_ratio": 2.0}}`.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OutlierOptions {
    /// Keep only the points inside this box (none by default: no cropping).
    pub crop_box: Option<CropBox>,
    /// Remove points farther than this from `sensor_origin` (m; none by default).
    pub max_range: Option<f64>,
    /// The sensor's position in the cloud's frame (m), for `max_range`; `[0, 0, 0]` by
    /// default (where a sensor-frame scan has its sensor).
    pub sensor_origin: Option<[f64; 3]>,
    /// Statistical outlier removal (none by default; `{}` turns it on with k = 20, α = 2).
    pub statistical: Option<StatisticalOutliers>,
}

/// What reading and outlier removal did to a cloud: point counts per step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CloudReport {
    /// Points in the file or sampled (including invalid ones).
    pub read: usize,
    /// Skipped for a NaN or infinite coordinate (or normal).
    pub invalid: usize,
    /// Removed by the crop box.
    pub outside_crop_box: usize,
    /// Removed by the maximum range.
    pub beyond_max_range: usize,
    /// Removed by statistical outlier removal.
    pub statistical_outliers: usize,
}

impl CloudReport {
    /// The points left.
    pub fn kept(&self) -> usize {
        self.read
            - self.invalid
            - self.outside_crop_box
            - self.beyond_max_range
            - self.statistical_outliers
    }
}

impl std::fmt::Display for CloudReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} points read, {} kept; removed: {} NaN/infinite, {} outside the crop box, {} beyond the maximum range, {} statistical outliers",
            self.read,
            self.kept(),
            self.invalid,
            self.outside_crop_box,
            self.beyond_max_range,
            self.statistical_outliers
        )
    }
}

fn bad(field: &str, message: String) -> CloudError {
    CloudError::BadFilter {
        field: field.to_string(),
        message,
    }
}

impl OutlierOptions {
    /// Whether the options remove nothing.
    pub fn is_empty(&self) -> bool {
        self.crop_box.is_none() && self.max_range.is_none() && self.statistical.is_none()
    }

    /// Checks every value: finite numbers, `min ≤ max`, a positive range, `neighbours ≥ 1`.
    pub fn check(&self) -> Result<(), CloudError> {
        if let Some(b) = &self.crop_box {
            if b.min.iter().chain(&b.max).any(|v| !v.is_finite()) {
                return Err(bad("crop_box", "corners must be finite numbers".into()));
            }
            if let Some(a) = (0..3).find(|&a| b.min[a] > b.max[a]) {
                return Err(bad(
                    "crop_box",
                    format!(
                        "min {:?} exceeds max {:?} on axis {}",
                        b.min,
                        b.max,
                        ["x", "y", "z"][a]
                    ),
                ));
            }
        }
        if let Some(r) = self.max_range {
            if !(r.is_finite() && r > 0.0) {
                return Err(bad(
                    "max_range",
                    format!("must be a positive distance in metres, got {r}"),
                ));
            }
        }
        if let Some(o) = self.sensor_origin {
            if o.iter().any(|v| !v.is_finite()) {
                return Err(bad("sensor_origin", "must be three finite numbers".into()));
            }
        }
        if let Some(s) = &self.statistical {
            if s.neighbours == 0 {
                return Err(bad("statistical.neighbours", "must be at least 1".into()));
            }
            if !s.std_ratio.is_finite() {
                return Err(bad(
                    "statistical.std_ratio",
                    format!("must be a finite number, got {}", s.std_ratio),
                ));
            }
        }
        Ok(())
    }

    /// Removes outliers from `cloud` (crop box, then range, then statistics), updating the
    /// counts of `report`; an error when the options are invalid or nothing is left.
    /// `source_name` names the cloud in errors. Deterministic; the kept points keep their
    /// order.
    pub fn apply(
        &self,
        cloud: PointCloud,
        report: &mut CloudReport,
        source_name: &str,
    ) -> Result<PointCloud, CloudError> {
        self.check()?;
        let mut cloud = cloud;
        if let Some(b) = &self.crop_box {
            let before = cloud.len();
            cloud = retain(cloud, |p| {
                (0..3).all(|a| b.min[a] <= p[a] && p[a] <= b.max[a])
            });
            report.outside_crop_box += before - cloud.len();
        }
        if let Some(range) = self.max_range {
            let origin = Point3::from(self.sensor_origin.unwrap_or([0.0; 3]));
            let before = cloud.len();
            cloud = retain(cloud, |p| (p - origin).norm() <= range);
            report.beyond_max_range += before - cloud.len();
        }
        if let Some(s) = &self.statistical {
            let keep = statistical_inliers(&cloud.points, s.neighbours, s.std_ratio);
            let before = cloud.len();
            let mut flags = keep.into_iter();
            cloud = retain(cloud, |_| flags.next().unwrap_or(true));
            report.statistical_outliers += before - cloud.len();
        }
        if cloud.is_empty() {
            return Err(CloudError::AllFiltered {
                source_name: source_name.to_string(),
                report: *report,
            });
        }
        Ok(cloud)
    }
}

/// The cloud's points (and normals) for which `keep` holds, in order; `keep` is called once
/// per point, in order.
fn retain(cloud: PointCloud, mut keep: impl FnMut(&Point3<f64>) -> bool) -> PointCloud {
    let flags: Vec<bool> = cloud.points.iter().map(&mut keep).collect();
    let points = cloud
        .points
        .iter()
        .zip(&flags)
        .filter(|(_, k)| **k)
        .map(|(p, _)| *p)
        .collect();
    let normals = cloud.normals.map(|ns| {
        ns.iter()
            .zip(&flags)
            .filter(|(_, k)| **k)
            .map(|(n, _)| *n)
            .collect::<Vec<Vector3<f64>>>()
    });
    PointCloud { points, normals }
}

/// Per point, whether it survives statistical outlier removal with `k` neighbours and ratio
/// `alpha`. A cloud of at most `k` points has too few neighbours to judge: nothing is removed.
pub(crate) fn statistical_inliers(points: &[Point3<f64>], k: usize, alpha: f64) -> Vec<bool> {
    let n = points.len();
    if n <= k {
        return vec![true; n];
    }
    let index = PointIndex::new(points);
    // Mean distance to the k nearest other points (the point itself is its own nearest, at
    // distance 0, and is excluded: k + 1 are asked for).
    let mean_distance: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| {
            let distances = index.nearest_distances(&points[i], k + 1);
            // Drop one zero (the point itself); duplicates of it count as neighbours.
            let total: f64 = distances.iter().skip(1).sum();
            total / k as f64
        })
        .collect();
    let mean = mean_distance.iter().sum::<f64>() / n as f64;
    let variance = mean_distance
        .iter()
        .map(|d| (d - mean) * (d - mean))
        .sum::<f64>()
        / n as f64;
    let threshold = mean + alpha * variance.sqrt();
    mean_distance.iter().map(|d| *d <= threshold).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_counts_add_up() {
        let report = CloudReport {
            read: 10,
            invalid: 1,
            outside_crop_box: 2,
            beyond_max_range: 3,
            statistical_outliers: 1,
        };
        assert_eq!(report.kept(), 3);
        let text = report.to_string();
        assert!(text.contains("10 points read, 3 kept"), "{text}");
    }
}
