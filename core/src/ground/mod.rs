//! Ground filtering by the Cloth Simulation Filter (Zhang et al. 2016),
//! docs/design.md step 1, and every point's height above the terrain it finds.
//!
//! The cloud is turned upside down (z → −z) and a cloth of particles is
//! dropped onto it from above: gravity pulls the particles down, springs
//! between neighbours keep the cloth stiff, and a particle stops where it
//! reaches the inverted surface. Stiff cloth rests on the (inverted) ground
//! but does not sink into the pits that buildings and trees become. Points
//! within `class_threshold` of the cloth are ground; the cloth, turned back,
//! is the terrain model.

mod cloth;
mod dtm;
mod error;
mod fill;
mod grid;
mod params;
mod raised;
mod smoothing;
mod surface;

use rayon::prelude::*;

pub use dtm::Dtm;
pub(crate) use dtm::xy_extent;
pub use error::CsfError;
pub use params::CsfParams;
pub use raised::Raised;

use crate::density::Density;
use crate::geom::grid::{GridFrame, square_filter};

/// What [`csf`] finds: ground or not, and height above the terrain, per point.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundSplit {
    /// `true` for ground points, one per input point (`false` for points
    /// with a non-finite coordinate).
    pub is_ground: Vec<bool>,
    /// Height of each point above the terrain model, metres (NaN exactly
    /// for points with a non-finite coordinate).
    pub hag: Vec<f32>,
    /// The terrain model: the settled cloth turned back up, bridged parts
    /// filled smoothly from where it touched.
    pub dtm: Dtm,
    /// Simulation steps run before the cloth settled (or the step limit).
    pub iterations_run: u32,
    /// The density measured over the finite points.
    pub density: Density,
    /// The parameters used: `auto` resolved for that density.
    pub params: CsfParams,
    /// Ground the cloth rested on that stands on a step (a roof where the
    /// survey ends), taken out of the ground.
    pub raised: Raised,
}

/// Splits `xyz` into ground and the rest with the Cloth Simulation Filter
/// and measures every point's height above the terrain.
///
/// Points with NaN or infinite coordinates are skipped (not ground); an
/// empty cloud, a cloud with no finite point or invalid `params` is an error.
pub fn csf(xyz: &[[f32; 3]], params: &CsfParams) -> Result<GroundSplit, CsfError> {
    params.validate()?;
    if xyz.is_empty() {
        return Err(CsfError::Empty);
    }
    let finite: Vec<[f32; 3]> = xyz
        .par_iter()
        .filter(|p| p.iter().all(|v| v.is_finite()))
        .copied()
        .collect();
    let no_finite = CsfError::NoFinitePoints { count: xyz.len() };
    let (lo, hi) = xy_bounds(&finite).ok_or(no_finite.clone())?;
    let density = Density::measure(&finite).ok_or(no_finite)?;
    let resolved = params.resolved(&density);
    let threshold = params.class_threshold_for(&density);
    let cloth_cell = params.cloth_resolution_for(&density);
    let lattice = grid::covering(lo, hi, cloth_cell)?;
    let min_points = void_below(&density, cloth_cell);
    let surface = surface::inverted_surface(&lattice, &finite, min_points);
    let mut cloth = cloth::simulate(&lattice, &surface, params);
    if params.slope_smoothing {
        smoothing::smooth_slopes(
            &lattice,
            &surface,
            &mut cloth.z,
            &mut cloth.fixed,
            params.slope_threshold,
        );
    }
    fill::fill_bridged(&lattice, &mut cloth.z, &cloth.fixed);
    let heights: Vec<f32> = cloth.z.par_iter().map(|z| -z).collect();
    let mut dtm = Dtm {
        frame: lattice,
        heights,
    };
    let (mut is_ground, mut hag) = split(xyz, &dtm, threshold);
    let settings = raised::Settings {
        cell: (RAISED_SPACINGS * density.spacing_m).max(RAISED_MIN_CELL),
        // The cloth hangs from a raised piece's edge over about one of its cells.
        band_m: cloth_cell,
        void_below: min_points,
        step_m: params.raised_step_m,
        max_m2: params.raised_max_m2,
    };
    let (on_step, raised) = raised::find(xyz, &is_ground, &settings);
    if raised.pieces > 0 {
        let held = held_terrain(&dtm.frame, xyz, &is_ground, &on_step);
        fill::fill_bridged(&dtm.frame, &mut dtm.heights, &held);
        (is_ground, hag) = split(xyz, &dtm, threshold);
    }
    Ok(GroundSplit {
        is_ground,
        hag,
        dtm,
        iterations_run: cloth.steps,
        density,
        params: resolved,
        raised,
    })
}

/// The terrain model's cells that keep their height once raised pieces
/// are taken out; the others are filled from them. Let go: the cells over a
/// raised point, and every cell reached from them through cells with no
/// kept ground point in them or in the eight round them (the lattice's
/// margin past a roof at the survey's edge copies the roof's height, and
/// the cloth rests there too). So the terrain under kept ground, which
/// interpolates only the cells round its own, does not move.
fn held_terrain(
    frame: &GridFrame,
    xyz: &[[f32; 3]],
    is_ground: &[bool],
    raised: &[bool],
) -> Vec<bool> {
    let index = |p: &[f32; 3]| frame.clamped_index(f64::from(p[0]), f64::from(p[1]));
    let mut keeps_ground = vec![false; frame.len()];
    for (p, _) in xyz
        .iter()
        .zip(is_ground.iter().zip(raised))
        .filter(|(_, (g, r))| **g && !**r)
    {
        keeps_ground[index(p)] = true;
    }
    let near_ground = square_filter(&keeps_ground, frame.nx, frame.ny, 1, true);
    let mut seen = vec![false; frame.len()];
    let mut todo: Vec<usize> = Vec::new();
    for (p, _) in xyz.iter().zip(raised).filter(|(_, r)| **r) {
        let k = index(p);
        if !seen[k] {
            seen[k] = true;
            todo.push(k);
        }
    }
    while let Some(k) = todo.pop() {
        for m in frame.neighbours(k) {
            if !seen[m] && !near_ground[m] {
                seen[m] = true;
                todo.push(m);
            }
        }
    }
    seen.iter().map(|s| !s).collect()
}

/// Ground cells for [`raised::find`] are this many point spacings wide...
const RAISED_SPACINGS: f32 = 2.0;
/// ...and at least this wide, metres.
const RAISED_MIN_CELL: f32 = 1.0;

/// Ground (within `threshold` of the terrain) and height above it, per
/// point; non-finite points are not ground and have a NaN height.
fn split(xyz: &[[f32; 3]], dtm: &Dtm, threshold: f32) -> (Vec<bool>, Vec<f32>) {
    xyz.par_iter()
        .map(|p| {
            if !p.iter().all(|v| v.is_finite()) {
                return (false, f32::NAN);
            }
            let above = p[2] - dtm.height_at(p[0], p[1]);
            (above.abs() < threshold, above)
        })
        .unzip()
}

/// Share of the points a cloth cell of the measured density holds below
/// which the cell is a data void (water returns little, occlusions none):
/// a few stray returns there would pull the cloth down to them.
const VOID_SHARE: f32 = 0.1;

/// Fewest points a particle's cell (`cell` wide) needs to take part in the
/// cloth: [`VOID_SHARE`] of what the density `d` puts there, at least one.
fn void_below(d: &Density, cell: f32) -> u32 {
    ((VOID_SHARE * d.points_per_m2 * cell * cell).floor() as u32).max(1)
}

fn xy_bounds(points: &[[f32; 3]]) -> Option<([f32; 2], [f32; 2])> {
    if points.is_empty() {
        return None;
    }
    let init = || ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    Some(
        points
            .par_iter()
            .fold(init, |(lo, hi), p| {
                (
                    [lo[0].min(p[0]), lo[1].min(p[1])],
                    [hi[0].max(p[0]), hi[1].max(p[1])],
                )
            })
            .reduce(init, |(a, b), (c, d)| {
                (
                    [a[0].min(c[0]), a[1].min(c[1])],
                    [b[0].max(d[0]), b[1].max(d[1])],
                )
            }),
    )
}
