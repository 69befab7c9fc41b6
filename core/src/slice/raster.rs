//! An occupancy grid over xy: which cells a set of points covers, made robust
//! to uneven density by a morphological closing, and split into 4-connected
//! components.

use crate::geom::grid::{self, GridFrame};

/// Boolean grid over a [`GridFrame`].
#[derive(Debug, Clone, PartialEq)]
pub struct Raster {
    /// The cells' frame.
    pub frame: GridFrame,
    /// Row-major occupancy (`j * nx + i`).
    pub occupied: Vec<bool>,
}

/// The frame's fields read through the raster (`raster.nx`, `raster.cell`),
/// as the detector's callers always have.
impl std::ops::Deref for Raster {
    type Target = GridFrame;

    fn deref(&self) -> &GridFrame {
        &self.frame
    }
}

impl Raster {
    /// An empty grid covering `lo..hi` with `pad` free cells on every side
    /// (so boundaries never touch the grid edge).
    pub fn covering(lo: [f64; 2], hi: [f64; 2], cell: f64, pad: usize) -> Self {
        let frame = GridFrame::covering(lo, hi, cell, pad);
        Raster {
            frame,
            occupied: vec![false; frame.len()],
        }
    }

    /// Cell indices of a world point, if it lies on the grid.
    pub fn cell_of(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        self.frame.cell_of(x, y)
    }

    /// Whether cell (i, j) is occupied (false off the grid).
    pub fn get(&self, i: isize, j: isize) -> bool {
        self.frame
            .index(i as i64, j as i64)
            .is_some_and(|k| self.occupied[k])
    }

    /// Number of occupied cells.
    pub fn count(&self) -> usize {
        self.occupied.iter().filter(|&&o| o).count()
    }

    /// Dilation then erosion by a (2r+1)² square: bridges gaps of up to 2r
    /// cells left by sparse or uneven sampling without moving straight edges.
    pub fn close(&mut self, r: usize) {
        self.occupied = grid::close(&self.occupied, self.frame.nx, self.frame.ny, r);
    }

    /// 4-connected components: a label per cell (`u32::MAX` = free) and each
    /// component's cell count.
    pub fn components(&self) -> (Vec<u32>, Vec<usize>) {
        let nx = self.frame.nx;
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
                let (i, j) = (k % nx, k / nx);
                let mut visit = |n: usize| {
                    if self.occupied[n] && label[n] == u32::MAX {
                        label[n] = id;
                        stack.push(n);
                    }
                };
                if i > 0 {
                    visit(k - 1);
                }
                if i + 1 < nx {
                    visit(k + 1);
                }
                if j > 0 {
                    visit(k - nx);
                }
                if j + 1 < self.frame.ny {
                    visit(k + nx);
                }
            }
            sizes.push(size);
        }
        (label, sizes)
    }
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
                    r.occupied[b * r.frame.nx + a] = true;
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
