//! The inverted surface under each cloth particle: the height (z → −z) of
//! the point nearest to it in xy, gaps filled from the nearest particle
//! along the grid that has one.

use std::collections::VecDeque;

use rayon::prelude::*;

use crate::geom::grid::GridFrame;

/// Inverted height of the surface below every particle (one per particle).
///
/// `points` are all finite. A particle with fewer than `min_points` points
/// nearer to it than to any other particle sits over a data void (no
/// returns, water that returns a few, the margin around the cloud): it
/// takes the value of the nearest particle along the grid that has enough
/// (breadth-first, 4-neighbours), as the paper does for empty particles, so
/// a void holds the cloth at its surroundings' height and a few stray low
/// returns in it do not pull the cloth down to them.
pub(crate) fn inverted_surface(
    lattice: &GridFrame,
    points: &[[f32; 3]],
    min_points: u32,
) -> Vec<f32> {
    let keyed: Vec<(usize, f32, f32)> = points
        .par_iter()
        .map(|p| {
            let k = lattice.clamped_index(f64::from(p[0]), f64::from(p[1]));
            let c = lattice.centre(k).map(|v| v as f32);
            let d2 = (p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2);
            (k, d2, -p[2])
        })
        .collect();
    let mut best = vec![(f32::INFINITY, f32::NAN); lattice.len()];
    let mut count = vec![0u32; lattice.len()];
    for &(k, d2, z) in &keyed {
        count[k] += 1;
        if d2 < best[k].0 {
            best[k] = (d2, z);
        }
    }
    // Nothing dense enough to fill the rest from: trust every point.
    let min = if count.iter().any(|&c| c >= min_points) {
        min_points.max(1)
    } else {
        1
    };
    let mut height: Vec<f32> = best
        .into_iter()
        .zip(&count)
        .map(|((_, z), &c)| if c >= min { z } else { f32::NAN })
        .collect();
    fill_from_neighbours(lattice, &mut height);
    height
}

/// Replaces NaN entries by the value of the nearest (grid steps) non-NaN
/// entry; leaves all-NaN input unchanged.
fn fill_from_neighbours(lattice: &GridFrame, height: &mut [f32]) {
    let mut queue: VecDeque<usize> = (0..height.len()).filter(|&k| !height[k].is_nan()).collect();
    while let Some(k) = queue.pop_front() {
        let h = height[k];
        for n in lattice.neighbours(k) {
            if height[n].is_nan() {
                height[n] = h;
                queue.push_back(n);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_point_wins_and_gaps_take_neighbours() {
        let l = super::super::grid::covering([0.0, 0.0], [4.0, 0.0], 1.0).unwrap();
        let pts = [[0.1, 0.0, 5.0], [0.4, 0.0, 9.0], [4.0, 0.0, 1.0]];
        let h = inverted_surface(&l, &pts, 1);
        assert_eq!(h[l.clamped_index(0.0, 0.0)], -5.0);
        assert_eq!(h[l.clamped_index(4.0, 0.0)], -1.0);
        // x = 1 is nearer to the particle at 0, x = 3 to the one at 4.
        assert_eq!(h[l.clamped_index(1.0, 0.0)], -5.0);
        assert_eq!(h[l.clamped_index(3.0, 0.0)], -1.0);
        assert!(h.iter().all(|v| v.is_finite()));
        // With two points needed, the lone low return at x = 4 is a void:
        // it takes the height of the particle at 0 (two points).
        let h = inverted_surface(&l, &pts, 2);
        assert_eq!(h[l.clamped_index(4.0, 0.0)], -5.0);
        // Nothing has enough: every point counts.
        let h = inverted_surface(&l, &pts, 10);
        assert_eq!(h[l.clamped_index(4.0, 0.0)], -1.0);
    }
}
