//! Assigning points to footprints: point-in-polygon over a grid of
//! footprint bounding boxes, in parallel.

use geo::{Contains, Coord, MultiPolygon};
use rayon::prelude::*;

use super::params::SplitParams;
use super::types::Footprint;
use crate::geom::grid::GridFrame;
use crate::geom::segment;
use crate::params::ParamError;

/// The index grid never exceeds this many cells (the cell grows instead).
const MAX_CELLS: f64 = 4.0e6;

/// One footprint: its polygon for the inside test, its edges for the depth.
struct Shape<'a> {
    id: u32,
    polygon: &'a MultiPolygon<f64>,
    edges: Vec<[[f64; 2]; 2]>,
}

impl Shape<'_> {
    /// Whether `p` lies inside (holes excluded).
    fn contains(&self, p: [f64; 2]) -> bool {
        self.polygon.contains(&Coord { x: p[0], y: p[1] })
    }

    /// Distance to the nearest edge.
    fn edge_distance(&self, p: [f64; 2]) -> f64 {
        self.edges
            .iter()
            .map(|&[a, b]| segment::distance(p, a, b))
            .fold(f64::INFINITY, f64::min)
    }
}

/// The building id of each point (x, y used; 0 = outside every footprint).
///
/// A point inside one footprint gets its id; inside several (overlapping
/// footprints), the one it lies deepest in; inside none, the footprint whose
/// outline is nearest if within `tolerance_m`.
pub fn split(
    points: &[[f32; 3]],
    footprints: &[Footprint],
    params: &SplitParams,
) -> Result<Vec<u32>, ParamError> {
    params.validate()?;
    let tol = params.tolerance_m;
    let shapes: Vec<(Shape, [f64; 4])> = footprints
        .iter()
        .filter_map(|f| {
            let b = f.bounds()?;
            let mut edges = Vec::new();
            for poly in &f.polygon.0 {
                for ring in std::iter::once(poly.exterior()).chain(poly.interiors()) {
                    for l in ring.lines() {
                        edges.push([[l.start.x, l.start.y], [l.end.x, l.end.y]]);
                    }
                }
            }
            let b = [b[0] - tol, b[1] - tol, b[2] + tol, b[3] + tol];
            Some((
                Shape {
                    id: f.id,
                    polygon: &f.polygon,
                    edges,
                },
                b,
            ))
        })
        .collect();
    if shapes.is_empty() {
        return Ok(vec![0; points.len()]);
    }
    let grid = Grid::new(&shapes, params.index_cell_m);
    Ok(points
        .par_iter()
        .map(|p| {
            let q = [f64::from(p[0]), f64::from(p[1])];
            let Some(cands) = grid.candidates(q) else {
                return 0;
            };
            let mut best_inside: Option<(f64, u32)> = None;
            let mut best_near: Option<(f64, u32)> = None;
            for &k in cands {
                let (s, b) = &shapes[k as usize];
                if q[0] < b[0] || q[0] > b[2] || q[1] < b[1] || q[1] > b[3] {
                    continue;
                }
                if s.contains(q) {
                    if cands.len() == 1 {
                        return s.id;
                    }
                    let depth = s.edge_distance(q);
                    if best_inside.is_none_or(|(d, _)| depth > d) {
                        best_inside = Some((depth, s.id));
                    }
                } else if best_inside.is_none() {
                    let d = s.edge_distance(q);
                    if d <= tol && best_near.is_none_or(|(e, _)| d < e) {
                        best_near = Some((d, s.id));
                    }
                }
            }
            best_inside.or(best_near).map_or(0, |(_, id)| id)
        })
        .collect())
}

/// Footprint indices per cell of a regular grid over their (buffered) boxes.
struct Grid {
    frame: GridFrame,
    cells: Vec<Vec<u32>>,
}

impl Grid {
    fn new(shapes: &[(Shape, [f64; 4])], cell: f64) -> Self {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for (_, b) in shapes {
            lo = [lo[0].min(b[0]), lo[1].min(b[1])];
            hi = [hi[0].max(b[2]), hi[1].max(b[3])];
        }
        let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
        // Bounded by MAX_CELLS: the frame's float-to-int casts cannot overflow.
        let frame = GridFrame::covering(lo, hi, cell.max((w * h / MAX_CELLS).sqrt()), 0);
        let mut cells = vec![Vec::new(); frame.len()];
        for (k, (_, b)) in shapes.iter().enumerate() {
            let (i0, j0) = frame.clamped_cell(b[0], b[1]);
            let (i1, j1) = frame.clamped_cell(b[2], b[3]);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    cells[j * frame.nx + i].push(u32::try_from(k).unwrap_or(u32::MAX));
                }
            }
        }
        Self { frame, cells }
    }

    fn candidates(&self, p: [f64; 2]) -> Option<&[u32]> {
        let c = &self.cells[self.frame.index_of(p[0], p[1])?];
        (!c.is_empty()).then_some(c.as_slice())
    }
}
