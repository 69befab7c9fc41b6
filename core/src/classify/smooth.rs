//! Neighbourhood smoothing of the forest's votes: a point takes the class
//! its neighbours vote for together. Single points of a roof that look like
//! foliage (a chimney, a dormer edge) or of a crown that look like a roof
//! (a flat top) follow the object around them.

use std::num::NonZeroUsize;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

/// Averages each row of `proba` (`classes` columns per point of `xyz`)
/// with its `k` nearest neighbours' rows (itself included), within
/// `radius` metres.
pub fn smooth_votes(
    xyz: &[[f32; 3]],
    proba: &[f32],
    classes: usize,
    k: usize,
    radius: f32,
) -> Vec<f32> {
    if k < 2 || classes == 0 || xyz.len() * classes != proba.len() {
        return proba.to_vec();
    }
    let Ok(tree) = ImmutableKdTree::<f32, 3>::new_from_slice(xyz) else {
        return proba.to_vec();
    };
    let n = NonZeroUsize::new(k.min(xyz.len())).unwrap_or(NonZeroUsize::MIN);
    let r2 = radius * radius;
    let mut out = vec![0.0f32; proba.len()];
    out.par_chunks_mut(classes)
        .zip(xyz.par_iter())
        .for_each(|(acc, p)| {
            let near = tree
                .query(p)
                .nearest_n::<SquaredEuclidean<f32>>(n)
                .execute();
            let mut w = 0.0f32;
            for nb in near.iter().filter(|nb| nb.distance <= r2) {
                let row = nb.item as usize * classes;
                for (a, v) in acc.iter_mut().zip(&proba[row..row + classes]) {
                    *a += v;
                }
                w += 1.0;
            }
            if w > 0.0 {
                acc.iter_mut().for_each(|a| *a /= w);
            }
        });
    out
}

/// Index of the largest value of each `classes`-wide row.
pub fn argmax_rows(proba: &[f32], classes: usize) -> Vec<usize> {
    proba
        .chunks(classes.max(1))
        .map(|p| {
            (0..p.len())
                .max_by(|&a, &b| p[a].total_cmp(&p[b]))
                .unwrap_or(0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lone_dissenting_vote_follows_its_neighbours() {
        // Nine points in a row, the middle one voting the other way.
        let xyz: Vec<[f32; 3]> = (0..9).map(|i| [i as f32 * 0.3, 0.0, 0.0]).collect();
        let mut proba = Vec::new();
        for i in 0..9 {
            proba.extend(if i == 4 { [0.8, 0.2] } else { [0.1, 0.9] });
        }
        assert_eq!(argmax_rows(&proba, 2)[4], 0);
        let s = smooth_votes(&xyz, &proba, 2, 5, 1.0);
        assert_eq!(argmax_rows(&s, 2), vec![1; 9]);
        // Out of reach, nothing is averaged.
        let s = smooth_votes(&xyz, &proba, 2, 5, 0.1);
        assert_eq!(s, proba);
    }
}
