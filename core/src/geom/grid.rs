//! One 2D grid frame over xy (origin, square cell, dimensions, index ↔
//! world) and the morphology the occupancy rasters share.

/// Square cells of side `cell`; cell `(i, j)` spans
/// `[origin + (i, j) · cell, origin + (i + 1, j + 1) · cell)`, row-major
/// (`j · nx + i`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridFrame {
    /// World xy of cell (0, 0)'s lower-left corner.
    pub origin: [f64; 2],
    /// Cell edge length, metres.
    pub cell: f64,
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
}

impl GridFrame {
    /// The frame of `cell`-wide cells covering `lo..=hi` with `pad` cells of
    /// margin on every side (a non-positive or non-finite cell becomes 1 m).
    pub fn covering(lo: [f64; 2], hi: [f64; 2], cell: f64, pad: usize) -> Self {
        let cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            1.0
        };
        let span = |a: f64, b: f64| (((b - a) / cell).floor().max(0.0) as usize) + 1 + 2 * pad;
        let margin = pad as f64 * cell;
        Self {
            origin: [lo[0] - margin, lo[1] - margin],
            cell,
            nx: span(lo[0], hi[0]),
            ny: span(lo[1], hi[1]),
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Whether the frame has no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Cell `(i, j)` holding world `(x, y)`, `None` off the grid.
    pub fn cell_of(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        let i = ((x - self.origin[0]) / self.cell).floor();
        let j = ((y - self.origin[1]) / self.cell).floor();
        let inside = i >= 0.0 && j >= 0.0 && (i as usize) < self.nx && (j as usize) < self.ny;
        inside.then_some((i as usize, j as usize))
    }

    /// Cell `(i, j)` holding world `(x, y)`, clamped onto the grid.
    pub fn clamped_cell(&self, x: f64, y: f64) -> (usize, usize) {
        let at = |v: f64, o: f64, n: usize| (((v - o) / self.cell).max(0.0) as usize).min(n - 1);
        (
            at(x, self.origin[0], self.nx),
            at(y, self.origin[1], self.ny),
        )
    }

    /// Flat index of cell `(i, j)`, `None` off the grid.
    pub fn index(&self, i: isize, j: isize) -> Option<usize> {
        let inside = i >= 0 && j >= 0 && (i as usize) < self.nx && (j as usize) < self.ny;
        inside.then(|| j as usize * self.nx + i as usize)
    }

    /// World xy of grid vertex `(i, j)` (a cell corner).
    pub fn corner(&self, i: f64, j: f64) -> [f64; 2] {
        [
            self.origin[0] + i * self.cell,
            self.origin[1] + j * self.cell,
        ]
    }
}

/// Separable square max (`dilate`) or min filter of radius `r` over a
/// row-major `nx × ny` mask; off-grid cells count as free, so erosion never
/// grows a shape into the padding.
pub fn square_filter(src: &[bool], nx: usize, ny: usize, r: usize, dilate: bool) -> Vec<bool> {
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

/// Morphological closing (dilation then erosion by a (2r+1)² square): bridges
/// gaps of up to 2r cells without moving straight edges.
pub fn close(src: &[bool], nx: usize, ny: usize, r: usize) -> Vec<bool> {
    if r == 0 {
        return src.to_vec();
    }
    let grown = square_filter(src, nx, ny, r, true);
    square_filter(&grown, nx, ny, r, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_indices_and_closing() {
        let f = GridFrame::covering([10.0, 20.0], [14.5, 21.0], 1.0, 2);
        assert_eq!((f.origin, f.nx, f.ny), ([8.0, 18.0], 9, 6));
        assert_eq!(f.cell_of(10.2, 20.9), Some((2, 2)));
        assert_eq!(f.cell_of(7.9, 20.0), None);
        assert_eq!(f.clamped_cell(-100.0, 100.0), (0, 5));
        assert_eq!(f.index(8, 5), Some(53));
        assert_eq!(f.index(9, 0), None);
        assert_eq!(f.corner(2.0, 3.0), [10.0, 21.0]);
        assert_eq!(
            GridFrame::covering([0.0; 2], [1.0; 2], f64::NAN, 0).cell,
            1.0
        );
        // A one-cell gap in a 5-cell bar closes; the bar's ends do not move.
        let (nx, ny) = (9, 3);
        let mut m = vec![false; nx * ny];
        for i in [2, 3, 5, 6] {
            m[nx + i] = true;
        }
        let c = close(&m, nx, ny, 1);
        let row: Vec<usize> = (0..nx).filter(|&i| c[nx + i]).collect();
        assert_eq!(row, vec![2, 3, 4, 5, 6]);
        assert_eq!(c.iter().filter(|&&v| v).count(), 5);
    }
}
