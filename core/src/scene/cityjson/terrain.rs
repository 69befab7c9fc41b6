//! A ground surface under loaded buildings: a regular grid over each
//! building's footprint box plus a margin, at the buildings' base heights.
//!
//! Height at a grid vertex: inside one or more footprint boxes, the highest
//! of their bases (so no wall floats above the ground); outside, an inverse
//! distance blend of the nearby bases (flat near each building, smooth in
//! between). Buildings far apart (a city-wide sample) get separate patches.

use std::collections::{BTreeSet, HashMap};

use crate::scene::builder::MeshPart;

/// Where a building stands: its footprint's bounding box and base height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footprint {
    /// Minimum x, y.
    pub min: [f64; 2],
    /// Maximum x, y.
    pub max: [f64; 2],
    /// Lowest z of the building.
    pub base: f64,
}

impl Footprint {
    fn distance(&self, x: f64, y: f64) -> f64 {
        let dx = (self.min[0] - x).max(x - self.max[0]).max(0.0);
        let dy = (self.min[1] - y).max(y - self.max[1]).max(0.0);
        (dx * dx + dy * dy).sqrt()
    }
}

/// How the ground under loaded buildings is made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TerrainOptions {
    /// Ground reaches this far beyond each footprint box, metres.
    pub margin: f64,
    /// Grid cell size, metres (grown when the grid would exceed 4 M cells).
    pub cell: f64,
}

impl Default for TerrainOptions {
    fn default() -> Self {
        Self {
            margin: 30.0,
            cell: 2.0,
        }
    }
}

const MAX_CELLS: usize = 4_000_000;
const BUCKET: f64 = 128.0;

/// The ground mesh under `footprints` (empty when there are none).
pub fn terrain_around(footprints: &[Footprint], options: &TerrainOptions) -> MeshPart {
    let mut m = MeshPart::default();
    let margin = if options.margin.is_finite() {
        options.margin.max(0.0)
    } else {
        30.0
    };
    let mut cell = if options.cell.is_finite() && options.cell > 0.01 {
        options.cell
    } else {
        2.0
    };
    let Some(x0) = footprints
        .iter()
        .map(|f| f.min[0] - margin)
        .min_by(f64::total_cmp)
    else {
        return m;
    };
    let y0 = footprints
        .iter()
        .map(|f| f.min[1] - margin)
        .fold(f64::INFINITY, f64::min);
    let cells_at = |cell: f64| -> f64 {
        footprints
            .iter()
            .map(|f| {
                ((f.max[0] - f.min[0] + 2.0 * margin) / cell + 2.0)
                    * ((f.max[1] - f.min[1] + 2.0 * margin) / cell + 2.0)
            })
            .sum()
    };
    while cells_at(cell) > MAX_CELLS as f64 {
        cell *= 2.0;
    }
    let index = |v: f64, o: f64| ((v - o) / cell).floor() as i64;
    let mut cells: BTreeSet<(i64, i64)> = BTreeSet::new();
    for f in footprints {
        for j in index(f.min[1] - margin, y0)..=index(f.max[1] + margin, y0) {
            for i in index(f.min[0] - margin, x0)..=index(f.max[0] + margin, x0) {
                cells.insert((j, i));
            }
        }
    }
    let near = Buckets::new(footprints, margin + 2.0 * cell);
    let mut ids: HashMap<(i64, i64), u32> = HashMap::new();
    let mut vertex = |m: &mut MeshPart, i: i64, j: i64| -> u32 {
        *ids.entry((i, j)).or_insert_with(|| {
            let (x, y) = (x0 + i as f64 * cell, y0 + j as f64 * cell);
            m.vertex([x, y, near.height(footprints, x, y)])
        })
    };
    for &(j, i) in &cells {
        let v00 = vertex(&mut m, i, j);
        let v10 = vertex(&mut m, i + 1, j);
        let v11 = vertex(&mut m, i + 1, j + 1);
        let v01 = vertex(&mut m, i, j + 1);
        m.triangle(v00, v10, v11);
        m.triangle(v00, v11, v01);
    }
    m
}

/// Footprints registered in square buckets, for finding those near a point.
struct Buckets {
    map: HashMap<(i64, i64), Vec<usize>>,
}

impl Buckets {
    fn new(footprints: &[Footprint], reach: f64) -> Self {
        let mut map: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        let b = |v: f64| (v / BUCKET).floor() as i64;
        for (k, f) in footprints.iter().enumerate() {
            for by in b(f.min[1] - reach)..=b(f.max[1] + reach) {
                for bx in b(f.min[0] - reach)..=b(f.max[0] + reach) {
                    map.entry((bx, by)).or_default().push(k);
                }
            }
        }
        Self { map }
    }

    fn height(&self, footprints: &[Footprint], x: f64, y: f64) -> f64 {
        let key = ((x / BUCKET).floor() as i64, (y / BUCKET).floor() as i64);
        let all: Vec<usize>;
        let candidates: &[usize] = match self.map.get(&key) {
            Some(c) => c,
            None => {
                all = (0..footprints.len()).collect();
                &all
            }
        };
        blend_bases(candidates.iter().map(|&k| {
            let f = &footprints[k];
            let d = f.distance(x, y);
            (d * d, f.base)
        }))
    }
}

/// Ground height from nearby building bases, given as (squared xy distance
/// to the footprint, base height): the highest base of a footprint the point
/// lies in, else an inverse-distance blend that is flat near each building
/// (0 without bases).
pub(crate) fn blend_bases(bases: impl IntoIterator<Item = (f64, f64)>) -> f64 {
    let mut inside = f64::NEG_INFINITY;
    let (mut sum, mut weight) = (0.0, 0.0);
    for (d2, base) in bases {
        if d2 == 0.0 {
            inside = inside.max(base);
        }
        let w = 1.0 / (1.0 + d2).powi(2);
        sum += w * base;
        weight += w;
    }
    if inside.is_finite() {
        inside
    } else if weight > 0.0 {
        sum / weight
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patch_covers_footprint_at_base_height() {
        let f = Footprint {
            min: [0.0, 0.0],
            max: [10.0, 6.0],
            base: 400.0,
        };
        let m = terrain_around(&[f], &TerrainOptions::default());
        assert!(!m.triangles.is_empty());
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &m.vertices {
            assert!((p[2] - 400.0).abs() < 1e-9);
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        assert!(lo[0] <= -30.0 && lo[1] <= -30.0 && hi[0] >= 40.0 && hi[1] >= 36.0);
        assert!(
            terrain_around(&[], &TerrainOptions::default())
                .triangles
                .is_empty()
        );
    }
}
