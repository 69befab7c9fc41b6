//! One 2D grid frame over xy (origin, square cell, dimensions, index ↔
//! world) and the morphology the occupancy rasters share; its tiled
//! storage is [`super::tiled`].

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

    /// Signed cell coordinates of world `(x, y)`, which may lie off the grid.
    pub fn key(&self, x: f64, y: f64) -> (i64, i64) {
        (
            ((x - self.origin[0]) / self.cell).floor() as i64,
            ((y - self.origin[1]) / self.cell).floor() as i64,
        )
    }

    /// Flat index of cell `(i, j)`, `None` off the grid.
    pub fn index(&self, i: i64, j: i64) -> Option<usize> {
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

    /// World xy of the centre of the cell with flat index `k`.
    pub fn centre(&self, k: usize) -> [f64; 2] {
        self.corner((k % self.nx) as f64 + 0.5, (k / self.nx) as f64 + 0.5)
    }

    /// Flat index of the cell holding `(x, y)`, `None` off the grid.
    pub fn index_of(&self, x: f64, y: f64) -> Option<usize> {
        self.cell_of(x, y).map(|(i, j)| j * self.nx + i)
    }

    /// Flat index of the cell holding `(x, y)`, clamped onto the grid (the
    /// cell whose centre is nearest, for points off the grid too).
    pub fn clamped_index(&self, x: f64, y: f64) -> usize {
        let (i, j) = self.clamped_cell(x, y);
        j * self.nx + i
    }

    /// The 4-neighbours of the cell with flat index `k`.
    pub fn neighbours(&self, k: usize) -> impl Iterator<Item = usize> + use<> {
        let (nx, ny) = (self.nx, self.ny);
        let (i, j) = (k % nx, k / nx);
        [
            (i > 0).then(|| k - 1),
            (i + 1 < nx).then(|| k + 1),
            (j > 0).then(|| k - nx),
            (j + 1 < ny).then(|| k + nx),
        ]
        .into_iter()
        .flatten()
    }

    /// Bilinear interpolation at `(x, y)` of `values` (one per cell, taken
    /// at the cell centres), clamped to the outermost centres; NaN for a
    /// NaN coordinate or when `values` does not match the grid.
    pub fn bilinear(&self, values: &[f32], x: f64, y: f64) -> f32 {
        if self.is_empty() || values.len() != self.len() || x.is_nan() || y.is_nan() {
            return f32::NAN;
        }
        let at = |v: f64, o: f64, n: usize| {
            let t = ((v - o) / self.cell - 0.5).clamp(0.0, (n - 1) as f64);
            let i = t.floor();
            (i as usize, (t - i) as f32)
        };
        let (i0, fx) = at(x, self.origin[0], self.nx);
        let (j0, fy) = at(y, self.origin[1], self.ny);
        let i1 = (i0 + 1).min(self.nx - 1);
        let j1 = (j0 + 1).min(self.ny - 1);
        let v = |i: usize, j: usize| values[j * self.nx + i];
        let bottom = v(i0, j0) + fx * (v(i1, j0) - v(i0, j0));
        let top = v(i0, j1) + fx * (v(i1, j1) - v(i0, j1));
        bottom + fy * (top - bottom)
    }
}

/// Per-cell means of `value` over `points` (xy → cell; points off the
/// grid are skipped); NaN where a cell has none.
pub fn cell_means(frame: &GridFrame, points: impl Iterator<Item = ([f64; 2], f32)>) -> Vec<f32> {
    let mut sum = vec![0.0f64; frame.len()];
    let mut n = vec![0u32; frame.len()];
    for (xy, v) in points {
        if let Some(k) = frame.index_of(xy[0], xy[1]) {
            sum[k] += f64::from(v);
            n[k] += 1;
        }
    }
    sum.iter()
        .zip(&n)
        .map(|(&s, &c)| {
            if c > 0 {
                (s / f64::from(c)) as f32
            } else {
                f32::NAN
            }
        })
        .collect()
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

/// Which neighbours a cell has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Neighbours {
    /// Left, right, below, above.
    Four,
    /// The four, then the diagonals.
    Eight,
}

impl Neighbours {
    /// The cell offsets `(di, dj)` of these neighbours.
    pub fn offsets(self) -> &'static [(isize, isize)] {
        const EIGHT: [(isize, isize); 8] = [
            (-1, 0),
            (1, 0),
            (0, -1),
            (0, 1),
            (-1, -1),
            (1, 1),
            (-1, 1),
            (1, -1),
        ];
        match self {
            Neighbours::Four => &EIGHT[..4],
            Neighbours::Eight => &EIGHT,
        }
    }
}

/// Fills unknown (NaN) cells of a row-major `nx × ny` height grid from their
/// known `neighbours`' mean, `steps` rings deep (each ring from the last).
pub fn fill_holes(z: &mut [f32], nx: usize, ny: usize, steps: usize, neighbours: Neighbours) {
    let (w, h) = (nx as i64, ny as i64);
    fill_holes_with(
        z,
        steps,
        neighbours,
        |k| Some(((k % nx) as i64, (k / nx) as i64)),
        |i, j| (i >= 0 && j >= 0 && i < w && j < h).then(|| (j * w + i) as usize),
    );
}

/// [`fill_holes`] on any grid storage: `cell_of(k)` is slot `k`'s cell (or
/// `None` for a slot that is no cell), `index(i, j)` a cell's slot.
pub fn fill_holes_with(
    z: &mut [f32],
    steps: usize,
    neighbours: Neighbours,
    cell_of: impl Fn(usize) -> Option<(i64, i64)>,
    index: impl Fn(i64, i64) -> Option<usize>,
) {
    for _ in 0..steps {
        let prev = z.to_vec();
        let mut changed = false;
        for k in 0..prev.len() {
            if prev[k].is_finite() {
                continue;
            }
            let Some((i, j)) = cell_of(k) else {
                continue;
            };
            let (mut s, mut c) = (0.0f32, 0u32);
            for &(di, dj) in neighbours.offsets() {
                if let Some(q) = index(i + di as i64, j + dj as i64)
                    && prev[q].is_finite()
                {
                    s += prev[q];
                    c += 1;
                }
            }
            if c > 0 {
                z[k] = s / c as f32;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
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

    #[test]
    fn holes_fill_ring_by_ring() {
        let nan = f32::NAN;
        let mut z = vec![1.0, nan, nan, nan, 3.0, nan];
        fill_holes(&mut z, 3, 2, 1, Neighbours::Four);
        // Row 0: 1 ? ?, row 1: ? 3 ?: one ring reaches all but the far corner.
        assert_eq!((z[1], z[3], z[5]), (2.0, 2.0, 3.0));
        assert!(z[2].is_nan());
        fill_holes(&mut z, 3, 2, 5, Neighbours::Four);
        assert_eq!(z[2], 2.5);
        // With diagonals one ring reaches the far corner, from the 3 beside it.
        let mut z = vec![1.0, nan, nan, nan, 3.0, nan];
        fill_holes(&mut z, 3, 2, 1, Neighbours::Eight);
        assert_eq!((z[1], z[2], z[5]), (2.0, 3.0, 3.0));
    }
}
