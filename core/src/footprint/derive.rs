//! Footprints from building points when no footprint file is given: an
//! occupancy grid, connected components cut at roof-height steps between
//! houses of a row (small and enclosed parts joined back), traced outlines
//! with courtyards kept, simplified.

use geo::{Area, Simplify};
use rayon::prelude::*;

use super::params::DeriveParams;
use super::polygon::union_valid;
use super::raster::{Cuts, Raster};
use super::trace::trace;
use super::types::Footprint;
use crate::density::Density;
use crate::params::ParamError;

/// Derives one footprint per cluster of `building_points` (local frame), ids
/// 1.. by decreasing point count, named `derived_N`. Empty input gives none.
pub fn derive(
    building_points: &[[f32; 3]],
    params: &DeriveParams,
) -> Result<Vec<Footprint>, ParamError> {
    params.validate()?;
    let params = &match Density::measure(building_points) {
        Some(d) => params.resolved(&d),
        None => params.clone(),
    };
    let Some(r) = Raster::new(
        building_points,
        params.cell(),
        params.closing_cells as usize,
    ) else {
        return Ok(Vec::new());
    };
    let cell_area = r.frame.cell * r.frame.cell;
    let cuts = Cuts {
        jump: params.height_jump_m,
        valley: params.valley_m,
        valley_dilate: params.valley_dilate_cells as usize,
        min_part_cells: (params.min_part_m2 / cell_area).ceil() as usize,
        min_open: params.min_open_share,
    };
    let (label, n) = r.components(&cuts);
    let mut points = vec![0usize; n as usize];
    for (l, c) in label.iter().zip(&r.count) {
        if *l > 0 {
            points[(*l - 1) as usize] += *c as usize;
        }
    }
    let outlines = trace(
        &label,
        r.frame.nx,
        r.frame.ny,
        n,
        r.frame.origin,
        r.frame.cell,
    );
    // Cell edges lie up to a cell outside the points; half a cell back in
    // is the unbiased outline for points spread evenly up to the wall.
    let inset = r.frame.cell / 2.0;
    let mut kept: Vec<(usize, geo::MultiPolygon<f64>)> = outlines
        .into_par_iter()
        .zip(points)
        .filter(|(_, count)| *count >= params.min_points)
        .filter_map(|(mp, count)| {
            let mp = super::inset::inset(&mp, inset);
            let mp = if params.simplify_m > 0.0 {
                mp.simplify(params.simplify_m)
            } else {
                mp
            };
            let polys: Vec<_> = mp.0;
            let mp = union_valid(&polys).ok()?;
            (mp.unsigned_area() >= params.min_area_m2).then_some((count, mp))
        })
        .collect();
    kept.sort_by_key(|k| std::cmp::Reverse(k.0));
    Ok(kept
        .into_iter()
        .enumerate()
        .map(|(k, (_, polygon))| {
            let id = u32::try_from(k + 1).unwrap_or(u32::MAX);
            Footprint {
                id,
                polygon,
                name: format!("derived_{id}"),
            }
        })
        .collect())
}
