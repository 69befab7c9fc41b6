//! Where the vehicle starts (docs/design.md step 8): the free spot nearest
//! a preferred point (the scene's middle), found anywhere on the ground,
//! or, on a classified prior, the spot whose ground graph is largest. A
//! scene where no such spot exists gets a [`StartError`] that says why.
//!
//! The search first walks rings about the preferred point (1 m apart, up to
//! [`NEAR_RADIUS_M`]): where that finds a spot, it is the one the search
//! always gave. Beyond, spots on a grid over the whole scene (2 m, coarser
//! when the scene would need more than 250 k) are tried nearest first: a
//! city model whose buildings stand far apart has no ground in its middle.

use thiserror::Error;

use super::probe::{Terrain, goal_inside_building};
use crate::graph::{GraphError, GraphParams, GroundGraph};
use crate::lidar::{Caster, Ray};
use crate::scene::Window;

/// Room the vehicle needs at its start: metres free all round.
pub const START_CLEARANCE_M: f32 = 2.0;
/// The rings about the preferred point reach this far, m.
pub const NEAR_RADIUS_M: f32 = 100.0;
/// The whole-scene grid holds at most this many spots.
const MAX_SPOTS: f32 = 250_000.0;
/// The whole-scene grid's finest spacing, m.
const MIN_SPACING_M: f32 = 2.0;
/// Rings about each of the 16 spots [`start_on_classes`] tries, m.
const CELL_RADIUS_M: f32 = 30.0;

/// Why the vehicle has nowhere to start.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum StartError {
    /// The scene has no triangle.
    #[error("the scene is empty: there is nothing to start on")]
    EmptyScene,
    /// No object of the scene is ground.
    #[error(
        "the scene has no ground: none of its objects is ground (a mesh needs one, e.g. an object named `terrain`; a city model gets ground built about its buildings)"
    )]
    NoGround,
    /// Ground objects exist, but no spot of the search lies over them.
    #[error(
        "no spot of the search lies over the scene's ground: {spots} spots {spacing:.1} m apart over its {width:.0} m × {depth:.0} m found none (its ground objects are smaller than that, or vertical)"
    )]
    NoGroundUnder {
        /// Spots tried.
        spots: usize,
        /// Their spacing, m.
        spacing: f32,
        /// The scene's extent in x, m.
        width: f32,
        /// The scene's extent in y, m.
        depth: f32,
    },
    /// Every spot on the ground is inside a building or crowded.
    #[error(
        "no free spot on the ground: of {on_ground} spots on it ({spacing:.1} m apart), {inside} lie inside buildings and {crowded} have an obstacle or the ground's edge within {clearance} m (the vehicle needs that much room to start)"
    )]
    NoFreeSpot {
        /// Spots over the ground.
        on_ground: usize,
        /// Of them, inside a building.
        inside: usize,
        /// Of them, with an obstacle or the ground's edge within `clearance`.
        crowded: usize,
        /// Room needed, m.
        clearance: f32,
        /// Spacing of the spots, m.
        spacing: f32,
    },
    /// vehicle_sim's `start` param is neither `[x, y]` nor `[]`.
    #[error("start must be [x, y] or [], not {0:?}")]
    BadStart(Vec<f64>),
    /// No spot's ground graph could be built on the classified cloud.
    #[error("no spot on the ground starts a ground graph on the prior's classes: {0}")]
    NoGraph(GraphError),
}

/// What a spot offers the vehicle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Spot {
    /// No ground under it.
    Off,
    /// Inside a building.
    Inside,
    /// Something stands within the clearance, or the ground ends there.
    Crowded,
    /// The vehicle can start here.
    Free,
}

/// Spot checks against one scene.
struct Probe<'a> {
    caster: &'a Caster,
    terrain: Terrain<'a>,
    clearance: f32,
}

impl<'a> Probe<'a> {
    fn new(caster: &'a Caster, clearance: f32) -> Self {
        Self {
            caster,
            terrain: Terrain::new(caster),
            clearance,
        }
    }

    fn check(&self, x: f32, y: f32) -> Spot {
        let Some(z) = self.terrain.ground_height(x, y) else {
            return Spot::Off;
        };
        if goal_inside_building(self.caster, [x, y, z + 0.5]) {
            return Spot::Inside;
        }
        let dirs = (0..16).map(|k| {
            let a = k as f32 * std::f32::consts::PI / 8.0;
            [a.cos(), a.sin()]
        });
        let clear = dirs.clone().all(|[dx, dy]| {
            let ray = Ray::new([x, y, z + 0.5], [dx, dy, 0.0], self.clearance);
            self.caster.cast_ray(&ray).is_none()
        });
        // Ground all round too: a spot at the ground's edge is no place to set a robot down.
        let r = self.clearance;
        let grounded = || {
            dirs.clone()
                .step_by(2)
                .all(|[dx, dy]| self.terrain.ground_height(x + r * dx, y + r * dy).is_some())
        };
        if clear && grounded() {
            Spot::Free
        } else {
            Spot::Crowded
        }
    }

    /// The first free spot on rings of growing radius about `(x, y)` (1 m
    /// apart, up to `max_radius`).
    fn on_rings(&self, x: f32, y: f32, max_radius: f32) -> Option<[f32; 2]> {
        let mut r = 0.0f32;
        while r <= max_radius {
            let n = ((2.0 * std::f32::consts::PI * r).ceil() as usize).max(1);
            for k in 0..n {
                let a = k as f32 * 2.0 * std::f32::consts::PI / n as f32;
                let (px, py) = (x + r * a.cos(), y + r * a.sin());
                if self.check(px, py) == Spot::Free {
                    return Some([px, py]);
                }
            }
            r += 1.0;
        }
        None
    }

    /// The free spot of a grid over the scene nearest `near`, or why there is none.
    fn on_grid(&self, near: [f32; 2]) -> Result<[f32; 2], StartError> {
        let (lo, hi) = self.caster.bounds().ok_or(StartError::EmptyScene)?;
        let size = [hi[0] - lo[0], hi[1] - lo[1]];
        let spacing = MIN_SPACING_M.max((size[0] * size[1] / MAX_SPOTS).sqrt());
        let n = [0, 1].map(|k| (size[k] / spacing).floor() as usize + 1);
        let mut spots: Vec<[f32; 2]> = (0..n[1])
            .flat_map(|j| {
                (0..n[0]).map(move |i| {
                    [
                        lo[0] + (i as f32 + 0.5) * spacing,
                        lo[1] + (j as f32 + 0.5) * spacing,
                    ]
                })
            })
            .collect();
        let d2 = |p: &[f32; 2]| (p[0] - near[0]).powi(2) + (p[1] - near[1]).powi(2);
        spots.sort_by(|a, b| d2(a).total_cmp(&d2(b)));
        let (mut on_ground, mut inside, mut crowded) = (0, 0, 0);
        for p in &spots {
            match self.check(p[0], p[1]) {
                Spot::Free => return Ok(*p),
                Spot::Off => continue,
                Spot::Inside => inside += 1,
                Spot::Crowded => crowded += 1,
            }
            on_ground += 1;
        }
        if on_ground == 0 {
            return Err(StartError::NoGroundUnder {
                spots: spots.len(),
                spacing,
                width: size[0],
                depth: size[1],
            });
        }
        Err(StartError::NoFreeSpot {
            on_ground,
            inside,
            crowded,
            clearance: self.clearance,
            spacing,
        })
    }
}

/// The free spot nearest `near` (default: the middle of the scene's
/// bounds) with [`START_CLEARANCE_M`] clear all round, anywhere on the
/// ground; or why there is none.
pub fn find_start(caster: &Caster, near: Option<[f32; 2]>) -> Result<[f32; 2], StartError> {
    let (lo, hi) = caster.bounds().ok_or(StartError::EmptyScene)?;
    if caster.ground_top().is_none() {
        return Err(StartError::NoGround);
    }
    let near = near.unwrap_or([(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0]);
    let probe = Probe::new(caster, START_CLEARANCE_M);
    match probe.on_rings(near[0], near[1], NEAR_RADIUS_M) {
        Some(p) => Ok(p),
        None => probe.on_grid(near),
    }
}

/// A spot near `(x, y)` where the vehicle can stand: on the terrain, outside
/// buildings, with `clearance` metres of ground free all around; searched on rings of
/// growing radius (1 m steps, up to `max_radius`).
pub fn free_spot(
    caster: &Caster,
    x: f32,
    y: f32,
    clearance: f32,
    max_radius: f32,
) -> Option<[f32; 2]> {
    Probe::new(caster, clearance).on_rings(x, y, max_radius)
}

/// Where the vehicle starts: `start` as `[x, y]`, or (empty) [`find_start`].
pub fn start_spot(caster: &Caster, start: &[f64]) -> Result<[f32; 2], StartError> {
    match start {
        [x, y] => Ok([*x as f32, *y as f32]),
        [] => find_start(caster, None),
        other => Err(StartError::BadStart(other.to_vec())),
    }
}

/// A start found on a classified cloud, and the size of its ground graph.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GraphStart {
    /// Where the vehicle starts (plan, local metres).
    pub at: [f32; 2],
    /// Nodes of the ground graph built there on the cloud's classes.
    pub nodes: usize,
    /// Spots whose graph was built.
    pub tried: usize,
}

/// The start whose ground graph on the classified points (`xyz`, LAS
/// `labels`, built with `params`) is largest, of the free spots nearest
/// the middles of a 4 × 4 grid over `extent` (each
/// within 30 m of its middle, else the one [`find_start`] gives). A real
/// survey's ground is cut by cars, kerbs, quays and canals into hundreds of
/// pieces (AHN3 Delft 1 + 2: 772), and the middle of a model stood on one
/// of 23 nodes.
pub fn start_on_classes(
    caster: &Caster,
    xyz: &[[f32; 3]],
    labels: &[u8],
    extent: &Window,
    params: &GraphParams,
) -> Result<GraphStart, StartError> {
    let probe = Probe::new(caster, START_CLEARANCE_M);
    let mut spots: Vec<[f32; 2]> = Vec::new();
    for i in 0..4 {
        for j in 0..4 {
            let at =
                |k: usize, n: i32| extent.min[k] + extent.size()[k] * (f64::from(n) + 0.5) / 4.0;
            if let Some(s) = probe.on_rings(at(0, i) as f32, at(1, j) as f32, CELL_RADIUS_M) {
                spots.push(s);
            }
        }
    }
    if spots.is_empty() {
        let middle = extent.centre().map(|v| v as f32);
        spots.push(find_start(caster, Some(middle))?);
    }
    let mut best: Option<GraphStart> = None;
    let mut last = GraphError::NoGround;
    for s in &spots {
        let z = ground_z(&probe.terrain, xyz, labels, *s);
        match GroundGraph::build(xyz, labels, [s[0], s[1], z], params) {
            Ok(g) => {
                let nodes = g.report().nodes;
                if best.is_none_or(|b| nodes > b.nodes) {
                    best = Some(GraphStart {
                        at: *s,
                        nodes,
                        tried: spots.len(),
                    });
                }
            }
            Err(e) => last = e,
        }
    }
    best.ok_or(StartError::NoGraph(last))
}

/// The mean height of the cloud's ground points (class 2) within 3 m of
/// `xy`; without any, the scene's ground there (0 off it).
fn ground_z(terrain: &Terrain<'_>, xyz: &[[f32; 3]], labels: &[u8], xy: [f32; 2]) -> f32 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (p, &l) in xyz.iter().zip(labels) {
        if l == 2 && (p[0] - xy[0]).hypot(p[1] - xy[1]) < 3.0 {
            sum += f64::from(p[2]);
            n += 1;
        }
    }
    if n > 0 {
        (sum / n as f64) as f32
    } else {
        terrain.ground_height(xy[0], xy[1]).unwrap_or(0.0)
    }
}
