//! The ground graph: nodes on open ground, edges the vehicle can drive,
//! only the part reachable from the start.

use petgraph::unionfind::UnionFind;
use rayon::prelude::*;

use super::cells::{bin_ground, drivable, filled_heights};
use super::error::GraphError;
use super::obstacles::{Band, GroundHeights, ObstacleMap};
use super::params::{GraphParams, MAX_OCCUPANCY_CELLS};
use crate::cloud::ColumnLength;
use crate::density::Density;
use crate::geom::ring::Ring;
use crate::geom::tiled::TiledFrame;

/// A way-point counts as reached this close (vehicle_sim's `goal_tolerance`),
/// so the vehicle's look-ahead reaches this far past an edge's end node.
const ARRIVAL_OVERHANG_M: f32 = 0.5;

/// Ground cells this far from known ground still get a height, so walls at
/// the edge of large roofs are measured against the street beside them.
const HEIGHT_FILL_RINGS: usize = 6;

/// What the build kept and what it left out.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct GraphReport {
    /// Ground points used.
    pub ground_points: usize,
    /// Nodes before the reachability cut (cells with ground and room for the vehicle).
    pub candidate_nodes: usize,
    /// Nodes kept (reachable from the start).
    pub nodes: usize,
    /// Edges kept.
    pub edges: usize,
    /// Nodes in the other components (not reachable from the start).
    pub unreachable_nodes: usize,
    /// Number of other components.
    pub unreachable_components: usize,
    /// Cells of the obstacle grid holding a blocking non-ground point.
    pub obstacle_cells: usize,
    /// Obstacle-grid cells stored (tiles near ground only).
    pub obstacle_cells_stored: usize,
    /// Obstacle-grid cells a dense map over the bounding box would hold.
    pub obstacle_cells_bbox: usize,
    /// Node-grid cells stored (tiles near ground only).
    pub node_grid_cells: usize,
    /// Node-grid cells a dense grid over the bounding box would hold.
    pub node_grid_cells_bbox: usize,
    /// Bytes the graph keeps (nodes, adjacency, node grid, obstacle map).
    pub bytes: usize,
}

impl GraphReport {
    /// `nodes` as a share of the candidate nodes (0 without candidates).
    pub fn share_of_candidates(&self, nodes: usize) -> f64 {
        nodes as f64 / self.candidate_nodes.max(1) as f64
    }

    /// The share of the candidate nodes the graph reaches from its start.
    pub fn reachable_share(&self) -> f64 {
        self.share_of_candidates(self.nodes)
    }
}

/// Nodes on open ground joined where the vehicle can drive, restricted to the
/// connected component of the start.
#[derive(Debug, Clone)]
pub struct GroundGraph {
    /// Node positions (the node's index is its position here).
    pub(super) positions: Vec<[f32; 3]>,
    /// Candidate nodes of the other components: ground the vehicle fits on
    /// but cannot reach from the start (for pictures and reports).
    unreachable: Vec<[f32; 3]>,
    /// Distance (xy) from each node to the nearest obstacle, metres (capped at 8).
    clearance: Vec<f32>,
    /// The node grid and which kept node (if any) sits in each stored cell.
    grid: TiledFrame,
    cell_node: Vec<u32>,
    obstacles: ObstacleMap,
    /// Ground height per stored node-grid cell (gaps filled near known ground), NaN where unknown.
    heights: Vec<f32>,
    /// Adjacency in compressed rows, for fast searches.
    pub(super) adj_start: Vec<usize>,
    pub(super) adj: Vec<u32>,
    pub(super) adj_w: Vec<f32>,
    start: usize,
    report: GraphReport,
    pub(super) params: GraphParams,
    /// Spots the vehicle was blocked at while driving, with their radius.
    pub(super) blocked_spots: Vec<([f32; 2], f32)>,
}

impl GroundGraph {
    /// Builds the graph from a classified cloud (`labels`: LAS classes, 2 =
    /// ground) and keeps the component of the node nearest `start`.
    pub fn build(
        xyz: &[[f32; 3]],
        labels: &[u8],
        start: [f32; 3],
        params: &GraphParams,
    ) -> Result<Self, GraphError> {
        Self::build_from(xyz, labels, Start::Near(start), params)
    }

    /// Builds the graph and keeps its largest component, starting at that
    /// component's node nearest its middle: where a robot set down on a
    /// survey nobody has walked reaches most (a real tile's ground comes in
    /// hundreds of pieces, and its middle may stand on one of a few nodes).
    pub fn build_largest(
        xyz: &[[f32; 3]],
        labels: &[u8],
        params: &GraphParams,
    ) -> Result<Self, GraphError> {
        Self::build_from(xyz, labels, Start::Piece(0), params)
    }

    /// Builds the graph and keeps its `rank`-th largest component (0: the
    /// largest), starting at that component's node nearest its middle: the
    /// ground a field team reaches by setting the robot down there.
    pub fn build_piece(
        xyz: &[[f32; 3]],
        labels: &[u8],
        params: &GraphParams,
        rank: usize,
    ) -> Result<Self, GraphError> {
        Self::build_from(xyz, labels, Start::Piece(rank), params)
    }

    fn build_from(
        xyz: &[[f32; 3]],
        labels: &[u8],
        start: Start,
        params: &GraphParams,
    ) -> Result<Self, GraphError> {
        params.validate()?;
        ColumnLength::check("labels", xyz.len(), labels.len())?;
        let density = Density::measure_where(xyz, |i| drivable(labels[i]));
        let params = &match density {
            Some(d) => params.resolved(&d),
            None => params.clone(),
        };
        let spacing = params.node_spacing();
        let pad = (params.vehicle_radius_m / spacing).ceil() as usize + 1;
        let cells = bin_ground(xyz, labels, spacing, pad).ok_or(GraphError::NoGround)?;
        let grid = cells.grid.clone();
        let frame = grid.frame;
        let occ_cells =
            frame.len() as f64 * (frame.cell / f64::from(params.occupancy_resolution_m)).powi(2);
        if occ_cells > MAX_OCCUPANCY_CELLS {
            return Err(GraphError::TooLarge {
                cells: occ_cells as usize,
                max: MAX_OCCUPANCY_CELLS as usize,
            });
        }
        let heights = filled_heights(&cells, HEIGHT_FILL_RINGS);
        let band = Band {
            low: params.clearance_m,
            high: params.vehicle_height_m,
            canopy: params.canopy_is_obstacle,
            trunk_radius: params.canopy_trunk_radius_m,
        };
        let ground = GroundHeights {
            grid: &grid,
            z: &heights,
        };
        let obstacles =
            ObstacleMap::build(xyz, labels, &ground, &band, params.occupancy_resolution_m);

        // Candidate nodes: cells with ground where the vehicle fits.
        let mut cand_cell = Vec::new();
        let mut cand_pos = Vec::new();
        for (k, p) in cells.mean.iter().enumerate() {
            if p[2].is_finite() && obstacles.clearance(p[0], p[1]) >= params.vehicle_radius_m {
                cand_cell.push(k);
                cand_pos.push(*p);
            }
        }
        let mut cell_cand = vec![u32::MAX; grid.len()];
        for (i, &k) in cand_cell.iter().enumerate() {
            cell_cand[k] = i as u32;
        }
        let edges = candidate_edges(&grid, &cell_cand, &cand_cell, &cand_pos, &obstacles, params);

        let mut uf = UnionFind::<usize>::new(cand_pos.len());
        for &(a, b, _) in &edges {
            uf.union(a as usize, b as usize);
        }
        let labels_cc = uf.into_labeling();
        let start_node = match start {
            // The nearest node at any distance: it is the start when close
            // enough and says how far off the start was when not.
            Start::Near(s) => {
                match nearest_in(&grid, &cell_cand, &cand_pos, [s[0], s[1]], f32::INFINITY) {
                    Some((n, d)) if d <= params.max_start_snap_m => n,
                    near => {
                        return Err(GraphError::StartOffGraph {
                            x: s[0],
                            y: s[1],
                            distance: near.map_or(f32::INFINITY, |(_, d)| d),
                            max: params.max_start_snap_m,
                        });
                    }
                }
            }
            Start::Piece(rank) => middle_of_piece(&labels_cc, &cand_pos, rank)?,
        };
        let keep_label = labels_cc[start_node];
        let mut other = std::collections::HashSet::new();
        let mut new_index = vec![u32::MAX; cand_pos.len()];
        let mut positions = Vec::new();
        let mut unreachable = Vec::new();
        let mut cell_node = vec![u32::MAX; grid.len()];
        for (i, &l) in labels_cc.iter().enumerate() {
            if l == keep_label {
                new_index[i] = positions.len() as u32;
                cell_node[cand_cell[i]] = positions.len() as u32;
                positions.push(cand_pos[i]);
            } else {
                other.insert(l);
                unreachable.push(cand_pos[i]);
            }
        }
        let mut kept_edges = Vec::new();
        for &(a, b, w) in &edges {
            let (a, b) = (new_index[a as usize], new_index[b as usize]);
            if a != u32::MAX && b != u32::MAX {
                kept_edges.push((a, b, w));
            }
        }
        let (adj_start, adj, adj_w) = csr(positions.len(), &kept_edges);
        let clearance = positions
            .iter()
            .map(|p| obstacles.clearance(p[0], p[1]))
            .collect();
        let report = GraphReport {
            ground_points: cells.ground_points,
            candidate_nodes: cand_pos.len(),
            nodes: positions.len(),
            edges: kept_edges.len(),
            unreachable_nodes: cand_pos.len() - positions.len(),
            unreachable_components: other.len(),
            obstacle_cells: obstacles.occupied_cells(),
            obstacle_cells_stored: obstacles.stored_cells().0,
            obstacle_cells_bbox: obstacles.stored_cells().1,
            node_grid_cells: grid.len(),
            node_grid_cells_bbox: frame.len(),
            bytes: 0,
        };
        let mut report = report;
        report.bytes = kept_bytes(&positions, &adj, &grid, &obstacles) + 12 * unreachable.len();
        Ok(Self {
            start: new_index[start_node] as usize,
            positions,
            unreachable,
            clearance,
            grid,
            cell_node,
            obstacles,
            heights,
            adj_start,
            adj,
            adj_w,
            report,
            params: params.clone(),
            blocked_spots: Vec::new(),
        })
    }

    /// Node positions; node `i` is at `positions()[i]`.
    pub fn positions(&self) -> &[[f32; 3]] {
        &self.positions
    }

    /// Ground the vehicle fits on but cannot reach from the start: the
    /// candidate nodes of the other components.
    pub fn unreachable_positions(&self) -> &[[f32; 3]] {
        &self.unreachable
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True when the graph has no node (never after a successful build).
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Edges as `(a, b, length_m)` with `a < b`, each once (cut ones at infinite length).
    pub fn edges(&self) -> Vec<(usize, usize, f32)> {
        (0..self.positions.len())
            .flat_map(|u| {
                (self.adj_start[u]..self.adj_start[u + 1])
                    .map(move |e| (u, self.adj[e] as usize, self.adj_w[e]))
                    .filter(|&(u, v, _)| u < v)
            })
            .collect()
    }

    /// The node the start was snapped to.
    pub fn start_node(&self) -> usize {
        self.start
    }

    /// Counts of what was kept and left out.
    pub fn report(&self) -> GraphReport {
        self.report
    }

    /// The parameters the graph was built with.
    pub fn params(&self) -> &GraphParams {
        &self.params
    }

    /// What tree crowns cost this graph: the same cloud's graph from the
    /// same start with crowns blocking only in the vehicle's height band
    /// (`canopy_is_obstacle: false`); `None` when this one already lets
    /// them. Whether to drive under crowns is the user's call (trunks are
    /// seldom in an aerial cloud); this says what the call is worth.
    pub fn if_crowns_block_only_in_band(
        &self,
        xyz: &[[f32; 3]],
        labels: &[u8],
    ) -> Result<Option<GraphReport>, GraphError> {
        if !self.params.canopy_is_obstacle {
            return Ok(None);
        }
        let params = GraphParams {
            canopy_is_obstacle: false,
            ..self.params.clone()
        };
        let start = self.positions[self.start];
        Ok(Some(
            GroundGraph::build(xyz, labels, start, &params)?.report(),
        ))
    }

    /// Distance (xy) from node `i` to the nearest obstacle, metres (capped at 8; 0 for a bad index).
    pub fn clearance(&self, i: usize) -> f32 {
        self.clearance.get(i).copied().unwrap_or(0.0)
    }

    /// The nearest node to `xy` and its distance (xy), searching the node grid; `None` for an empty graph.
    pub fn nearest_node(&self, xy: [f32; 2]) -> Option<(usize, f32)> {
        nearest_in(
            &self.grid,
            &self.cell_node,
            &self.positions,
            xy,
            f32::INFINITY,
        )
    }

    /// Up to `k` nearest nodes within `max_dist` (xy) of `xy`, nearest first.
    pub fn nodes_near(&self, xy: [f32; 2], max_dist: f32, k: usize) -> Vec<(usize, f32)> {
        let g = &self.grid;
        let r = (max_dist / g.frame.cell as f32).ceil().min(1.0e6) as i64 + 1;
        let (ci, cj) = g.frame.key(f64::from(xy[0]), f64::from(xy[1]));
        let mut out = Vec::new();
        for j in cj - r..=cj + r {
            for i in ci - r..=ci + r {
                if let Some(n) = g
                    .index(i, j)
                    .map(|c| self.cell_node[c])
                    .filter(|&n| n != u32::MAX)
                {
                    let d = dist2(self.positions[n as usize], xy);
                    if d <= max_dist {
                        out.push((n as usize, d));
                    }
                }
            }
        }
        out.sort_by(|a, b| a.1.total_cmp(&b.1));
        out.truncate(k);
        out
    }

    /// Nodes whose xy lies inside `polygon` (a ring, open or closed).
    pub fn nodes_in_polygon(&self, polygon: &[[f64; 2]]) -> Vec<usize> {
        let ring = Ring::new(polygon);
        self.positions
            .iter()
            .enumerate()
            .filter(|(_, p)| ring.contains([f64::from(p[0]), f64::from(p[1])]))
            .map(|(i, _)| i)
            .filter(|&i| self.indexed(i))
            .collect()
    }

    /// Ground height at `xy` from the ground points of its cell (or nearby
    /// ones where the cell has none); `None` off the known ground.
    pub fn ground_height(&self, xy: [f32; 2]) -> Option<f32> {
        self.grid
            .index_of(f64::from(xy[0]), f64::from(xy[1]))
            .map(|k| self.heights[k])
            .filter(|z| z.is_finite())
    }

    /// The cell that indexes node `n`, while it does (`block_near` takes nodes out).
    fn cell_of(&self, n: usize) -> Option<usize> {
        let p = self.positions.get(n)?;
        self.grid
            .index_of(f64::from(p[0]), f64::from(p[1]))
            .filter(|&c| self.cell_node[c] as usize == n)
    }

    /// True while node `n` is in the cell index.
    fn indexed(&self, n: usize) -> bool {
        self.cell_of(n).is_some()
    }

    /// Drops node `n` from the cell index, so look-ups no longer find it.
    pub(super) fn unindex_node(&mut self, n: usize) {
        if let Some(c) = self.cell_of(n) {
            self.cell_node[c] = u32::MAX;
        }
    }

    /// True when the vehicle (its radius) fits along the straight segment `a → b` (xy).
    pub fn segment_free(&self, a: [f32; 2], b: [f32; 2]) -> bool {
        self.obstacles
            .segment_free(a, b, self.params.vehicle_radius_m)
    }
}

/// Distance in xy.
fn dist2(p: [f32; 3], xy: [f32; 2]) -> f32 {
    ((p[0] - xy[0]).powi(2) + (p[1] - xy[1]).powi(2)).sqrt()
}

/// Nearest node in `cell_node` to `xy` within `max`, by growing square rings of cells.
fn nearest_in(
    grid: &TiledFrame,
    cell_node: &[u32],
    pos: &[[f32; 3]],
    xy: [f32; 2],
    max: f32,
) -> Option<(usize, f32)> {
    if pos.is_empty() || !xy.iter().all(|v| v.is_finite()) {
        return None;
    }
    let frame = &grid.frame;
    let (ci, cj) = frame.key(f64::from(xy[0]), f64::from(xy[1]));
    let (nx, ny) = (frame.nx as i64, frame.ny as i64);
    // Rings before the first one touching the grid are empty; the last one covers it all.
    let first = [ci - (nx - 1), -ci, cj - (ny - 1), -cj, 0]
        .into_iter()
        .max()
        .unwrap_or(0);
    let last = first + nx.max(ny) + 1;
    let mut best: Option<(usize, f32)> = None;
    let visit = |i: i64, j: i64, best: &mut Option<(usize, f32)>| {
        if let Some(n) = grid
            .index(i, j)
            .map(|c| cell_node[c])
            .filter(|&n| n != u32::MAX)
        {
            let d = dist2(pos[n as usize], xy);
            if d <= max && best.is_none_or(|(_, bd)| d < bd) {
                *best = Some((n as usize, d));
            }
        }
    };
    for r in first..=last {
        // Every node in ring r is at least (r - 1) cells away.
        let ring_min = (r - 1).max(0) as f32 * frame.cell as f32;
        if best.is_some_and(|(_, d)| d <= ring_min) || ring_min > max {
            break;
        }
        for i in ci - r..=ci + r {
            visit(i, cj - r, &mut best);
            if r > 0 {
                visit(i, cj + r, &mut best);
            }
        }
        for j in cj - r + 1..cj + r {
            visit(ci - r, j, &mut best);
            visit(ci + r, j, &mut best);
        }
    }
    best
}

/// Edges between candidate nodes closer than `d_threshold` whose slope is
/// drivable, between the nodes and by the vehicle's own rule along the
/// ground between them, and whose segment keeps the vehicle's radius from
/// obstacles.
fn candidate_edges(
    grid: &TiledFrame,
    cell_cand: &[u32],
    cand_cell: &[usize],
    pos: &[[f32; 3]],
    obstacles: &ObstacleMap,
    params: &GraphParams,
) -> Vec<(u32, u32, f32)> {
    let r = (params.d_threshold() / grid.frame.cell as f32).ceil() as i64;
    let max_grade = params.max_slope_deg.to_radians().tan();
    (0..pos.len())
        .into_par_iter()
        .flat_map_iter(|a| {
            let k = cand_cell[a];
            let (ci, cj) = grid.cell(k);
            let mut out = Vec::new();
            for dj in 0..=r {
                for di in -r..=r {
                    // Half the neighbourhood: every pair once.
                    if dj == 0 && di <= 0 {
                        continue;
                    }
                    let Some(b) = grid
                        .index(ci + di, cj + dj)
                        .map(|c| cell_cand[c])
                        .filter(|&b| b != u32::MAX)
                    else {
                        continue;
                    };
                    let (p, q) = (pos[a], pos[b as usize]);
                    let dxy = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
                    let len = (dxy * dxy + (q[2] - p[2]).powi(2)).sqrt();
                    if len >= params.d_threshold() || (q[2] - p[2]).abs() > max_grade * dxy {
                        continue;
                    }
                    let (a2, b2) = ([p[0], p[1]], [q[0], q[1]]);
                    if obstacles.segment_free(a2, b2, params.vehicle_radius_m)
                        && obstacles.segment_climbable(
                            a2,
                            b2,
                            params.max_slope_deg,
                            ARRIVAL_OVERHANG_M,
                        )
                    {
                        out.push((a as u32, b, len));
                    }
                }
            }
            out
        })
        .collect()
}

/// Bytes a graph keeps: per node its position, clearance and row start; per
/// half-edge its neighbour and length; per stored node-grid cell its node
/// and height; the obstacle map's stored cells.
fn kept_bytes(
    positions: &[[f32; 3]],
    adj: &[u32],
    grid: &TiledFrame,
    obstacles: &ObstacleMap,
) -> usize {
    positions.len() * (12 + 4 + 8) + adj.len() * (4 + 4) + grid.len() * (4 + 4) + obstacles.bytes()
}

/// Compressed adjacency rows of an undirected edge list.
fn csr(n: usize, edges: &[(u32, u32, f32)]) -> (Vec<usize>, Vec<u32>, Vec<f32>) {
    let mut deg = vec![0usize; n + 1];
    for &(a, b, _) in edges {
        deg[a as usize + 1] += 1;
        deg[b as usize + 1] += 1;
    }
    for i in 0..n {
        deg[i + 1] += deg[i];
    }
    let mut fill = deg.clone();
    let mut adj = vec![0u32; 2 * edges.len()];
    let mut w = vec![0f32; 2 * edges.len()];
    for &(a, b, l) in edges {
        for (u, v) in [(a, b), (b, a)] {
            let s = &mut fill[u as usize];
            adj[*s] = v;
            w[*s] = l;
            *s += 1;
        }
    }
    (deg, adj, w)
}

/// Where the kept component comes from.
#[derive(Debug, Clone, Copy)]
enum Start {
    /// The component of the node nearest this point.
    Near([f32; 3]),
    /// The component of this rank by size (0: the largest).
    Piece(usize),
}

/// The node of the `rank`-th largest component (ties: the lower label
/// first) nearest (xy) that component's mean position.
fn middle_of_piece(labels: &[usize], pos: &[[f32; 3]], rank: usize) -> Result<usize, GraphError> {
    // Union-find labels are node indices, so a count per index will do.
    let mut count = vec![0usize; labels.len()];
    for &l in labels {
        count[l] += 1;
    }
    let mut pieces: Vec<usize> = (0..count.len()).filter(|&l| count[l] > 0).collect();
    if pieces.is_empty() {
        return Err(GraphError::NoGround);
    }
    pieces.sort_by(|a, b| count[*b].cmp(&count[*a]).then(a.cmp(b)));
    let &piece = pieces.get(rank).ok_or(GraphError::NoSuchPiece {
        rank,
        pieces: pieces.len(),
    })?;
    let members = || (0..labels.len()).filter(move |&i| labels[i] == piece);
    let n = count[piece] as f32;
    let mean = members().fold([0.0f32; 2], |m, i| {
        [m[0] + pos[i][0] / n, m[1] + pos[i][1] / n]
    });
    let d = |i: &usize| (pos[*i][0] - mean[0]).powi(2) + (pos[*i][1] - mean[1]).powi(2);
    members()
        .min_by(|a, b| d(a).total_cmp(&d(b)))
        .ok_or(GraphError::NoGround)
}
