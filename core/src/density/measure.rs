//! Points per m² over the ground the cloud covers, robust to voids,
//! strip overlaps and ragged edges.

use rayon::prelude::*;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

/// Side of the square cells the points are counted in, metres: 2 m holds
/// ~8 points at 2 pts/m² (so almost no cell of a covered area is empty)
/// and is small next to the voids (water, courtyards) it should leave out.
pub const DENSITY_CELL_M: f32 = 2.0;

/// A cloud's sampling density.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Density {
    /// Points per m²: the median point count of the occupied
    /// [`DENSITY_CELL_M`] cells over their area. The median ignores empty
    /// cells (voids, water), half-covered edge cells and double-covered strip
    /// overlaps, which a count over the bounding box does not.
    pub points_per_m2: f32,
    /// Mean distance between neighbouring points, `1 / √points_per_m2`, metres.
    pub spacing_m: f32,
    /// Area of the occupied cells, m².
    pub occupied_m2: f32,
    /// Points counted.
    pub points: usize,
}

impl Density {
    /// A density given in points per m² (`None` unless finite and > 0).
    pub fn from_points_per_m2(points_per_m2: f32) -> Option<Self> {
        (points_per_m2.is_finite() && points_per_m2 > 0.0).then(|| Self {
            points_per_m2,
            spacing_m: 1.0 / points_per_m2.sqrt(),
            occupied_m2: f32::NAN,
            points: 0,
        })
    }

    /// Measures the density of `xyz` (xy only; non-finite points are
    /// skipped). `None` for a cloud without a finite point.
    pub fn measure(xyz: &[[f32; 3]]) -> Option<Self> {
        Self::measure_where(xyz, |_| true)
    }

    /// Measures the density of the points of `xyz` whose index passes `keep`
    /// (e.g. one class).
    pub fn measure_where(xyz: &[[f32; 3]], keep: impl Fn(usize) -> bool + Sync) -> Option<Self> {
        let cells: FxHashMap<(i64, i64), u32> = xyz
            .par_iter()
            .enumerate()
            .filter(|(i, p)| p[0].is_finite() && p[1].is_finite() && keep(*i))
            .fold(FxHashMap::default, |mut m, (_, p)| {
                *m.entry(cell_of(p)).or_insert(0) += 1;
                m
            })
            .reduce(FxHashMap::default, |a, b| {
                // Fold the smaller map into the larger one.
                if a.len() >= b.len() {
                    merge(a, b)
                } else {
                    merge(b, a)
                }
            });
        let points: usize = cells.values().map(|&c| c as usize).sum();
        if points == 0 {
            return None;
        }
        let mut counts: Vec<u32> = cells.values().copied().collect();
        let mid = counts.len() / 2;
        let (_, median, _) = counts.select_nth_unstable(mid);
        let area = DENSITY_CELL_M * DENSITY_CELL_M;
        let points_per_m2 = *median as f32 / area;
        Some(Self {
            points_per_m2,
            spacing_m: 1.0 / points_per_m2.sqrt(),
            occupied_m2: cells.len() as f32 * area,
            points,
        })
    }
}

fn cell_of(p: &[f32; 3]) -> (i64, i64) {
    (
        (p[0] / DENSITY_CELL_M).floor() as i64,
        (p[1] / DENSITY_CELL_M).floor() as i64,
    )
}

fn merge(
    mut into: FxHashMap<(i64, i64), u32>,
    from: FxHashMap<(i64, i64), u32>,
) -> FxHashMap<(i64, i64), u32> {
    for (k, v) in from {
        *into.entry(k).or_insert(0) += v;
    }
    into
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A regular grid of `per_m` × `per_m` points per m² over `w` × `h` m.
    fn grid(w: f32, h: f32, step: f32) -> Vec<[f32; 3]> {
        let mut v = Vec::new();
        let (nx, ny) = ((w / step) as usize, (h / step) as usize);
        for j in 0..ny {
            for i in 0..nx {
                v.push([(i as f32 + 0.5) * step, (j as f32 + 0.5) * step, 0.0]);
            }
        }
        v
    }

    #[test]
    fn regular_grids_give_their_density() {
        for (step, want) in [
            (0.5, 4.0),
            (0.25, 16.0),
            (std::f32::consts::FRAC_1_SQRT_2, 2.0),
        ] {
            let d = Density::measure(&grid(100.0, 60.0, step)).unwrap();
            assert!(
                (d.points_per_m2 - want).abs() / want < 0.13,
                "step {step}: {} pts/m² (want {want})",
                d.points_per_m2
            );
            assert!((d.spacing_m - step).abs() / step < 0.07, "{}", d.spacing_m);
        }
    }

    #[test]
    fn voids_and_a_doubled_strip_do_not_move_the_median() {
        // 4 pts/m² over 100 × 100 m, a 40 m lake without returns, a 20 m
        // strip scanned twice: the bounding-box mean would be 3.6 pts/m².
        let mut pts: Vec<[f32; 3]> = grid(100.0, 100.0, 0.5)
            .into_iter()
            .filter(|p| !((30.0..70.0).contains(&p[0]) && (30.0..70.0).contains(&p[1])))
            .collect();
        let strip: Vec<[f32; 3]> = pts.iter().filter(|p| p[1] < 20.0).copied().collect();
        pts.extend(strip);
        let d = Density::measure(&pts).unwrap();
        assert!((d.points_per_m2 - 4.0).abs() < 0.3, "{}", d.points_per_m2);
        assert!((d.occupied_m2 - 8400.0).abs() < 200.0, "{}", d.occupied_m2);
    }

    #[test]
    fn no_finite_point_is_none_and_filters_apply() {
        assert!(Density::measure(&[]).is_none());
        assert!(Density::measure(&[[f32::NAN, 0.0, 0.0]]).is_none());
        let pts = grid(50.0, 50.0, 0.5);
        assert!(Density::measure_where(&pts, |_| false).is_none());
        let half = Density::measure_where(&pts, |i| i % 4 == 0).unwrap();
        assert!(
            (half.points_per_m2 - 1.0).abs() < 0.15,
            "{}",
            half.points_per_m2
        );
        assert!(Density::from_points_per_m2(0.0).is_none());
        assert_eq!(Density::from_points_per_m2(4.0).unwrap().spacing_m, 0.5);
    }
}
