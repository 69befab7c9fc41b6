//! A file's ground surfaces at another height than its buildings: a
//! terrain in another vertical datum (ellipsoidal heights beside
//! orthometric ones differ by ~50 m in Switzerland and the Netherlands), or
//! exported with an offset. Buildings standing 50 m over their terrain (or
//! buried in it) leave the vehicle no way to reach a wall, so the file's
//! ground is moved to meet the buildings' bases by the median height
//! difference, where it is larger than [`MISMATCH_M`].

use std::collections::HashMap;

/// A median gap (m) between the bases and the file's ground above which the
/// ground is moved: bases of real models meet their terrain within a few
/// decimetres (3dfier's Delft test area: see the tests), kerbs and
/// basement ramps stay well below it.
pub const MISMATCH_M: f64 = 1.0;

/// Base samples look for ground vertices this near in plan, m.
const REACH_M: f64 = 10.0;

/// The height to add to the file's ground (`ground` vertices) so it meets
/// the buildings' `bases`: the median over base samples of the base height
/// minus the nearest ground vertex's within [`REACH_M`] in plan; 0 when it
/// is within [`MISMATCH_M`] or no base has ground near.
pub fn ground_shift(bases: &[[f64; 3]], ground: &[[f64; 3]]) -> f64 {
    let key = |p: &[f64; 3]| {
        (
            (p[0] / REACH_M).floor() as i64,
            (p[1] / REACH_M).floor() as i64,
        )
    };
    let mut cells: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, g) in ground.iter().enumerate() {
        if g.iter().all(|v| v.is_finite()) {
            cells.entry(key(g)).or_default().push(i);
        }
    }
    let mut gaps: Vec<f64> = Vec::new();
    for b in bases.iter().filter(|b| b.iter().all(|v| v.is_finite())) {
        let (ci, cj) = key(b);
        let mut best: Option<(f64, f64)> = None;
        for di in -1..=1 {
            for dj in -1..=1 {
                for &i in cells
                    .get(&(ci.saturating_add(di), cj.saturating_add(dj)))
                    .into_iter()
                    .flatten()
                {
                    let g = ground[i];
                    let d = (g[0] - b[0]).hypot(g[1] - b[1]);
                    if d <= REACH_M && best.is_none_or(|(bd, _)| d < bd) {
                        best = Some((d, b[2] - g[2]));
                    }
                }
            }
        }
        gaps.extend(best.map(|(_, gap)| gap));
    }
    if gaps.is_empty() {
        return 0.0;
    }
    gaps.sort_by(f64::total_cmp);
    let median = gaps[gaps.len() / 2];
    if median.abs() > MISMATCH_M {
        median
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(z: f64) -> Vec<[f64; 3]> {
        (0..20)
            .flat_map(|i| (0..20).map(move |j| [i as f64 * 5.0, j as f64 * 5.0, z]))
            .collect()
    }

    #[test]
    fn ground_in_another_datum_is_moved_to_the_bases() {
        let bases = [
            [20.0, 20.0, 400.0],
            [31.0, 20.0, 400.2],
            [20.0, 33.0, 399.9],
        ];
        assert!((ground_shift(&bases, &grid(350.0)) - 50.0).abs() < 1e-9);
        assert!((ground_shift(&bases, &grid(420.0)) + 20.0).abs() < 1e-9);
        // Within a metre: the file's ground as it is.
        assert_eq!(ground_shift(&bases, &grid(399.6)), 0.0);
        // No ground near any base (or none at all): nothing to compare.
        let far = [[500.0, 500.0, 400.0]];
        assert_eq!(ground_shift(&far, &grid(350.0)), 0.0);
        assert_eq!(ground_shift(&bases, &[]), 0.0);
        assert_eq!(ground_shift(&[], &grid(0.0)), 0.0);
        // Coordinates past i64's cells (a damaged file) are compared, not overflowed.
        assert_eq!(
            ground_shift(&[[1e300, 1e300, 0.0]], &[[1e300, 1e300, 0.0]]),
            0.0
        );
    }
}
