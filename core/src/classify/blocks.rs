//! The forest's votes on a large cloud, block by block: each block's
//! features are computed on its own points and those within a margin
//! around it, so its k-d trees stay the size of one block. One tree over a
//! 10 M-point tile spent its time missing the cache: features and forest
//! took 67.0 s there in one pass, 58.6 s in blocks of about 1 M points,
//! with the same labels for every point (docs/density.md).

use super::error::ClassifyError;
use super::model::Model;
use crate::features::compute::check_request;
use crate::features::{Echoes, compute_subset};

/// Clouds up to this many points are one block (the old single pass).
pub const BLOCK_POINTS: usize = 1_000_000;

/// Margin (m) of points around a block that its features see: beyond the
/// largest neighbourhood (3 m spheres on 0.5 m voxels, 1.5 m columns) and
/// the k nearest neighbours of any surveyed surface.
pub const MARGIN_M: f32 = 10.0;

/// The forest's class probabilities for the points `rows` of `xyz`, in that
/// order (`model.forest.classes()` columns each), computed in square
/// blocks of about `block_points` points of the cloud.
pub fn votes(
    xyz: &[[f32; 3]],
    hag: &[f32],
    echoes: Option<Echoes<'_>>,
    rows: &[usize],
    model: &Model,
    block_points: usize,
) -> Result<Vec<f32>, ClassifyError> {
    // Bad input is refused before any block is cut, with the whole cloud's
    // point numbers, as the single pass refuses it.
    check_request(xyz, hag, echoes.as_ref(), rows, &model.feature_params)?;
    let forest = model.forest_for(echoes.is_some());
    let Some(grid) = Grid::new(xyz, rows, block_points) else {
        let f = compute_subset(xyz, hag, echoes, rows, &model.feature_params)?;
        return Ok(forest.predict_proba(&f.data)?);
    };
    let classes = forest.classes().len();
    let mut out = vec![0.0f32; rows.len() * classes];
    // Which rows (positions in `rows`) fall in which block.
    let mut own: Vec<Vec<usize>> = vec![Vec::new(); grid.n * grid.n];
    for (k, &r) in rows.iter().enumerate() {
        own[grid.block_of(xyz[r])].push(k);
    }
    for (b, mine) in own.iter().enumerate().filter(|(_, m)| !m.is_empty()) {
        let (lo, hi) = grid.bounds(b, MARGIN_M);
        let inside = |p: &[f32; 3]| p[0] >= lo[0] && p[0] < hi[0] && p[1] >= lo[1] && p[1] < hi[1];
        let sub: Vec<usize> = (0..xyz.len()).filter(|&i| inside(&xyz[i])).collect();
        let sxyz: Vec<[f32; 3]> = sub.iter().map(|&i| xyz[i]).collect();
        let shag: Vec<f32> = sub.iter().map(|&i| hag[i]).collect();
        let echo_cols = echoes.as_ref().map(|e| {
            let pick = |col: &[u8]| {
                sub.iter()
                    .map(|&i| col.get(i).copied().unwrap_or(0))
                    .collect()
            };
            (pick(e.return_number), pick(e.number_of_returns))
        });
        let sechoes = echo_cols
            .as_ref()
            .map(|(rn, nr): &(Vec<u8>, Vec<u8>)| Echoes {
                return_number: rn,
                number_of_returns: nr,
            });
        // Each own point's index in the block's cloud (`sub` is sorted).
        let srows: Vec<usize> = mine
            .iter()
            .filter_map(|&k| sub.binary_search(&rows[k]).ok())
            .collect();
        let proba = if srows.len() == mine.len() {
            let f = compute_subset(&sxyz, &shag, sechoes, &srows, &model.feature_params)?;
            forest.predict_proba(&f.data)?
        } else {
            // Unreachable by construction (a block's own points lie inside
            // its margin); the whole cloud still gives their features.
            let whole: Vec<usize> = mine.iter().map(|&k| rows[k]).collect();
            let f = compute_subset(xyz, hag, echoes, &whole, &model.feature_params)?;
            forest.predict_proba(&f.data)?
        };
        for (j, &k) in mine.iter().enumerate() {
            out[k * classes..(k + 1) * classes]
                .copy_from_slice(&proba[j * classes..(j + 1) * classes]);
        }
    }
    Ok(out)
}

/// An n × n grid of square blocks over the rows' plan extent.
struct Grid {
    min: [f32; 2],
    side: f32,
    n: usize,
}

impl Grid {
    /// None when the cloud is one block.
    fn new(xyz: &[[f32; 3]], rows: &[usize], block_points: usize) -> Option<Self> {
        let n = (xyz.len() as f64 / block_points.max(1) as f64)
            .sqrt()
            .ceil() as usize;
        if n <= 1 || rows.is_empty() {
            return None;
        }
        let (mut min, mut max) = ([f32::MAX; 2], [f32::MIN; 2]);
        for &r in rows {
            for a in 0..2 {
                min[a] = min[a].min(xyz[r][a]);
                max[a] = max[a].max(xyz[r][a]);
            }
        }
        let side = (max[0] - min[0]).max(max[1] - min[1]) / n as f32;
        (side.is_finite() && side > 2.0 * MARGIN_M).then_some(Self { min, side, n })
    }

    fn block_of(&self, p: [f32; 3]) -> usize {
        let cell = |a: usize| {
            (((p[a] - self.min[a]) / self.side).floor().max(0.0) as usize).min(self.n - 1)
        };
        cell(1) * self.n + cell(0)
    }

    /// The block's extent grown by `margin`; the last row and column reach
    /// to infinity, so rounding never drops a point.
    fn bounds(&self, b: usize, margin: f32) -> ([f32; 2], [f32; 2]) {
        let (ix, iy) = (b % self.n, b / self.n);
        let edge = |a: usize, i: usize| {
            let lo = if i == 0 {
                f32::MIN
            } else {
                self.min[a] + i as f32 * self.side - margin
            };
            let hi = if i + 1 == self.n {
                f32::MAX
            } else {
                self.min[a] + (i + 1) as f32 * self.side + margin
            };
            (lo, hi)
        };
        let ((x0, x1), (y0, y1)) = (edge(0, ix), edge(1, iy));
        ([x0, y0], [x1, y1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::features::FeatureError;

    fn shipped() -> Model {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../config/classifier_model.json.gz");
        Model::load(&path).unwrap_or_else(|e| panic!("{e}"))
    }

    /// 120 × 120 m of ground at 1 m, flat-roofed boxes with walls and
    /// scattered crowns: (cloud, hag, the rows that are not ground).
    fn town() -> (Vec<[f32; 3]>, Vec<f32>, Vec<usize>) {
        let mut xyz = crate::geom::fixtures::lattice(120, 120, 1.0, |_, _| 0.0);
        let ground = xyz.len();
        let mut s = 7u32;
        let mut r = move || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        };
        for (bx, by) in [(10.0, 10.0), (50.0, 20.0), (85.0, 70.0), (30.0, 90.0)] {
            for i in 0..40 {
                for j in 0..40 {
                    xyz.push([bx + i as f32 * 0.4, by + j as f32 * 0.4, 7.0]);
                }
                for h in 0..14 {
                    xyz.push([bx + i as f32 * 0.4, by, h as f32 * 0.5]);
                }
            }
        }
        for (cx, cy) in [(40.0, 60.0), (60.0, 59.0), (100.0, 30.0), (70.0, 100.0)] {
            for _ in 0..600 {
                xyz.push([cx + 5.0 * r(), cy + 5.0 * r(), 3.0 + 5.0 * r()]);
            }
        }
        // Jitter: on an exact lattice the k nearest are a tie, broken by
        // each tree's shape.
        for p in xyz.iter_mut() {
            p[0] += 0.1 * r();
            p[1] += 0.1 * r();
            p[2] += 0.02 * r();
        }
        let hag = xyz.iter().map(|p| p[2]).collect();
        let rows = (ground..xyz.len()).collect();
        (xyz, hag, rows)
    }

    #[test]
    fn blocks_vote_as_one_pass_does() {
        let (xyz, hag, rows) = town();
        let model = shipped();
        let one = votes(&xyz, &hag, None, &rows, &model, usize::MAX).unwrap();
        // 3 × 3 blocks of 40 m: every building and crown near some edge.
        let grid = Grid::new(&xyz, &rows, xyz.len() / 8).expect("several blocks");
        assert_eq!(grid.n, 3);
        let blocked = votes(&xyz, &hag, None, &rows, &model, xyz.len() / 8).unwrap();
        assert_eq!(blocked.len(), one.len());
        let worst = one
            .iter()
            .zip(&blocked)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-6, "votes differ by {worst}");
    }

    #[test]
    fn a_bad_point_is_named_by_its_place_in_the_whole_cloud() {
        let (mut xyz, hag, rows) = town();
        let bad = rows[rows.len() / 2];
        xyz[bad][0] = f32::NAN;
        let got = votes(&xyz, &hag, None, &rows, &shipped(), xyz.len() / 8);
        assert!(
            matches!(
                got,
                Err(ClassifyError::Features(FeatureError::NonFinite { index, .. })) if index == bad
            ),
            "{got:?}"
        );
        // A row past the cloud is an error, not a panic, in blocks too.
        let (xyz, hag, mut rows) = town();
        rows.push(xyz.len() + 5);
        let got = votes(&xyz, &hag, None, &rows, &shipped(), xyz.len() / 8);
        assert!(
            matches!(
                got,
                Err(ClassifyError::Features(FeatureError::RowOutOfRange { .. }))
            ),
            "{got:?}"
        );
    }
}
