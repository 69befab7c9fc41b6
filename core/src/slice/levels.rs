//! Slice heights of one building and the contour of each slice.
//!
//! A slice's contour is the outline of everything the building holds at or
//! above the slice's bottom (the projection of its points with z ≥ the band's
//! lower edge): roofs are sampled densely from the air while walls often are
//! not, so this outline stays whole where the slice's own wall points are
//! missing — which is exactly where the detector must look.

use geo::MultiPolygon;
use serde::{Deserialize, Serialize};

use super::contour::occupancy_contour;
use super::raster::Raster;
use crate::density::{Auto, Density};
use crate::params::{Checks, ParamError};

/// Finest outline raster cell, metres: the value tuned on the reference
/// prior, kept wherever points are denser than 4 pts/m².
const MIN_CELL: f64 = 0.5;
/// Thinnest slice, metres (the reference prior's 1 m).
const MIN_SPACING: f32 = 1.0;
/// Thickest slice, metres: about a storey, so a one-storey gap still shows.
const MAX_SPACING: f32 = 3.0;
/// Points per m² of surface a slice band should hold per metre of wall
/// height × its thickness: 4 pts/m² × 1 m, where the 1 m slices were tuned.
const SLICE_POINTS_PER_M: f32 = 4.0;

/// How a building is cut into slices and outlined.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SliceParams {
    /// Vertical distance between slice centres, metres (also the band
    /// thickness); `auto`: [`SliceParams::spacing_rule`].
    pub spacing: Auto<f32>,
    /// Height of the first slice centre above the building's ground, metres.
    pub first: f32,
    /// Raster cell of the xy outline, metres; `auto`: [`SliceParams::cell_rule`].
    pub cell: Auto<f64>,
    /// Closing radius that bridges sparse sampling, metres; `auto`: two cells.
    pub closing: Auto<f64>,
    /// Douglas–Peucker tolerance that removes the raster staircase, metres.
    pub simplify: f64,
    /// Outline parts smaller than this are dropped, m².
    pub min_area: f64,
}

impl Default for SliceParams {
    fn default() -> Self {
        SliceParams {
            spacing: Auto::Auto,
            first: 0.5,
            cell: Auto::Auto,
            closing: Auto::Auto,
            simplify: 0.4,
            min_area: 4.0,
        }
    }
}

impl SliceParams {
    /// `spacing: auto` for points `spacing_m` apart: thick enough that a band
    /// holds as many wall returns per metre as 1 m did at 4 pts/m²
    /// (thickness = 4 / density), between 1 m and a storey (3 m).
    pub fn spacing_rule(spacing_m: f32) -> f32 {
        (SLICE_POINTS_PER_M * spacing_m * spacing_m).clamp(MIN_SPACING, MAX_SPACING)
    }

    /// `cell: auto`: about the point spacing, never finer than 0.5 m (the
    /// reference prior's value: finer cells only split sparse roofs).
    pub fn cell_rule(spacing_m: f32) -> f64 {
        f64::from(spacing_m).max(MIN_CELL)
    }

    /// Slice spacing in use (the rule at high density while still `auto`).
    pub fn spacing_m(&self) -> f32 {
        self.spacing.or_rule(|| Self::spacing_rule(0.0))
    }

    /// Outline cell in use (the rule at high density while still `auto`).
    pub fn cell_m(&self) -> f64 {
        self.cell.or_rule(|| Self::cell_rule(0.0))
    }

    /// Closing radius in use: two cells while `auto`.
    pub fn closing_m(&self) -> f64 {
        self.closing.or_rule(|| 2.0 * self.cell_m())
    }

    /// These parameters with every `auto` resolved for building points of
    /// density `d`.
    pub fn resolved(&self, d: &Density) -> Self {
        let cell = self.cell.resolved(|| Self::cell_rule(d.spacing_m));
        let resolved_cell = Self {
            cell,
            ..self.clone()
        };
        Self {
            spacing: self.spacing.resolved(|| Self::spacing_rule(d.spacing_m)),
            cell,
            closing: Auto::Value(resolved_cell.closing_m()),
            ..self.clone()
        }
    }

    /// Checks every field is usable.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("slice");
        c.positive("spacing", self.spacing_m())?;
        c.positive("cell", self.cell_m())?;
        c.positive("min_area", self.min_area)?;
        c.non_negative("closing", self.closing_m())?;
        c.non_negative("simplify", self.simplify)?;
        // A slice below the ground would cut the terrain, not the walls.
        let above = self.first.is_finite() && self.first >= 0.0;
        c.that(
            above,
            "first",
            self.first,
            "must be ≥ 0 (height above ground)",
        )
    }
}

/// One slice of a building.
#[derive(Debug, Clone)]
pub struct Level {
    /// Height of the slice centre, metres (local frame).
    pub height: f32,
    /// Lower and upper edge of the band of points tested at this slice.
    pub band: [f32; 2],
    /// Number of building points in the band.
    pub points: usize,
    /// Component label per raster cell (`u32::MAX` = free).
    pub labels: Vec<u32>,
    /// Contour of each component kept (component label, outline).
    pub parts: Vec<(u32, MultiPolygon<f64>)>,
    /// Cell count per component label.
    pub sizes: Vec<usize>,
}

/// A building cut into slices.
#[derive(Debug, Clone)]
pub struct Sliced {
    /// Ground height used, metres.
    pub ground_z: f32,
    /// Highest point, metres.
    pub top_z: f32,
    /// Grid geometry shared by every level (occupancy left empty).
    pub grid: Raster,
    /// Highest point per grid cell (`-inf` where none): the local roof.
    pub top: Vec<f32>,
    /// Outline of the whole building (C_building when no footprint is given).
    pub global: MultiPolygon<f64>,
    /// Slices from the lowest up.
    pub levels: Vec<Level>,
}

/// Slices `points` (finite ones only) from `ground_z` (default: their lowest
/// z) to their top. None when there are no finite points.
pub fn slice_building(
    points: &[[f32; 3]],
    ground_z: Option<f32>,
    params: &SliceParams,
) -> Option<Sliced> {
    let finite = || points.iter().filter(|p| p.iter().all(|v| v.is_finite()));
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    let (mut zmin, mut zmax) = (f32::MAX, f32::MIN);
    let mut any = false;
    for p in finite() {
        any = true;
        for k in 0..2 {
            lo[k] = lo[k].min(p[k] as f64);
            hi[k] = hi[k].max(p[k] as f64);
        }
        zmin = zmin.min(p[2]);
        zmax = zmax.max(p[2]);
    }
    if !any {
        return None;
    }
    let ground_z = ground_z.filter(|g| g.is_finite()).unwrap_or(zmin);
    let (cell, closing, spacing) = (params.cell_m(), params.closing_m(), params.spacing_m());
    let pad = (closing / cell).ceil() as usize + 2;
    let mut grid = Raster::covering(lo, hi, cell, pad);
    let mut top = vec![f32::NEG_INFINITY; grid.frame.len()];
    for p in finite() {
        if let Some((i, j)) = grid.cell_of(p[0] as f64, p[1] as f64) {
            let t = &mut top[j * grid.frame.nx + i];
            *t = t.max(p[2]);
        }
    }
    let r = (closing / cell).round() as usize;
    let outline = |floor: f32| -> Raster {
        let mut occ = grid.clone();
        occ.occupied = top
            .iter()
            .map(|&t| t > f32::NEG_INFINITY && t >= floor)
            .collect();
        occ.close(r);
        occ
    };
    let whole = outline(f32::NEG_INFINITY);
    let global = occupancy_contour(&whole, None, params.simplify, params.min_area);

    let half = spacing / 2.0;
    let mut heights = Vec::new();
    let mut h = ground_z + params.first.max(half);
    while h - half < zmax && heights.len() < 10_000 {
        heights.push(h);
        h += spacing;
    }
    let mut counts = vec![0usize; heights.len()];
    let base = heights.first().map_or(0.0, |h| h - half);
    for p in finite() {
        let k = ((p[2] - base) / spacing).floor();
        if k >= 0.0 && (k as usize) < counts.len() {
            counts[k as usize] += 1;
        }
    }
    let min_cells = (params.min_area / (cell * cell)).ceil() as usize;
    let levels = heights
        .iter()
        .zip(counts)
        .map(|(&height, n)| {
            let occ = outline(height - half);
            let (labels, sizes) = occ.components();
            let parts = (0..sizes.len() as u32)
                .filter(|&c| sizes[c as usize] >= min_cells)
                .map(|c| {
                    let keep = |k: usize| labels[k] == c;
                    (
                        c,
                        occupancy_contour(&occ, Some(&keep), params.simplify, params.min_area),
                    )
                })
                .filter(|(_, mp)| !mp.0.is_empty())
                .collect();
            Level {
                height,
                band: [height - half, height + half],
                points: n,
                labels,
                parts,
                sizes,
            }
        })
        .collect();
    grid.occupied.clear();
    Some(Sliced {
        ground_z,
        top_z: zmax,
        grid,
        top,
        global,
        levels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::Area;

    /// Podium 20 × 20 m to 6 m, tower 8 × 8 m on it to 20 m: roof grids only.
    fn podium_tower() -> Vec<[f32; 3]> {
        let mut pts = Vec::new();
        for i in 0..80 {
            for j in 0..80 {
                let (x, y) = (i as f32 * 0.25, j as f32 * 0.25);
                let tower = (6.0..14.0).contains(&x) && (6.0..14.0).contains(&y);
                pts.push([x, y, if tower { 20.0 } else { 6.0 }]);
            }
        }
        pts.push([0.0, 0.0, 0.0]);
        pts
    }

    #[test]
    fn podium_and_tower_levels() {
        let s = slice_building(&podium_tower(), None, &SliceParams::default()).unwrap();
        assert_eq!(s.levels.len(), 20);
        let area = |l: &Level| l.parts.iter().map(|(_, m)| m.unsigned_area()).sum::<f64>();
        let low = area(&s.levels[2]);
        let high = area(&s.levels[10]);
        assert!((low - 400.0).abs() < 30.0, "{low}");
        assert!((high - 64.0).abs() < 12.0, "{high}");
        assert!(
            (s.global.unsigned_area() - 400.0).abs() < 30.0,
            "{}",
            s.global.unsigned_area()
        );
    }

    #[test]
    fn bad_params_and_empty_points() {
        let p = SliceParams {
            spacing: Auto::Value(0.0),
            ..SliceParams::default()
        };
        assert!(p.validate().is_err());
        assert!(slice_building(&[], None, &SliceParams::default()).is_none());
        assert!(slice_building(&[[f32::NAN, 0.0, 0.0]], None, &SliceParams::default()).is_none());
    }
}
