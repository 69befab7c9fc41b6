//! Merging vertices on the snapping grid, as val3dity's snap_tol does.

use std::collections::HashMap;

/// For each vertex, the index of the first vertex in the same cell of the
/// `snap` grid (itself when alone); non-finite vertices stay alone.
pub(super) fn merge(vertices: &[[f64; 3]], snap: f64) -> Vec<usize> {
    let mut first: HashMap<[i64; 3], usize> = HashMap::with_capacity(vertices.len());
    vertices
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if !p.iter().all(|c| c.is_finite()) {
                return i;
            }
            let key = if snap > 0.0 && snap.is_finite() {
                // `as` saturates: only coordinates beyond 9e15 cells share a cell by accident.
                p.map(|c| (c / snap).round() as i64)
            } else {
                // No tolerance: only equal positions are one vertex (+0 and -0 included).
                p.map(|c| (c + 0.0).to_bits() as i64)
            };
            *first.entry(key).or_insert(i)
        })
        .collect()
}
