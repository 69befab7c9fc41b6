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
}

/// The cells of a [`GridFrame`] stored in square tiles only where wanted
/// (where there is ground, and a ring of tiles around it): memory grows with
/// the area that matters, not with the bounding box. Stored cells have flat
/// indices `0..len()`; cells in tiles not stored have none.
#[derive(Debug, Clone)]
pub struct TiledFrame {
    /// The whole grid (the bounding box).
    pub frame: GridFrame,
    /// Cells per tile side.
    tile: usize,
    /// Tiles along x and y.
    tiles: [usize; 2],
    /// For each tile, its slot in storage (u32::MAX: not stored).
    slot: Vec<u32>,
    /// For each slot, its tile.
    tile_of: Vec<u32>,
}

impl TiledFrame {
    /// Stores every tile holding one of `cells` (keys `(i, j)` of `frame`)
    /// and the `ring` tiles around each.
    pub fn around(
        frame: GridFrame,
        tile: usize,
        cells: impl IntoIterator<Item = (i64, i64)>,
        ring: i64,
    ) -> Self {
        let tile = tile.max(1);
        let tiles = [frame.nx.div_ceil(tile), frame.ny.div_ceil(tile)];
        let mut want = vec![false; tiles[0] * tiles[1]];
        for (i, j) in cells {
            let (ti, tj) = (i.div_euclid(tile as i64), j.div_euclid(tile as i64));
            for b in tj - ring..=tj + ring {
                for a in ti - ring..=ti + ring {
                    if a >= 0 && b >= 0 && (a as usize) < tiles[0] && (b as usize) < tiles[1] {
                        want[b as usize * tiles[0] + a as usize] = true;
                    }
                }
            }
        }
        let mut tile_of = Vec::new();
        let slot = want
            .iter()
            .enumerate()
            .map(|(t, &w)| {
                if w {
                    tile_of.push(t as u32);
                    tile_of.len() as u32 - 1
                } else {
                    u32::MAX
                }
            })
            .collect();
        Self {
            frame,
            tile,
            tiles,
            slot,
            tile_of,
        }
    }

    /// Number of stored cells.
    pub fn len(&self) -> usize {
        self.tile_of.len() * self.tile * self.tile
    }

    /// Storage index of cell `(i, j)`; `None` outside the frame or in a tile not stored.
    pub fn index(&self, i: i64, j: i64) -> Option<usize> {
        self.frame.index(i, j)?;
        let (i, j, t) = (i as usize, j as usize, self.tile);
        let s = self.slot[(j / t) * self.tiles[0] + i / t];
        (s != u32::MAX).then(|| (s as usize * t + j % t) * t + i % t)
    }

    /// Storage index of the cell holding `xy`.
    pub fn index_of(&self, x: f32, y: f32) -> Option<usize> {
        let (i, j) = self.frame.key(x, y);
        self.index(i, j)
    }

    /// The cell `(i, j)` stored at index `k` (`k < len()`); it may lie
    /// beyond the frame's last row or column where a tile overhangs it.
    pub fn cell(&self, k: usize) -> (i64, i64) {
        let t = self.tile;
        let tile = self.tile_of[k / (t * t)] as usize;
        let (ti, tj) = (tile % self.tiles[0], tile / self.tiles[0]);
        let r = k % (t * t);
        ((ti * t + r % t) as i64, (tj * t + r / t) as i64)
    }

    /// Centre (xy) of the cell stored at `k`.
    pub fn centre(&self, k: usize) -> [f32; 2] {
        let (i, j) = self.cell(k);
        let f = &self.frame;
        [
            f.x0 + (i as f32 + 0.5) * f.cell,
            f.y0 + (j as f32 + 0.5) * f.cell,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_are_stored_around_the_given_cells_only() {
        let frame = GridFrame::covering([0.0, 0.0], [99.9, 99.9], 1.0, 0);
        let t = TiledFrame::around(frame, 10, [(5, 5), (95, 95)], 1);
        // Two corners: 2 × 2 tiles each (the ring is cut at the edge).
        assert_eq!(t.len(), 8 * 100);
        for k in 0..t.len() {
            let (i, j) = t.cell(k);
            assert_eq!(t.index(i, j), Some(k));
        }
        assert!(t.index(5, 5).is_some() && t.index(19, 19).is_some());
        assert_eq!(t.index(50, 50), None);
        assert_eq!(t.index(-1, 5), None);
        assert_eq!(t.index_of(95.5, 95.5), t.index(95, 95));
        let c = t.centre(t.index(95, 95).unwrap());
        assert_eq!(c, [95.5, 95.5]);
    }
}
