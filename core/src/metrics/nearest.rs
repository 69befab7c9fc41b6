//! Nearest observed point for many query points (kiddo k-d tree, rayon).

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

/// Distance from each of `queries` to the nearest of `points`
/// (`f32::INFINITY` when there are no finite points). Non-finite points are
/// ignored; a non-finite query gets `f32::INFINITY`.
pub fn nearest_distances(queries: &[[f32; 3]], points: &[[f32; 3]]) -> Vec<f32> {
    nearest_indices(queries, points)
        .into_iter()
        .map(|n| n.map_or(f32::INFINITY, |(_, d)| d))
        .collect()
}

/// The index into `points` of the nearest one to each of `queries`, and its
/// distance; None for a non-finite query or when no point is finite.
pub fn nearest_indices(queries: &[[f32; 3]], points: &[[f32; 3]]) -> Vec<Option<(usize, f32)>> {
    let (finite, index): (Vec<[f32; 3]>, Vec<usize>) = points
        .iter()
        .enumerate()
        .filter(|(_, p)| p.iter().all(|v| v.is_finite()))
        .map(|(i, p)| (*p, i))
        .unzip();
    let tree = if finite.is_empty() {
        None
    } else {
        ImmutableKdTree::<f32, 3>::new_from_slice(&finite).ok()
    };
    let Some(tree) = tree else {
        return vec![None; queries.len()];
    };
    queries
        .par_iter()
        .map(|q| {
            if !q.iter().all(|v| v.is_finite()) {
                return None;
            }
            let hit = tree
                .query(q)
                .nearest_one::<SquaredEuclidean<f32>>()
                .execute();
            Some((index[hit.item as usize], hit.distance.sqrt()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duplicates_empty_and_non_finite() {
        let same = vec![[1.0f32, 2.0, 3.0]; 10_000];
        let d = nearest_distances(&[[1.0, 2.0, 4.0], [f32::NAN, 0.0, 0.0]], &same);
        assert_eq!(d[0], 1.0);
        assert!(d[1].is_infinite());
        let d = nearest_distances(&[[0.0; 3]], &[[f32::NAN, 0.0, 0.0]]);
        assert!(d[0].is_infinite());
        let pts: Vec<[f32; 3]> = (0..1000).map(|i| [i as f32 * 0.5, 0.0, 0.0]).collect();
        let d = nearest_distances(&[[100.2, 0.0, 0.0], [-3.0, 4.0, 0.0]], &pts);
        assert!((d[0] - 0.2).abs() < 1e-4 && (d[1] - 5.0).abs() < 1e-5);
    }
}
