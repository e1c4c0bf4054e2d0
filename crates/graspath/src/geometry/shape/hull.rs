//! The convex hull of a point set in 3-D (incremental construction): outward triangles over a
//! subset of the input points.

use nalgebra::{Point3, Vector3};
use std::collections::HashSet;

/// A hull triangle: indices into the input points, counter-clockwise seen from outside, and
/// its outward unit normal and offset (`n · x = d` on its plane).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Facet {
    pub vertices: [usize; 3],
    pub normal: Vector3<f64>,
    pub offset: f64,
}

fn facet(points: &[Point3<f64>], vertices: [usize; 3]) -> Option<Facet> {
    let [a, b, c] = vertices.map(|i| points[i]);
    let n = (b - a).cross(&(c - a));
    let length = n.norm();
    if length == 0.0 || !length.is_finite() {
        return None;
    }
    let normal = n / length;
    Some(Facet {
        vertices,
        normal,
        offset: normal.dot(&a.coords),
    })
}

/// Why no hull could be built.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum HullError {
    /// Fewer than four points, or all on one plane (within `tolerance`).
    Flat,
}

/// The hull of `points` (finite coordinates): its facets, or [`HullError::Flat`] when the
/// points span no volume. Points within `1e-10 ×` the bounding-box diagonal of a facet's plane
/// count as on it. Deterministic: points are added in their order.
pub(crate) fn convex_hull(points: &[Point3<f64>]) -> Result<Vec<Facet>, HullError> {
    if points.len() < 4 {
        return Err(HullError::Flat);
    }
    let (mut lo, mut hi) = (points[0], points[0]);
    for p in points {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let eps = 1e-10 * (hi - lo).norm();
    // An initial tetrahedron from extreme points.
    let i0 = (0..points.len())
        .min_by(|&a, &b| points[a].x.total_cmp(&points[b].x))
        .unwrap_or(0);
    let farthest = |score: &dyn Fn(&Point3<f64>) -> f64| {
        (0..points.len())
            .map(|i| (score(&points[i]), i))
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap_or((0.0, 0))
    };
    let (d1, i1) = farthest(&|p| (p - points[i0]).norm());
    if d1 <= eps {
        return Err(HullError::Flat);
    }
    let line = (points[i1] - points[i0]) / d1;
    let (d2, i2) = farthest(&|p| (p - points[i0]).cross(&line).norm());
    if d2 <= eps {
        return Err(HullError::Flat);
    }
    let plane = (points[i1] - points[i0])
        .cross(&(points[i2] - points[i0]))
        .normalize();
    let (d3, i3) = farthest(&|p| (p - points[i0]).dot(&plane).abs());
    if d3 <= eps {
        return Err(HullError::Flat);
    }
    let centre = Point3::from(
        (points[i0].coords + points[i1].coords + points[i2].coords + points[i3].coords) / 4.0,
    );
    let mut facets: Vec<Facet> = Vec::new();
    for tri in [[i0, i1, i2], [i0, i1, i3], [i0, i2, i3], [i1, i2, i3]] {
        let mut f = facet(points, tri).ok_or(HullError::Flat)?;
        if f.normal.dot(&centre.coords) > f.offset {
            f = facet(points, [tri[0], tri[2], tri[1]]).ok_or(HullError::Flat)?;
        }
        facets.push(f);
    }
    let mut edges = HashSet::new();
    for (i, p) in points.iter().enumerate() {
        if [i0, i1, i2, i3].contains(&i) {
            continue;
        }
        let visible: Vec<bool> = facets
            .iter()
            .map(|f| f.normal.dot(&p.coords) - f.offset > eps)
            .collect();
        if !visible.contains(&true) {
            continue;
        }
        edges.clear();
        for (f, _) in facets.iter().zip(&visible).filter(|(_, v)| **v) {
            let [a, b, c] = f.vertices;
            edges.extend([(a, b), (b, c), (c, a)]);
        }
        let mut horizon: Vec<(usize, usize)> = edges
            .iter()
            .copied()
            .filter(|&(a, b)| !edges.contains(&(b, a)))
            .collect();
        // Sort so that the facet order does not depend on the hash set's order.
        horizon.sort_unstable();
        let mut kept: Vec<Facet> = facets
            .iter()
            .zip(&visible)
            .filter(|(_, v)| !**v)
            .map(|(f, _)| *f)
            .collect();
        for (a, b) in horizon {
            // A degenerate (zero-area) facet adds nothing to the boundary: skip it.
            if let Some(f) = facet(points, [a, b, i]) {
                kept.push(f);
            }
        }
        facets = kept;
    }
    Ok(facets)
}
