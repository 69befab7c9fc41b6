//! Ground over the whole crop when the source's ground leaves holes in it.
//!
//! A CityJSON scene's ground is one patch per building (footprint box +
//! margin): two buildings of a cluster may stand on separate islands, and a
//! vehicle cannot drive from one to the other. Where that happens the crop's
//! ground becomes one grid over its extent: the source ground's height where
//! it exists, elsewhere the kept buildings' base heights as the CityJSON
//! loader blends them (highest base inside a footprint box, else weighted
//! by 1 / (1 + d²)² with d the distance to each box).

use super::Window;
use crate::geom::grid::GridFrame;
use crate::geom::triangle::height_over;
use crate::scene::MeshPart;
use crate::scene::terrain::blend_bases;

/// Grid cell of the filled ground, metres (the CityJSON terrain's).
pub const FILL_CELL: f64 = 2.0;
/// Bucket side of the triangle look-up, metres.
const BUCKET: f64 = 8.0;
/// Barycentric slack: a point on a shared edge counts as covered.
const EPS: f64 = 1e-9;

/// Where a kept building stands: its xy box and lowest z.
#[derive(Debug, Clone, Copy)]
pub struct Base {
    /// The building's xy box.
    pub xy: Window,
    /// Its lowest z.
    pub z: f64,
}

/// Ground triangles (xy-bucketed) answering "how high is the ground here".
pub struct GroundLookup<'a> {
    triangles: &'a [[[f64; 3]; 3]],
    frame: GridFrame,
    buckets: Vec<Vec<usize>>,
}

impl<'a> GroundLookup<'a> {
    /// Buckets `triangles` over `extent`.
    pub fn new(triangles: &'a [[[f64; 3]; 3]], extent: &Window) -> Self {
        let frame = GridFrame::covering(extent.min, extent.max, BUCKET, 0);
        let mut buckets = vec![Vec::new(); frame.len()];
        for (k, t) in triangles.iter().enumerate() {
            let (lo, hi) = xy_box(t);
            let (i0, j0) = frame.clamped_cell(lo[0], lo[1]);
            let (i1, j1) = frame.clamped_cell(hi[0], hi[1]);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    buckets[j * frame.nx + i].push(k);
                }
            }
        }
        Self {
            triangles,
            frame,
            buckets,
        }
    }

    /// The highest ground at `(x, y)`, `None` where there is none.
    pub fn height(&self, x: f64, y: f64) -> Option<f64> {
        let (i, j) = self.frame.key(x, y);
        if i < 0 || j < 0 {
            return None;
        }
        // Points on the extent's far edge fall one bucket past the last.
        let bucket = self.buckets.get(self.frame.clamped_index(x, y))?;
        bucket
            .iter()
            .filter_map(|&k| height_over(&self.triangles[k], x, y, EPS))
            .max_by(f64::total_cmp)
    }
}

fn xy_box(t: &[[f64; 3]; 3]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in t {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// The base-height blend of the CityJSON loader at `(x, y)`.
fn base_height(bases: &[Base], x: f64, y: f64) -> f64 {
    blend_bases(bases.iter().map(|b| {
        let dx = (b.xy.min[0] - x).max(x - b.xy.max[0]).max(0.0);
        let dy = (b.xy.min[1] - y).max(y - b.xy.max[1]).max(0.0);
        (dx * dx + dy * dy, b.z)
    }))
}

/// A grid of `FILL_CELL` cells over `extent` (vertices, counter-clockwise
/// triangles), or `None` when `ground` already covers every grid vertex.
pub fn fill_ground(ground: &[[[f64; 3]; 3]], bases: &[Base], extent: &Window) -> Option<MeshPart> {
    let look = GroundLookup::new(ground, extent);
    let [w, h] = extent.size();
    let nx = (w / FILL_CELL).ceil().max(1.0) as usize;
    let ny = (h / FILL_CELL).ceil().max(1.0) as usize;
    let mut holes = false;
    let mut vertices = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        // The last row and column sit on the extent's edge exactly.
        let y = if j == ny {
            extent.max[1]
        } else {
            extent.min[1] + j as f64 * FILL_CELL
        };
        for i in 0..=nx {
            let x = if i == nx {
                extent.max[0]
            } else {
                extent.min[0] + i as f64 * FILL_CELL
            };
            let z = look.height(x, y).unwrap_or_else(|| {
                holes = true;
                base_height(bases, x, y)
            });
            vertices.push([x, y, z]);
        }
    }
    if !holes {
        return None;
    }
    let at = |i: usize, j: usize| u32::try_from(j * (nx + 1) + i).unwrap_or(u32::MAX);
    let mut triangles = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    Some(MeshPart {
        vertices,
        triangles,
    })
}
