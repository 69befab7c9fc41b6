//! A 2D square-cell frame over xy: cell keys and their flat indices.

/// Square cells of side `cell` covering `[x0, x0 + nx·cell) × [y0, y0 + ny·cell)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridFrame {
    /// Lower-left corner x, metres.
    pub x0: f32,
    /// Lower-left corner y, metres.
    pub y0: f32,
    /// Cell side, metres.
    pub cell: f32,
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
}

impl GridFrame {
    /// The frame of cells `cell` wide covering `lo..=hi`, with `pad` cells of margin on each side.
    pub fn covering(lo: [f32; 2], hi: [f32; 2], cell: f32, pad: usize) -> Self {
        let p = pad as f32 * cell;
        let nx = (((hi[0] - lo[0] + 2.0 * p) / cell).floor() as usize) + 1;
        let ny = (((hi[1] - lo[1] + 2.0 * p) / cell).floor() as usize) + 1;
        Self {
            x0: lo[0] - p,
            y0: lo[1] - p,
            cell,
            nx,
            ny,
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Signed cell coordinates of `xy` (may lie outside the frame).
    pub fn key(&self, x: f32, y: f32) -> (i64, i64) {
        (
            ((x - self.x0) / self.cell).floor() as i64,
            ((y - self.y0) / self.cell).floor() as i64,
        )
    }

    /// Flat index of cell `(i, j)`, `None` outside the frame.
    pub fn index(&self, i: i64, j: i64) -> Option<usize> {
        let inside = i >= 0 && j >= 0 && (i as usize) < self.nx && (j as usize) < self.ny;
        inside.then(|| j as usize * self.nx + i as usize)
    }

    /// Flat index of the cell holding `xy`, `None` outside the frame.
    pub fn index_of(&self, x: f32, y: f32) -> Option<usize> {
        let (i, j) = self.key(x, y);
        self.index(i, j)
    }
}
