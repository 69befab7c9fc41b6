//! The explorer of one region: candidate viewpoints on the ground graph,
//! what each sees of the still-uncovered surface, the chosen ones in tour
//! order, and coverage kept up to date from the scans.

use std::collections::HashMap;
use std::sync::Arc;

use rayon::prelude::*;

use super::error::ExploreError;
use super::params::ExploreParams;
use super::select::{Problem, order_tour, select};
use super::surface::SurfaceSamples;
use super::voxels::Voxels;
use crate::graph::GroundGraph;
use crate::targets::Region;

/// Known points this close above the ground are left out of the occupancy,
/// so rays skimming the terrain towards a wall's foot are not blocked by it.
const GROUND_SKIP_M: f32 = 0.35;

/// Local exploration of one region (docs/design.md step 7).
#[derive(Debug, Clone)]
pub struct Explorer {
    /// Shared, so the explorer can live in a node beside the route planner.
    graph: Arc<GroundGraph>,
    params: ExploreParams,
    /// Candidate viewpoints: graph nodes, and the sensor position above each.
    nodes: Vec<usize>,
    eyes: Vec<[f32; 3]>,
    visited: Vec<bool>,
    surface: SurfaceSamples,
    covered: Vec<bool>,
    attempts: Vec<u8>,
    /// Samples bucketed by `tau`-wide cells, for coverage updates.
    buckets: HashMap<[i32; 3], Vec<u32>>,
    known: Voxels,
    /// Per candidate, the open samples it sees.
    sees: Vec<Vec<u32>>,
    /// The chosen viewpoints (candidate indices) in tour order.
    plan: Vec<usize>,
    position: [f32; 3],
}

impl Explorer {
    /// Prepares the exploration of `region`: `surface` is what must be seen
    /// (e.g. the missing wall samples of its building), `known` the points
    /// known so far (aerial + scans) that can hide it.
    pub fn new(
        region: &Region,
        surface: impl Into<SurfaceSamples>,
        known: &[[f32; 3]],
        graph: Arc<GroundGraph>,
        params: &ExploreParams,
    ) -> Result<Self, ExploreError> {
        params.validate()?;
        let surface = surface.into();
        if !surface.normal.is_empty() && surface.normal.len() != surface.xyz.len() {
            return Err(ExploreError::NormalLength {
                samples: surface.xyz.len(),
                normals: surface.normal.len(),
            });
        }
        if region.polygon.len() < 3 {
            return Err(ExploreError::DegenerateRegion {
                building: region.building,
                corners: region.polygon.len(),
            });
        }
        let nodes = thin(&graph, &graph.nodes_in_polygon(&region.polygon), params);
        let eyes: Vec<[f32; 3]> = nodes
            .iter()
            .map(|&n| {
                let p = graph.positions()[n];
                [p[0], p[1], p[2] + params.sensor_height_m]
            })
            .collect();
        // The box where occlusion matters: viewpoints, samples, and what lies between.
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in eyes.iter().chain(&surface.xyz) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if !lo[0].is_finite() {
            lo = [0.0; 3];
            hi = [1.0; 3];
        }
        lo = std::array::from_fn(|k| lo[k] - 1.0);
        hi = std::array::from_fn(|k| hi[k] + 1.0);
        let mut buckets: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
        for (i, p) in surface.xyz.iter().enumerate() {
            buckets
                .entry(bucket(*p, params.tau_m))
                .or_default()
                .push(i as u32);
        }
        let n_samples = surface.xyz.len();
        let position = eyes.first().copied().unwrap_or([0.0; 3]);
        let mut e = Self {
            graph,
            params: params.clone(),
            visited: vec![false; nodes.len()],
            nodes,
            eyes,
            covered: vec![false; n_samples],
            attempts: vec![0; n_samples],
            surface,
            buckets,
            known: Voxels::new(lo, hi, params.voxel_m),
            sees: Vec::new(),
            plan: Vec::new(),
            position,
        };
        e.add_known(known);
        e.reselect();
        Ok(e)
    }

    /// Number of candidate viewpoints.
    pub fn candidates(&self) -> usize {
        self.nodes.len()
    }

    /// The chosen viewpoints (ground positions of graph nodes) in tour order
    /// from `position`; empty when nothing is left worth a stop. Drive
    /// between them along the graph (`GroundGraph::shortest_path`).
    pub fn next_waypoints(&mut self, position: [f32; 3]) -> Vec<[f32; 3]> {
        self.position = position;
        self.plan = order_tour(&self.eyes, &self.plan, position);
        self.plan
            .iter()
            .map(|&c| self.graph.positions()[self.nodes[c]])
            .collect()
    }

    /// The graph path from the node nearest `position` to the node nearest
    /// `target` (ground positions of the nodes, both ends included); just
    /// `[target]` when either has no node or the target cannot be reached.
    pub fn path_to(&self, position: [f32; 3], target: [f32; 3]) -> Vec<[f32; 3]> {
        let g = &self.graph;
        let finite = |p: [f32; 3]| p[0].is_finite() && p[1].is_finite();
        if !finite(position) || !finite(target) {
            return vec![target];
        }
        let ends = g
            .nearest_node([position[0], position[1]])
            .zip(g.nearest_node([target[0], target[1]]));
        let Some(((a, _), (b, _))) = ends else {
            return vec![target];
        };
        match g.shortest_path(a, b) {
            Some((_, nodes)) => nodes.iter().map(|&n| g.positions()[n]).collect(),
            None => vec![target],
        }
    }

    /// Takes a scan made at `position` (the vehicle's ground position):
    /// samples with a scan point within τ become covered, the points join
    /// the known occupancy, viewpoints near `position` count as visited, and
    /// the viewpoints are chosen again.
    pub fn update(&mut self, position: [f32; 3], scan_points: &[[f32; 3]]) {
        self.position = position;
        let tau = self.params.tau_m;
        let tau2 = tau * tau;
        for p in scan_points {
            if !p.iter().all(|v| v.is_finite()) {
                continue;
            }
            let b = bucket(*p, tau);
            for dz in -1..=1 {
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        if let Some(list) = self.buckets.get(&[b[0] + dx, b[1] + dy, b[2] + dz]) {
                            for &i in list {
                                let s = self.surface.xyz[i as usize];
                                let d2 = (0..3).map(|k| (s[k] - p[k]).powi(2)).sum::<f32>();
                                if d2 <= tau2 {
                                    self.covered[i as usize] = true;
                                }
                            }
                        }
                    }
                }
            }
        }
        // Viewpoints scanned from: what they promised and did not deliver is tried once less.
        let near = 0.5
            * self
                .params
                .viewpoint_spacing_m
                .max(self.graph.params().node_spacing());
        for c in 0..self.nodes.len() {
            let p = self.graph.positions()[self.nodes[c]];
            if !self.visited[c]
                && ((p[0] - position[0]).powi(2) + (p[1] - position[1]).powi(2)).sqrt() <= near
            {
                self.visited[c] = true;
                for &i in &self.sees[c] {
                    if !self.covered[i as usize] {
                        self.attempts[i as usize] = self.attempts[i as usize].saturating_add(1);
                    }
                }
            }
        }
        self.add_known(scan_points);
        self.reselect();
    }

    /// Share of the surface samples covered, 0–1 (1 for an empty surface).
    pub fn coverage(&self) -> f64 {
        if self.covered.is_empty() {
            return 1.0;
        }
        self.covered.iter().filter(|&&c| c).count() as f64 / self.covered.len() as f64
    }

    /// True when everything is covered, or no unvisited viewpoint sees
    /// enough new surface per metre of driving from the last position.
    pub fn done(&self) -> bool {
        if self.covered.iter().all(|&c| c) || self.plan.is_empty() {
            return true;
        }
        let best = (0..self.nodes.len())
            .filter(|&c| !self.visited[c])
            .map(|c| {
                let e = self.eyes[c];
                let d =
                    ((e[0] - self.position[0]).powi(2) + (e[1] - self.position[1]).powi(2)).sqrt();
                self.sees[c].len() as f32 / d.max(self.params.viewpoint_spacing_m)
            })
            .fold(0.0f32, f32::max);
        best < self.params.min_gain_per_m
    }

    /// Adds points to the known occupancy (those near the ground left out).
    fn add_known(&mut self, points: &[[f32; 3]]) {
        for p in points {
            if !p.iter().all(|v| v.is_finite()) {
                continue;
            }
            let low = self
                .graph
                .ground_height([p[0], p[1]])
                .is_some_and(|g| p[2] - g < GROUND_SKIP_M);
            if !low {
                self.known.insert(*p);
            }
        }
    }

    /// Recomputes what every candidate sees of the open samples and chooses again.
    fn reselect(&mut self) {
        let open: Vec<u32> = (0..self.covered.len())
            .filter(|&i| !self.covered[i] && self.attempts[i] < self.params.max_attempts)
            .map(|i| i as u32)
            .collect();
        let p = &self.params;
        let (lo, hi) = (
            p.fov_min_deg.to_radians().tan(),
            p.fov_max_deg.to_radians().tan(),
        );
        let (known, surface) = (&self.known, &self.surface);
        self.sees = self
            .eyes
            .par_iter()
            .zip(&self.visited)
            .map(|(eye, &visited)| {
                if visited {
                    return Vec::new();
                }
                open.iter()
                    .copied()
                    .filter(|&i| {
                        let s = surface.xyz[i as usize];
                        let d = [s[0] - eye[0], s[1] - eye[1], s[2] - eye[2]];
                        let h = (d[0] * d[0] + d[1] * d[1]).sqrt();
                        let r = (h * h + d[2] * d[2]).sqrt();
                        if r > p.sensor_range_m || h < 1.0e-3 || d[2] < lo * h || d[2] > hi * h {
                            return false;
                        }
                        if let Some(n) = surface.normal.get(i as usize)
                            && n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > -0.1 * r
                        {
                            return false;
                        }
                        !known.blocked(*eye, s, 0.3, p.own_neighbourhood_m)
                    })
                    .collect()
            })
            .collect();
        let allowed: Vec<bool> = self.visited.iter().map(|v| !v).collect();
        let problem = Problem {
            sees: &self.sees,
            allowed: &allowed,
            position: &self.eyes,
            samples: self.covered.len(),
            min_gain: p.min_gain,
        };
        self.plan = select(&problem, self.position, p.restarts, p.seed);
    }
}

/// The `tau`-wide cell holding `p`.
fn bucket(p: [f32; 3], tau: f32) -> [i32; 3] {
    std::array::from_fn(|k| (p[k] / tau).floor() as i32)
}

/// Nodes with room for the collision margin, one per `viewpoint_spacing` cell
/// (the one nearest the cell's centre).
fn thin(graph: &GroundGraph, nodes: &[usize], params: &ExploreParams) -> Vec<usize> {
    let s = params.viewpoint_spacing_m;
    let mut best: HashMap<(i64, i64), (usize, f32)> = HashMap::new();
    // In a narrow alley no node keeps the margin; the graph's own clearance
    // (the vehicle's radius) then has to do, or the region gets no viewpoint.
    let margin = if nodes
        .iter()
        .any(|&n| graph.clearance(n) >= params.collision_margin_m)
    {
        params.collision_margin_m
    } else {
        0.0
    };
    for &n in nodes {
        if graph.clearance(n) < margin {
            continue;
        }
        let p = graph.positions()[n];
        let (i, j) = ((p[0] / s).floor() as i64, (p[1] / s).floor() as i64);
        let c = [(i as f32 + 0.5) * s, (j as f32 + 0.5) * s];
        let d = (p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2);
        let e = best.entry((i, j)).or_insert((n, d));
        if d < e.1 {
            *e = (n, d);
        }
    }
    let mut out: Vec<usize> = best.into_values().map(|(n, _)| n).collect();
    out.sort_unstable();
    out
}
