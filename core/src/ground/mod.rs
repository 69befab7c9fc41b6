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
mod smoothing;
mod surface;

use rayon::prelude::*;

pub use dtm::Dtm;
pub(crate) use dtm::xy_extent;
pub use error::CsfError;
pub use params::CsfParams;

use crate::density::Density;

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
    let lattice = grid::covering(lo, hi, params.cloth_resolution_for(&density))?;
    let min_points = void_below(&density, params.cloth_resolution_for(&density));
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
    let dtm = Dtm {
        frame: lattice,
        heights,
    };
    let (is_ground, hag): (Vec<bool>, Vec<f32>) = xyz
        .par_iter()
        .map(|p| {
            if !p.iter().all(|v| v.is_finite()) {
                return (false, f32::NAN);
            }
            let above = p[2] - dtm.height_at(p[0], p[1]);
            (above.abs() < threshold, above)
        })
        .unzip();
    Ok(GroundSplit {
        is_ground,
        hag,
        dtm,
        iterations_run: cloth.steps,
        density,
        params: resolved,
    })
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
