//! An occupancy grid over xy: which cells a set of points covers, made robust
//! to uneven density by a morphological closing, and split into 4-connected
//! components.

/// Boolean grid of square cells; cell (i, j) spans
/// `[origin + (i, j) * cell, origin + (i + 1, j + 1) * cell)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Raster {
    /// World xy of the grid's lower-left corner.
    pub origin: [f64; 2],
    /// Cell edge length, metres.
    pub cell: f64,
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
    /// Row-major occupancy (`j * nx + i`).
    pub occupied: Vec<bool>,
}

impl Raster {
    /// An empty grid covering `lo..hi` with `pad` free cells on every side
    /// (so boundaries never touch the grid edge).
    pub fn covering(lo: [f64; 2], hi: [f64; 2], cell: f64, pad: usize) -> Self {
        let cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            1.0
        };
        let span = |a: f64, b: f64| (((b - a) / cell).floor().max(0.0) as usize) + 1 + 2 * pad;
        let nx = span(lo[0], hi[0]);
        let ny = span(lo[1], hi[1]);
        Raster {
            origin: [lo[0] - pad as f64 * cell, lo[1] - pad as f64 * cell],
            cell,
            nx,
            ny,
            occupied: vec![false; nx * ny],
        }
    }

    /// Cell indices of a world point, if it lies on the grid.
    pub fn cell_of(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        let i = ((x - self.origin[0]) / self.cell).floor();
        let j = ((y - self.origin[1]) / self.cell).floor();
        if i >= 0.0 && j >= 0.0 && (i as usize) < self.nx && (j as usize) < self.ny {
            Some((i as usize, j as usize))
        } else {
            None
        }
    }

    /// Whether cell (i, j) is occupied (false off the grid).
    pub fn get(&self, i: isize, j: isize) -> bool {
        i >= 0
            && j >= 0
            && (i as usize) < self.nx
            && (j as usize) < self.ny
            && self.occupied[j as usize * self.nx + i as usize]
    }

    /// Number of occupied cells.
    pub fn count(&self) -> usize {
        self.occupied.iter().filter(|&&o| o).count()
    }

    /// Dilation then erosion by a (2r+1)² square: bridges gaps of up to 2r
    /// cells left by sparse or uneven sampling without moving straight edges.
    pub fn close(&mut self, r: usize) {
        if r == 0 {
            return;
        }
        self.occupied = square_filter(&self.occupied, self.nx, self.ny, r, true);
        self.occupied = square_filter(&self.occupied, self.nx, self.ny, r, false);
    }

    /// 4-connected components: a label per cell (`u32::MAX` = free) and each
    /// component's cell count.
    pub fn components(&self) -> (Vec<u32>, Vec<usize>) {
        let mut label = vec![u32::MAX; self.occupied.len()];
        let mut sizes = Vec::new();
        let mut stack = Vec::new();
        for start in 0..self.occupied.len() {
            if !self.occupied[start] || label[start] != u32::MAX {
                continue;
            }
            let id = sizes.len() as u32;
            let mut size = 0;
            label[start] = id;
            stack.push(start);
            while let Some(k) = stack.pop() {
                size += 1;
                let (i, j) = (k % self.nx, k / self.nx);
                let mut visit = |n: usize| {
                    if self.occupied[n] && label[n] == u32::MAX {
                        label[n] = id;
                        stack.push(n);
                    }
                };
                if i > 0 {
                    visit(k - 1);
                }
                if i + 1 < self.nx {
                    visit(k + 1);
                }
                if j > 0 {
                    visit(k - self.nx);
                }
                if j + 1 < self.ny {
                    visit(k + self.nx);
                }
            }
            sizes.push(size);
        }
        (label, sizes)
    }
}

/// Separable square max (dilate) or min (erode) filter; off-grid cells count
/// as free, so erosion never grows a shape into the padding.
fn square_filter(src: &[bool], nx: usize, ny: usize, r: usize, dilate: bool) -> Vec<bool> {
    let pass = |src: &[bool], along_x: bool| -> Vec<bool> {
        let mut out = vec![false; src.len()];
        for j in 0..ny {
            for i in 0..nx {
                let (pos, len) = if along_x { (i, nx) } else { (j, ny) };
                let lo = pos.saturating_sub(r);
                let hi = (pos + r).min(len - 1);
                let edge_cut = pos < r || pos + r >= len;
                let at = |p: usize| {
                    if along_x {
                        src[j * nx + p]
                    } else {
                        src[p * nx + i]
                    }
                };
                out[j * nx + i] = if dilate {
                    (lo..=hi).any(at)
                } else {
                    !edge_cut && (lo..=hi).all(at)
                };
            }
        }
        out
    };
    let once = pass(src, true);
    pass(&once, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closing_bridges_gaps_and_keeps_edges() {
        let mut r = Raster::covering([0.0, 0.0], [9.0, 9.0], 1.0, 3);
        for j in 0..10 {
            for i in 0..10 {
                if (i + j) % 3 != 1 {
                    let (a, b) = r.cell_of(i as f64 + 0.5, j as f64 + 0.5).unwrap();
                    r.occupied[b * r.nx + a] = true;
                }
            }
        }
        r.close(1);
        // every cell of the 10 × 10 square is filled, nothing outside it
        assert_eq!(r.count(), 100);
        let (labels, sizes) = r.components();
        assert_eq!(sizes, vec![100]);
        assert_eq!(labels.iter().filter(|&&l| l == 0).count(), 100);
    }
}
