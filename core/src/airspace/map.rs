//! The drone's free space from the aerial prior: a height map of the
//! highest point in each cell (buildings and trees are taken as solid from
//! the ground up to their top, as a survey from above sees them), each cell
//! marked building or not, and the distance from a position to that solid.

use geo::{Contains, Coord};

use super::rules::{AirspaceRules, Geofence};
use super::violation::{Obstacle, Refusal, Violation};
use crate::cloud::{Cloud, class};
use crate::footprint::inset;
use crate::geom::grid::{GridFrame, Neighbours};
use crate::params::ParamError;

/// Cells the survey left empty are filled from their neighbours this many
/// cells away (dark roofs, small gaps); farther from any point they are
/// taken at the lowest ground (water gives no return).
const FILL_CELLS: usize = 2;
/// Around the home pad the ground is not an obstacle within this radius
/// (m) and this height above the pad's body centre (m): take-off and landing.
const PAD_RADIUS_M: f32 = 1.0;

/// Building the airspace failed.
#[derive(Debug, thiserror::Error)]
pub enum AirspaceError {
    /// A rule out of range.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// The prior holds no usable point.
    #[error("the prior holds no point to build the drone's free space from")]
    EmptyPrior,
}

/// Where the drone may fly: the prior's height map and the rules.
#[derive(Debug, Clone)]
pub struct Airspace {
    rules: AirspaceRules,
    body_radius: f32,
    home: [f32; 3],
    pub(super) grid: GridFrame,
    pub(super) top: Vec<f32>,
    pub(super) building: Vec<bool>,
    /// Per cell, the lowest ground point (NaN where the survey saw none).
    pub(super) ground: Vec<f32>,
    /// Per cell, the lowest height the body centre may be at: the prior's
    /// solid grown by the distances kept (see [`floor`]).
    floor: Vec<f32>,
    fence: Option<Geofence>,
}

impl Airspace {
    /// The airspace over `prior` (local frame) for a body of `body_radius`
    /// taking off at `home` (its body centre on the pad).
    pub fn from_prior(
        prior: &Cloud,
        rules: AirspaceRules,
        body_radius: f32,
        home: [f32; 3],
    ) -> Result<Self, AirspaceError> {
        rules.validate()?;
        let keep = |k: usize| {
            let label = prior.label.as_ref().map_or(class::UNCLASSIFIED, |l| l[k]);
            prior.xyz[k].iter().all(|v| v.is_finite()) && !class::is_noise(label)
        };
        let kept: Vec<usize> = (0..prior.xyz.len()).filter(|&k| keep(k)).collect();
        if kept.is_empty() {
            return Err(AirspaceError::EmptyPrior);
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &k in &kept {
            for a in 0..2 {
                lo[a] = lo[a].min(f64::from(prior.xyz[k][a]));
                hi[a] = hi[a].max(f64::from(prior.xyz[k][a]));
            }
        }
        let grid = GridFrame::covering(lo, hi, f64::from(rules.cell_m), 0);
        let mut top = vec![f32::NAN; grid.len()];
        let mut building = vec![false; grid.len()];
        let mut ground = vec![f32::NAN; grid.len()];
        let mut floor = f32::INFINITY;
        for &k in &kept {
            let p = prior.xyz[k];
            let Some((i, j)) = grid.cell_of(f64::from(p[0]), f64::from(p[1])) else {
                continue;
            };
            let c = j * grid.nx + i;
            let label = prior.label.as_ref().map_or(class::UNCLASSIFIED, |l| l[k]);
            if label == class::GROUND {
                floor = floor.min(p[2]);
                ground[c] = if ground[c].is_nan() {
                    p[2]
                } else {
                    ground[c].min(p[2])
                };
            }
            if top[c].is_nan() || p[2] > top[c] {
                top[c] = p[2];
            }
            building[c] |= label == class::BUILDING;
        }
        if !floor.is_finite() {
            floor = top
                .iter()
                .copied()
                .filter(|v| v.is_finite())
                .fold(f32::INFINITY, f32::min);
        }
        fill_gaps(&grid, &mut top, floor);
        let other = body_radius + rules.margin_m;
        let kept = (rules.facade_min_m.max(other), other);
        let floor = grown_floor(&grid, &top, &building, kept);
        Ok(Self {
            rules,
            body_radius,
            home,
            grid,
            top,
            building,
            ground,
            floor,
            fence: None,
        })
    }

    /// The same airspace, with the whole body kept inside `fence` too: its
    /// centre at least the body radius from the fence's edge (a flight
    /// tracks its way-points within centimetres, not exactly).
    pub fn with_fence(mut self, fence: Geofence) -> Self {
        self.fence = Some(inset(&fence, f64::from(self.body_radius)));
        self
    }

    /// Moves the take-off point to `home` (a pad sought over one airspace).
    pub fn set_home(&mut self, home: [f32; 3]) {
        self.home = home;
    }

    /// The rules it keeps.
    pub fn rules(&self) -> &AirspaceRules {
        &self.rules
    }

    /// `Ok` when the drone's body centre may be at `p`, else the first rule broken.
    pub fn check(&self, p: [f32; 3]) -> Result<(), Violation> {
        let (x, y) = (f64::from(p[0]), f64::from(p[1]));
        if self.grid.cell_of(x, y).is_none() {
            return Err(Violation::Unmapped { at: p });
        }
        let above_m = p[2] - self.home[2];
        if above_m > self.rules.ceiling_m {
            let ceiling_m = self.rules.ceiling_m;
            return Err(Violation::AboveCeiling {
                at: p,
                above_m,
                ceiling_m,
            });
        }
        if let Some(f) = &self.fence
            && !f.contains(&Coord { x, y })
        {
            return Err(Violation::OutsideFence { at: p });
        }
        let c = self.grid.clamped_cell(x, y);
        if p[2] >= self.floor[c.1 * self.grid.nx + c.0] {
            return Ok(());
        }
        // Under the grown floor: the exact search names what is near (and
        // lets the pad's own ground pass).
        self.too_close(p).map_or(Ok(()), Err)
    }

    /// `Ok` when every point of the polyline `path` (sampled every half
    /// cell) may be flown, else the first leg that breaks a rule.
    pub fn check_path(&self, path: &[[f32; 3]]) -> Result<(), Refusal> {
        let Some(&first) = path.first() else {
            return Ok(());
        };
        self.check(first)
            .map_err(|violation| Refusal { leg: 0, violation })?;
        let step = 0.5 * self.rules.cell_m;
        for (leg, w) in path.windows(2).enumerate() {
            let d = [w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]];
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let n = (len / step).ceil().max(1.0) as usize;
            for s in 1..=n {
                let t = s as f32 / n as f32;
                let p = std::array::from_fn(|k| w[0][k] + t * d[k]);
                self.check(p).map_err(|violation| Refusal {
                    leg: leg + 1,
                    violation,
                })?;
            }
        }
        Ok(())
    }

    /// Whether the straight line from `a` to `b` passes over every column
    /// of the height map, leaving out its last `skip_end_m` (the target's
    /// own surface).
    pub fn line_of_sight(&self, a: [f32; 3], b: [f32; 3], skip_end_m: f32) -> bool {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let step = 0.5 * self.rules.cell_m;
        let n = ((len - skip_end_m).max(0.0) / step).floor() as usize;
        (1..=n).all(|s| {
            let t = s as f32 * step / len;
            let p: [f32; 3] = std::array::from_fn(|k| a[k] + t * d[k]);
            self.grid
                .cell_of(f64::from(p[0]), f64::from(p[1]))
                .is_none_or(|(i, j)| self.top[j * self.grid.nx + i] <= p[2])
        })
    }

    /// The highest top of the height map, m.
    pub fn highest_top(&self) -> f32 {
        self.top.iter().copied().fold(f32::NEG_INFINITY, f32::max)
    }

    /// The take-off point (the body centre on the pad).
    pub fn home(&self) -> [f32; 3] {
        self.home
    }

    /// The nearest obstacle that is closer to `p` than the rules keep from it.
    pub(super) fn too_close(&self, p: [f32; 3]) -> Option<Violation> {
        let other = self.body_radius + self.rules.margin_m;
        let near_building = self.rules.facade_min_m.max(other);
        let dx = p[0] - self.home[0];
        let dy = p[1] - self.home[1];
        let on_pad = dx.hypot(dy) <= PAD_RADIUS_M && p[2] <= self.home[2] + other;
        let reach = f64::from(near_building.max(other));
        let g = &self.grid;
        let (x, y) = (f64::from(p[0]), f64::from(p[1]));
        let (i0, j0) = g.key(x - reach, y - reach);
        let (i1, j1) = g.key(x + reach, y + reach);
        let mut worst: Option<Violation> = None;
        let mut worst_gap = 0.0f32;
        for j in j0..=j1 {
            for i in i0..=i1 {
                let Some(c) = g.index(i, j) else { continue };
                let is_building = self.building[c];
                if on_pad && !is_building {
                    continue;
                }
                let required = if is_building { near_building } else { other };
                let lo = [
                    g.origin[0] + i as f64 * g.cell,
                    g.origin[1] + j as f64 * g.cell,
                ];
                let ddx = (lo[0] - x).max(0.0).max(x - (lo[0] + g.cell)) as f32;
                let ddy = (lo[1] - y).max(0.0).max(y - (lo[1] + g.cell)) as f32;
                let dz = (p[2] - self.top[c]).max(0.0);
                let d = (ddx * ddx + ddy * ddy + dz * dz).sqrt();
                if d < required && required - d > worst_gap {
                    worst_gap = required - d;
                    let what = if is_building {
                        Obstacle::Building
                    } else {
                        Obstacle::Other
                    };
                    worst = Some(Violation::TooClose {
                        at: p,
                        what,
                        distance_m: d,
                        required_m: required,
                    });
                }
            }
        }
        worst
    }
}

/// Fills the empty cells of `top` from their neighbours (the highest within
/// [`FILL_CELLS`]), then the rest at `floor`.
fn fill_gaps(grid: &GridFrame, top: &mut [f32], floor: f32) {
    for _ in 0..FILL_CELLS {
        let before = top.to_vec();
        for j in 0..grid.ny as i64 {
            for i in 0..grid.nx as i64 {
                let c = j as usize * grid.nx + i as usize;
                if !before[c].is_nan() {
                    continue;
                }
                let mut best = f32::NAN;
                for &(di, dj) in Neighbours::Eight.offsets() {
                    if let Some(n) = grid.index(i + di as i64, j + dj as i64)
                        && !before[n].is_nan()
                        && (best.is_nan() || before[n] > best)
                    {
                        best = before[n];
                    }
                }
                top[c] = best;
            }
        }
    }
    for t in top.iter_mut().filter(|t| t.is_nan()) {
        *t = floor;
    }
}

/// Per cell, the lowest height at which a point is at least `kept.0` from
/// every building column and `kept.1` from every other column of the
/// height map (columns are solid from the ground to their top): the upper
/// envelope of the columns grown by a ball, max over the cells within reach
/// of `top + √(r² − d²)`, `d` the horizontal distance between the cells.
/// One lookup then answers what the search over the neighbours would.
fn grown_floor(grid: &GridFrame, top: &[f32], building: &[bool], kept: (f32, f32)) -> Vec<f32> {
    use rayon::prelude::*;
    let reach = kept.0.max(kept.1);
    let w = (f64::from(reach) / grid.cell).ceil() as i64;
    let cell = grid.cell as f32;
    (0..grid.len())
        .into_par_iter()
        .map(|c| {
            let (i, j) = ((c % grid.nx) as i64, (c / grid.nx) as i64);
            let mut floor = f32::NEG_INFINITY;
            for dj in -w..=w {
                for di in -w..=w {
                    let Some(n) = grid.index(i + di, j + dj) else {
                        continue;
                    };
                    let r = if building[n] { kept.0 } else { kept.1 };
                    // Nearest distance between two cells' squares.
                    let gap = |d: i64| (d.abs() - 1).max(0) as f32 * cell;
                    let d2 = gap(di).powi(2) + gap(dj).powi(2);
                    if d2 < r * r {
                        floor = floor.max(top[n] + (r * r - d2).sqrt());
                    }
                }
            }
            floor
        })
        .collect()
}
