//! A [`GridFrame`]'s cells stored in square tiles only where wanted: memory
//! grows with the area that matters, not with the bounding box.

use super::grid::GridFrame;

/// The cells of a [`GridFrame`] stored in square tiles only where wanted
/// (where there is ground, and a ring of tiles around it). Stored cells have
/// flat indices `0..len()`; cells in tiles not stored have none.
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

    /// Whether no cell is stored.
    pub fn is_empty(&self) -> bool {
        self.tile_of.is_empty()
    }

    /// Storage index of cell `(i, j)`; `None` outside the frame or in a tile not stored.
    pub fn index(&self, i: i64, j: i64) -> Option<usize> {
        self.frame.index(i, j)?;
        let (i, j, t) = (i as usize, j as usize, self.tile);
        let s = self.slot[(j / t) * self.tiles[0] + i / t];
        (s != u32::MAX).then(|| (s as usize * t + j % t) * t + i % t)
    }

    /// Storage index of the cell holding world `(x, y)`.
    pub fn index_of(&self, x: f64, y: f64) -> Option<usize> {
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

    /// World xy of the centre of the cell stored at `k`.
    pub fn centre(&self, k: usize) -> [f64; 2] {
        let (i, j) = self.cell(k);
        self.frame.corner(i as f64 + 0.5, j as f64 + 0.5)
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
