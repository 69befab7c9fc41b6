//! Distance-based downsampling of the ground: ground points binned into
//! square cells, one node per occupied cell at the cell's mean point.

use crate::cloud::class;
use crate::geom::grid::{self, GridFrame, Neighbours};
use crate::geom::tiled::TiledFrame;

/// AHN's class 26: civil structures (bridges, viaducts, quays).
const AHN_STRUCTURE: u8 = 26;

/// True for the classes a ground vehicle drives on: ground, and bridges
/// (producers class them apart from ground; without them a canal or a river
/// cuts the graph in two where a road crosses it).
pub fn drivable(label: u8) -> bool {
    matches!(label, class::GROUND | class::BRIDGE_DECK | AHN_STRUCTURE)
}

/// Node-grid cells per tile side: 8 × 1.25 m = 10 m, more than the height
/// fill reaches (6 cells), so one ring of tiles around the ground holds
/// every cell that gets a height; small, so tiles overhanging the box's
/// edge waste little on a scene that is ground from edge to edge.
const NODE_TILE: usize = 8;

/// Ground points binned into the node grid, stored in tiles where there is
/// ground (and one ring of tiles around it).
pub struct GroundCells {
    /// The node grid.
    pub grid: TiledFrame,
    /// Mean ground point per stored cell; NaN z where the cell has no ground point.
    pub mean: Vec<[f32; 3]>,
    /// Ground points counted.
    pub ground_points: usize,
}

/// Bins the finite ground points (every [`drivable`] class); `None` when
/// there are none.
pub fn bin_ground(
    xyz: &[[f32; 3]],
    labels: &[u8],
    spacing: f32,
    pad: usize,
) -> Option<GroundCells> {
    let is_ground = |p: &[f32; 3], l: u8| drivable(l) && p.iter().all(|v| v.is_finite());
    let mut lo = [f32::INFINITY; 2];
    let mut hi = [f32::NEG_INFINITY; 2];
    let mut n = 0usize;
    for (p, &l) in xyz.iter().zip(labels) {
        if is_ground(p, l) {
            n += 1;
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    if n == 0 {
        return None;
    }
    let frame = GridFrame::covering(
        lo.map(f64::from),
        hi.map(f64::from),
        f64::from(spacing),
        pad,
    );
    let ground_cells = xyz
        .iter()
        .zip(labels)
        .filter(|(p, l)| is_ground(p, **l))
        .map(|(p, _)| frame.key(f64::from(p[0]), f64::from(p[1])));
    let grid = TiledFrame::around(frame, NODE_TILE, ground_cells, 1);
    let mut sum = vec![[0.0f64; 4]; grid.len()];
    for (p, &l) in xyz.iter().zip(labels) {
        if !is_ground(p, l) {
            continue;
        }
        if let Some(k) = grid.index_of(f64::from(p[0]), f64::from(p[1])) {
            let s = &mut sum[k];
            s[0] += f64::from(p[0]);
            s[1] += f64::from(p[1]);
            s[2] += f64::from(p[2]);
            s[3] += 1.0;
        }
    }
    let mean = sum
        .iter()
        .map(|s| {
            if s[3] > 0.0 {
                [
                    (s[0] / s[3]) as f32,
                    (s[1] / s[3]) as f32,
                    (s[2] / s[3]) as f32,
                ]
            } else {
                [f32::NAN; 3]
            }
        })
        .collect();
    Some(GroundCells {
        grid,
        mean,
        ground_points: n,
    })
}

/// Cell heights with unknown cells filled from known neighbours (the
/// diagonals too), `rings` times (each pass reaches one cell farther); NaN
/// where still unknown.
pub fn filled_heights(cells: &GroundCells, rings: usize) -> Vec<f32> {
    let g = &cells.grid;
    let mut z: Vec<f32> = cells.mean.iter().map(|p| p[2]).collect();
    grid::fill_holes_with(
        &mut z,
        rings,
        Neighbours::Eight,
        // A tile's overhang beyond the frame is no cell.
        |k| {
            let (i, j) = g.cell(k);
            g.index(i, j).map(|_| (i, j))
        },
        |i, j| g.index(i, j),
    );
    z
}
