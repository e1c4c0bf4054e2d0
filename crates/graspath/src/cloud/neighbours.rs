//! Fixed-radius and nearest-neighbour search over a cloud (a `kiddo` k-d tree).

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::Point3;

/// A k-d tree over a set of points (metres). Queries never allocate unless they return a
/// vector; results are indices into the slice the index was built from.
pub struct PointIndex {
    tree: Option<ImmutableKdTree<f64, 3>>,
    points: Vec<Point3<f64>>,
}

impl std::fmt::Debug for PointIndex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PointIndex")
            .field("points", &self.points.len())
            .finish()
    }
}

impl PointIndex {
    /// Builds the tree (single-threaded, so the layout is the same on every run).
    pub fn new(points: &[Point3<f64>]) -> Self {
        let coords: Vec<[f64; 3]> = points.iter().map(|p| [p.x, p.y, p.z]).collect();
        let tree = if coords.is_empty() {
            None
        } else {
            ImmutableKdTree::new_from_slice(&coords).ok()
        };
        Self {
            tree,
            points: points.to_vec(),
        }
    }

    /// The indexed points.
    pub fn points(&self) -> &[Point3<f64>] {
        &self.points
    }

    /// Calls `visit(index, squared_distance)` for every point within `radius` (m, inclusive)
    /// of `query`, in an unspecified but repeatable order.
    #[inline]
    pub fn for_each_within(
        &self,
        query: &Point3<f64>,
        radius: f64,
        mut visit: impl FnMut(usize, f64),
    ) {
        if let Some(tree) = &self.tree {
            tree.query(&[query.x, query.y, query.z])
                .within::<SquaredEuclidean<f64>>(radius * radius)
                .unsorted()
                .visit(|r| visit(r.item as usize, r.distance));
        }
    }

    /// The indices of the points within `radius` of `query`, in increasing index order.
    pub fn within(&self, query: &Point3<f64>, radius: f64) -> Vec<usize> {
        let mut out = Vec::new();
        self.for_each_within(query, radius, |i, _| out.push(i));
        out.sort_unstable();
        out
    }

    /// The distances (m) from `query` to its `n` nearest indexed points (fewer when the index
    /// holds fewer), in increasing order; a point at `query` itself counts, at distance 0.
    pub fn nearest_distances(&self, query: &Point3<f64>, n: usize) -> Vec<f64> {
        let (Some(tree), Some(n)) = (&self.tree, std::num::NonZeroUsize::new(n)) else {
            return Vec::new();
        };
        let mut distances: Vec<f64> = tree
            .query(&[query.x, query.y, query.z])
            .nearest_n::<SquaredEuclidean<f64>>(n)
            .execute()
            .iter()
            .map(|r| r.distance.sqrt())
            .collect();
        distances.sort_unstable_by(f64::total_cmp);
        distances
    }

    /// The nearest point's index and its distance (m), or `None` for an empty index.
    pub fn nearest(&self, query: &Point3<f64>) -> Option<(usize, f64)> {
        let tree = self.tree.as_ref()?;
        let r = tree
            .query(&[query.x, query.y, query.z])
            .nearest_one::<SquaredEuclidean<f64>>()
            .execute();
        Some((r.item as usize, r.distance.sqrt()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_brute_force() {
        let points: Vec<Point3<f64>> = (0..500)
            .map(|i| {
                let t = i as f64;
                Point3::new((t * 0.37).sin(), (t * 0.11).cos(), (t * 0.05).sin() * 0.5)
            })
            .collect();
        let index = PointIndex::new(&points);
        let q = Point3::new(0.1, 0.2, 0.0);
        let brute: Vec<usize> = (0..points.len())
            .filter(|&i| (points[i] - q).norm() <= 0.4)
            .collect();
        assert_eq!(index.within(&q, 0.4), brute);
        let (best, d) = index.nearest(&q).expect("non-empty");
        let brute_best = (0..points.len())
            .min_by(|&a, &b| (points[a] - q).norm().total_cmp(&(points[b] - q).norm()))
            .expect("non-empty");
        assert_eq!(best, brute_best);
        assert!((d - (points[best] - q).norm()).abs() < 1e-12);
        assert!(PointIndex::new(&[]).nearest(&q).is_none());
    }
}
