//! The obstacle map: where non-ground points stand between the ground and the
//! vehicle's top, as a 2D grid with the distance to the nearest obstacle, built
//! once and asked for every edge.

use super::cells::drivable;
use super::grid::GridFrame;
use crate::cloud::class;

/// Distances saturate here: nothing farther matters to a vehicle, metres.
const FAR: f32 = 8.0;

/// A 2D grid of obstacle cells and, per cell, the distance to the nearest one.
#[derive(Debug, Clone)]
pub struct ObstacleMap {
    frame: GridFrame,
    /// Distance from each cell centre to the nearest obstacle cell, metres (capped).
    distance: Vec<f32>,
    /// Number of obstacle cells.
    occupied: usize,
}

/// Ground heights on the node grid, with gaps (under roofs, crowns) filled
/// from their neighbours so obstacle points there have a ground to stand on.
pub struct GroundHeights<'a> {
    /// The node grid.
    pub frame: &'a GridFrame,
    /// Height per cell, NaN where unknown.
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
}

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
        let g = ground.frame;
        let frame = GridFrame::covering(
            [g.x0, g.y0],
            [g.x0 + g.nx as f32 * g.cell, g.y0 + g.ny as f32 * g.cell],
            resolution,
            0,
        );
        let mut occ = vec![false; frame.len()];
        for (p, &l) in xyz.iter().zip(labels) {
            if drivable(l) || l == 7 || l == 18 || !p.iter().all(|v| v.is_finite()) {
                continue;
            }
            let Some(cell) = frame.index_of(p[0], p[1]) else {
                continue;
            };
            let canopy = class::fold(l) == class::VEGETATION && l != class::LOW_VEGETATION;
            let blocks = if band.canopy && canopy {
                true
            } else {
                match g.index_of(p[0], p[1]).map(|k| ground.z[k]) {
                    Some(z0) if z0.is_finite() => {
                        let h = p[2] - z0;
                        h >= band.low && h <= band.high
                    }
                    // No ground known nearby: inside a large roofed area, keep out.
                    _ => true,
                }
            };
            if blocks {
                occ[cell] = true;
            }
        }
        let occupied = occ.iter().filter(|&&o| o).count();
        let distance = distance_field(&frame, &occ);
        Self {
            frame,
            distance,
            occupied,
        }
    }

    /// Number of obstacle cells.
    pub fn occupied_cells(&self) -> usize {
        self.occupied
    }

    /// Distance (xy) from `p` to the nearest obstacle, metres, capped at 8 m;
    /// 0 outside the mapped area (unknown ground is not driven on).
    pub fn clearance(&self, x: f32, y: f32) -> f32 {
        self.frame.index_of(x, y).map_or(0.0, |k| self.distance[k])
    }

    /// True when every point of the segment `a → b` (xy) is at least `radius` from obstacles.
    pub fn segment_free(&self, a: [f32; 2], b: [f32; 2], radius: f32) -> bool {
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let steps = ((len / (0.5 * self.frame.cell)).ceil() as usize).max(1);
        (0..=steps).all(|s| {
            let t = s as f32 / steps as f32;
            self.clearance(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])) >= radius
        })
    }
}

/// Two-pass chamfer distance (weights 1, √2) from every cell to the nearest
/// occupied one, in metres, capped; the cell's own half-width is subtracted
/// so a cell next to an obstacle is half a cell away, not a whole one.
fn distance_field(frame: &GridFrame, occ: &[bool]) -> Vec<f32> {
    let (nx, ny, c) = (frame.nx, frame.ny, frame.cell);
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
