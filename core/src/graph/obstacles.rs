//! The obstacle map: where non-ground points stand between the ground and the
//! vehicle's top, as a 2D grid with the distance to the nearest obstacle, and
//! the ground's height per cell; built once and asked for every edge.

use std::collections::HashMap;

use super::cells::drivable;
use crate::cloud::class;
use crate::geom::grid::GridFrame;
use crate::geom::tiled::TiledFrame;
use crate::vehicle::profile_climbable;

/// Distances saturate here: nothing farther matters to a vehicle, metres.
const FAR: f32 = 8.0;

/// Obstacle-map cells per tile side: 64 × 0.25 m = 16 m, twice the 8 m
/// the distances saturate at, so one ring of tiles around the ground holds
/// every obstacle that matters to it.
const TILE: usize = 64;

/// A 2D grid of obstacle cells and, per cell, the distance to the nearest
/// one, stored in tiles only where there is ground (and one tile around it):
/// memory grows with the drivable area, not with the bounding box.
#[derive(Debug, Clone)]
pub struct ObstacleMap {
    /// The grid, stored in tiles near ground.
    grid: TiledFrame,
    /// Distance from each stored cell centre to the nearest obstacle cell,
    /// metres (capped).
    distance: Vec<f32>,
    /// Number of obstacle cells.
    occupied: usize,
    /// Mean height of the ground points of each stored cell, NaN where it
    /// has none: the relief the edges' slopes are checked against, fine
    /// enough to show a quay wall or a kerb that a node cell averages away.
    ground_z: Vec<f32>,
}

/// Ground heights on the node grid, with gaps (under roofs, crowns) filled
/// from their neighbours so obstacle points there have a ground to stand on.
pub struct GroundHeights<'a> {
    /// The node grid.
    pub grid: &'a TiledFrame,
    /// Height per stored cell, NaN where unknown.
    pub z: &'a [f32],
}

/// What turns a non-ground point into an obstacle.
pub struct Band {
    /// Lowest height above ground that blocks, metres.
    pub low: f32,
    /// Highest height above ground that blocks (the vehicle's top), metres.
    pub high: f32,
    /// Vegetation blocks at any height.
    pub canopy: bool,
    /// With `canopy`: above the height band only a disc of this radius
    /// about each crown's top blocks (the trunk beneath it) instead of the
    /// whole crown; 0 or less: the whole crown.
    pub trunk_radius: f32,
}

/// Crown heights are compared on cells this wide, metres.
const CROWN_CELL: f64 = 0.5;
/// A crown top is the highest crown cell within this radius, metres: one
/// per tree of street-tree size (crowns 4–10 m across).
const CROWN_TOP_RADIUS: f64 = 2.0;
/// Vegetation at least this high above the ground is a crown (lower: a
/// bush, which the height band blocks where it stands), metres.
const CROWN_MIN_HEIGHT: f32 = 2.5;

impl ObstacleMap {
    /// Marks the cells (of side `resolution` over `frame`'s extent) that hold
    /// a blocking non-ground point, then computes the distance field.
    pub fn build(
        xyz: &[[f32; 3]],
        labels: &[u8],
        ground: &GroundHeights<'_>,
        band: &Band,
        resolution: f32,
    ) -> Self {
        let g = &ground.grid.frame;
        let frame = GridFrame::covering(
            g.origin,
            g.corner(g.nx as f64, g.ny as f64),
            f64::from(resolution),
            0,
        );
        // Every node-grid cell with a height, and one ring of tiles around it.
        let with_height = (0..ground.z.len())
            .filter(|&k| ground.z[k].is_finite())
            .map(|k| {
                let c = ground.grid.centre(k);
                frame.key(c[0], c[1])
            });
        let grid = TiledFrame::around(frame, TILE, with_height, 1);
        let stored = grid.len();
        let mut occ = vec![false; stored];
        let mut occupied = 0;
        let mut z_sum = vec![(0.0f64, 0u32); stored];
        let mut crowns = Crowns::default();
        // Crowns block through their tops' trunks, or their whole column, or not at all.
        let trunks = band.canopy && band.trunk_radius > 0.0;
        let whole_crown = band.canopy && !trunks;
        for (p, &l) in xyz.iter().zip(labels) {
            if class::is_noise(l) || !p.iter().all(|v| v.is_finite()) {
                continue;
            }
            let Some(cell) = grid.index_of(f64::from(p[0]), f64::from(p[1])) else {
                continue;
            };
            if drivable(l) {
                let s = &mut z_sum[cell];
                s.0 += f64::from(p[2]);
                s.1 += 1;
                continue;
            }
            let canopy = class::fold(l) == class::VEGETATION && l != class::LOW_VEGETATION;
            let h = ground
                .grid
                .index_of(f64::from(p[0]), f64::from(p[1]))
                .map(|k| p[2] - ground.z[k])
                .filter(|h| h.is_finite());
            if let Some(h) = h.filter(|&h| canopy && trunks && h >= CROWN_MIN_HEIGHT) {
                crowns.add(p, h);
            }
            // No ground known nearby: inside a large roofed area, keep out.
            let blocks =
                (canopy && whole_crown) || h.is_none_or(|h| h >= band.low && h <= band.high);
            if blocks && !occ[cell] {
                occ[cell] = true;
                occupied += 1;
            }
        }
        for top in crowns.tops() {
            occupied += block_disc(&grid, &mut occ, top, band.trunk_radius);
        }
        let distance = tiled_distance(&grid, &occ);
        let ground_z = z_sum
            .iter()
            .map(|&(sum, n)| {
                if n > 0 {
                    (sum / f64::from(n)) as f32
                } else {
                    f32::NAN
                }
            })
            .collect();
        Self {
            grid,
            distance,
            occupied,
            ground_z,
        }
    }

    /// Mean ground height of the cell holding `xy`; NaN where it has no ground point.
    pub fn ground_z(&self, x: f32, y: f32) -> f32 {
        self.grid
            .index_of(f64::from(x), f64::from(y))
            .map_or(f32::NAN, |k| self.ground_z[k])
    }

    /// True when the vehicle's slope rule ([`profile_climbable`]) holds on
    /// the ground along `a → b` (xy), the line continued `overhang` metres
    /// past both ends (the vehicle looks ahead past a way-point it has not
    /// yet reached), driven either way.
    pub fn segment_climbable(&self, a: [f32; 2], b: [f32; 2], max_deg: f32, overhang: f32) -> bool {
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        if len <= 1e-6 {
            return true;
        }
        let dir = [(b[0] - a[0]) / len, (b[1] - a[1]) / len];
        // Half a cell: a diagonal line skips no cell it crosses.
        let step = 0.5 * self.grid.frame.cell as f32;
        let total = len + 2.0 * overhang;
        let n = (total / step).ceil() as usize;
        let z: Vec<f32> = (0..=n)
            .map(|k| {
                let t = (k as f32 * step).min(total) - overhang;
                self.ground_z(a[0] + dir[0] * t, a[1] + dir[1] * t)
            })
            .collect();
        profile_climbable(&z, step, max_deg)
    }

    /// Obstacle-map cells stored (the tiles near ground), and all cells of
    /// the bounding box a dense map would hold.
    pub fn stored_cells(&self) -> (usize, usize) {
        (self.distance.len(), self.grid.frame.len())
    }

    /// Bytes kept: distance and ground height per stored cell.
    pub fn bytes(&self) -> usize {
        self.distance.len() * 4 + self.ground_z.len() * 4
    }

    /// Number of obstacle cells.
    pub fn occupied_cells(&self) -> usize {
        self.occupied
    }

    /// Distance (xy) from `p` to the nearest obstacle, metres, capped at 8 m;
    /// 0 outside the mapped area (unknown ground is not driven on).
    pub fn clearance(&self, x: f32, y: f32) -> f32 {
        self.grid
            .index_of(f64::from(x), f64::from(y))
            .map_or(0.0, |k| self.distance[k])
    }

    /// True when every point of the segment `a → b` (xy) is at least `radius` from obstacles.
    pub fn segment_free(&self, a: [f32; 2], b: [f32; 2], radius: f32) -> bool {
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let steps = ((len / (0.5 * self.grid.frame.cell as f32)).ceil() as usize).max(1);
        (0..=steps).all(|s| {
            let t = s as f32 / steps as f32;
            self.clearance(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])) >= radius
        })
    }
}

/// The distance field tile by tile: each stored tile's chamfer distances
/// are computed on the tile grown by the saturation distance (neighbours'
/// cells read where stored, free where not), so every obstacle within
/// reach is seen and the result equals a dense map's.
fn tiled_distance(grid: &TiledFrame, occ: &[bool]) -> Vec<f32> {
    let frame = &grid.frame;
    let halo = (FAR / frame.cell as f32).ceil() as usize + 1;
    let side = TILE + 2 * halo;
    let mut out = vec![FAR; occ.len()];
    for base in (0..grid.len()).step_by(TILE * TILE) {
        let (ti, tj) = grid.cell(base);
        let (i0, j0) = (ti - halo as i64, tj - halo as i64);
        let mut window = vec![false; side * side];
        for b in 0..side {
            for a in 0..side {
                if let Some(k) = grid.index(i0 + a as i64, j0 + b as i64) {
                    window[b * side + a] = occ[k];
                }
            }
        }
        let local = GridFrame {
            origin: [0.0; 2],
            cell: frame.cell,
            nx: side,
            ny: side,
        };
        let d = distance_field(&local, &window);
        for b in 0..TILE {
            for a in 0..TILE {
                out[base + b * TILE + a] = d[(b + halo) * side + a + halo];
            }
        }
    }
    out
}

/// Two-pass chamfer distance (weights 1, √2) from every cell to the nearest
/// occupied one, in metres, capped; the cell's own half-width is subtracted
/// so a cell next to an obstacle is half a cell away, not a whole one.
fn distance_field(frame: &GridFrame, occ: &[bool]) -> Vec<f32> {
    let (nx, ny, c) = (frame.nx, frame.ny, frame.cell as f32);
    let mut d: Vec<f32> = occ.iter().map(|&o| if o { 0.0 } else { FAR + c }).collect();
    let diag = c * std::f32::consts::SQRT_2;
    for j in 0..ny {
        for i in 0..nx {
            let k = j * nx + i;
            let mut v = d[k];
            if i > 0 {
                v = v.min(d[k - 1] + c);
            }
            if j > 0 {
                v = v.min(d[k - nx] + c);
                if i > 0 {
                    v = v.min(d[k - nx - 1] + diag);
                }
                if i + 1 < nx {
                    v = v.min(d[k - nx + 1] + diag);
                }
            }
            d[k] = v;
        }
    }
    for j in (0..ny).rev() {
        for i in (0..nx).rev() {
            let k = j * nx + i;
            let mut v = d[k];
            if i + 1 < nx {
                v = v.min(d[k + 1] + c);
            }
            if j + 1 < ny {
                v = v.min(d[k + nx] + c);
                if i + 1 < nx {
                    v = v.min(d[k + nx + 1] + diag);
                }
                if i > 0 {
                    v = v.min(d[k + nx - 1] + diag);
                }
            }
            d[k] = v;
        }
    }
    d.iter()
        .map(|&v| {
            if v == 0.0 {
                0.0
            } else {
                (v - 0.5 * c).min(FAR)
            }
        })
        .collect()
}

/// The highest crown point per [`CROWN_CELL`] cell, to find crown tops.
#[derive(Default)]
struct Crowns {
    top: HashMap<(i64, i64), f32>,
}

impl Crowns {
    fn key(x: f64, y: f64) -> (i64, i64) {
        (
            (x / CROWN_CELL).floor() as i64,
            (y / CROWN_CELL).floor() as i64,
        )
    }

    fn add(&mut self, p: &[f32; 3], h: f32) {
        let e = self
            .top
            .entry(Self::key(f64::from(p[0]), f64::from(p[1])))
            .or_insert(h);
        *e = e.max(h);
    }

    /// Cells higher than every other within [`CROWN_TOP_RADIUS`] (ties
    /// broken by key, so a flat top gives one): where the trunks stand.
    fn tops(&self) -> Vec<[f64; 2]> {
        let r = (CROWN_TOP_RADIUS / CROWN_CELL).ceil() as i64;
        let mut out = Vec::new();
        for (&(i, j), &h) in &self.top {
            let highest = (-r..=r).all(|di| {
                (-r..=r).all(|dj| {
                    if (di, dj) == (0, 0) || di * di + dj * dj > r * r {
                        return true;
                    }
                    match self.top.get(&(i + di, j + dj)) {
                        Some(&o) => o < h || (o == h && (i + di, j + dj) > (i, j)),
                        None => true,
                    }
                })
            });
            if highest {
                out.push([(i as f64 + 0.5) * CROWN_CELL, (j as f64 + 0.5) * CROWN_CELL]);
            }
        }
        out
    }
}

/// Marks the stored cells within `radius` of `c` occupied; returns how many were new.
fn block_disc(grid: &TiledFrame, occ: &mut [bool], c: [f64; 2], radius: f32) -> usize {
    let (r, res) = (f64::from(radius), grid.frame.cell);
    let n = (r / res).ceil() as i64;
    let mut added = 0;
    for di in -n..=n {
        for dj in -n..=n {
            let (dx, dy) = (di as f64 * res, dj as f64 * res);
            if dx * dx + dy * dy > r * r {
                continue;
            }
            if let Some(k) = grid.index_of(c[0] + dx, c[1] + dy)
                && !occ[k]
            {
                occ[k] = true;
                added += 1;
            }
        }
    }
    added
}
