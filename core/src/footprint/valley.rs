//! Valleys between roofs: the gutter where two pitched roofs of a row meet
//! is a line of cells lower than the roof on both sides. Such cells are set
//! aside while components are formed (so the row falls apart at its party
//! walls) and then given back to the part beside them.

use std::collections::VecDeque;

use crate::geom::grid;

/// The occupancy raster the valley test reads: `nx × ny` cells, row-major,
/// whether each holds points and its highest point, m.
pub struct Heights<'a> {
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
    /// Whether each cell holds points.
    pub filled: &'a [bool],
    /// Each cell's highest point, m.
    pub top: &'a [f32],
}

/// Cells on either side that the valley test looks at: a gutter between
/// two cells has its roofs rising only from the second cell out.
const SPAN: usize = 2;

/// The cells lying in a valley: lower by more than `depth` (m) than the
/// occupied cells `SPAN` away on both sides along x or along y, then grown
/// by `dilate` cells (a square) to bridge gaps in a noisy gutter line.
/// Empty when `depth` ≤ 0.
pub fn barrier(r: &Heights, depth: f64, dilate: usize) -> Vec<bool> {
    let (nx, ny) = (r.nx, r.ny);
    let mut out = vec![false; nx * ny];
    if depth <= 0.0 {
        return out;
    }
    let rise =
        |k: usize, n: usize| r.filled[n] && f64::from(r.top[n]) - f64::from(r.top[k]) > depth;
    for j in SPAN..ny.saturating_sub(SPAN) {
        for i in SPAN..nx.saturating_sub(SPAN) {
            let k = j * nx + i;
            if !r.filled[k] {
                continue;
            }
            let along_x = rise(k, k - SPAN) && rise(k, k + SPAN);
            let along_y = rise(k, k - SPAN * nx) && rise(k, k + SPAN * nx);
            out[k] = along_x || along_y;
        }
    }
    if dilate > 0 {
        out = grid::square_filter(&out, nx, ny, dilate, true);
        for (b, f) in out.iter_mut().zip(r.filled) {
            *b &= *f;
        }
    }
    out
}

/// Joins each barrier cell to the part nearest it (breadth first from the
/// parts' cells, 4-connected); barrier cells no part reaches join each
/// other. `join(a, b)` puts cells `a` and `b` in one part.
pub fn absorb(r: &Heights, barrier: &[bool], mut join: impl FnMut(usize, usize)) {
    let nx = r.nx;
    let mut done: Vec<bool> = barrier.iter().map(|b| !b).collect();
    let mut queue: VecDeque<usize> = (0..barrier.len())
        .filter(|&k| r.filled[k] && !barrier[k])
        .collect();
    while let Some(k) = queue.pop_front() {
        for n in neighbours(k, nx, barrier.len()) {
            if r.filled[n] && !done[n] {
                done[n] = true;
                join(k, n);
                queue.push_back(n);
            }
        }
    }
    for k in (0..barrier.len()).filter(|&k| !done[k] && r.filled[k]) {
        for n in neighbours(k, nx, barrier.len()) {
            if !done[n] && r.filled[n] {
                join(k, n);
            }
        }
    }
}

/// The 4-neighbours of cell `k` that exist (the raster is padded, so row
/// wrap-around never joins occupied cells).
fn neighbours(k: usize, nx: usize, len: usize) -> impl Iterator<Item = usize> {
    [
        k.checked_sub(1),
        Some(k + 1).filter(|&n| n < len),
        k.checked_sub(nx),
        Some(k + nx).filter(|&n| n < len),
    ]
    .into_iter()
    .flatten()
}
