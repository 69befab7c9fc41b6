//! Detection scored against ground truth (the acceptance metric of the
//! detection issue).
//!
//! Every building's walls (GT samples of kind Wall) are cut into 1 m × 1 m
//! cells on the wall plane: samples are grouped by building and wall plane
//! (normal azimuth in 5° bins, plane offset to 0.5 m) and binned by the
//! along-wall coordinate and z. A cell is *truly missing* when fewer than
//! half of its samples have an aerial point within τ. Recall is the share
//! of truly missing cells with a missing point within `match_dist` of one of
//! their samples; precision the share of missing points within `match_dist`
//! of a sample of a truly missing cell.
//!
//! Undersides (Wall samples facing down, n_z ≤ −0.5: the slab over a hollow
//! base) have no wall plane to cut in along-wall × z cells; they are cut in
//! 1 m xy cells and reported apart (`underside_*`), outside recall, since
//! slice contours cannot see under a slab: region targets must.

use std::collections::{BTreeMap, HashMap};

use serde::{Deserialize, Serialize};

use super::detection::MissingPoint;
use crate::metrics::{GtSamples, SurfaceKind, nearest_distances};

/// τ, the completeness radius, metres.
pub const TAU: f32 = 0.25;
/// Wall cell edge, metres.
pub const CELL: f32 = 1.0;
/// A missing point this close to a truly missing cell finds it, metres.
pub const MATCH_DIST: f32 = 1.0;
/// Cells with fewer samples (wall edges) are left out: 1/4 of a full cell at 0.25 m spacing.
pub const MIN_CELL_SAMPLES: usize = 4;
const AZIMUTH_BINS: f32 = 72.0;

/// Facade cells against the missing points reported on them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WallCounts {
    /// Wall cells evaluated.
    pub cells: usize,
    /// Of which truly missing.
    pub truly_missing: usize,
    /// Truly missing cells found.
    pub found: usize,
    /// Missing points reported.
    pub missing_points: usize,
    /// Of which near a truly missing cell.
    pub correct_points: usize,
    /// found / truly_missing (1 when none are missing).
    pub recall: f64,
    /// correct_points / missing_points (1 when none were reported).
    pub precision: f64,
}

impl Default for WallCounts {
    fn default() -> Self {
        WallCounts {
            cells: 0,
            truly_missing: 0,
            found: 0,
            missing_points: 0,
            correct_points: 0,
            recall: 1.0,
            precision: 1.0,
        }
    }
}

impl WallCounts {
    /// Recall and precision from the counts.
    fn scored(mut self) -> Self {
        self.recall = share(self.found, self.truly_missing);
        self.precision = share(self.correct_points, self.missing_points);
        self
    }

    /// The counts of `self` and `other` together (scores not updated).
    fn plus(mut self, other: &WallCounts) -> Self {
        self.cells += other.cells;
        self.truly_missing += other.truly_missing;
        self.found += other.found;
        self.missing_points += other.missing_points;
        self.correct_points += other.correct_points;
        self
    }
}

/// Score of one building.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BuildingScore {
    /// Building id.
    pub building: u32,
    /// Its facade cells and missing points.
    #[serde(flatten)]
    pub walls: WallCounts,
}

/// Score of a detection over a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DetectionScore {
    /// Every building's facade cells and missing points.
    #[serde(flatten)]
    pub walls: WallCounts,
    /// Underside cells evaluated.
    pub underside_cells: usize,
    /// Of which truly missing.
    pub underside_truly_missing: usize,
    /// Truly missing underside cells with a missing point within reach.
    pub underside_found: usize,
    /// Per building (facades), ascending id.
    pub per_building: Vec<BuildingScore>,
}

fn share(a: usize, b: usize) -> f64 {
    if b == 0 { 1.0 } else { a as f64 / b as f64 }
}

/// The wall cells of a scene's ground truth and how the aerial cloud holds them.
pub(super) struct WallCells {
    /// Positions of the wall samples (GT kind Wall).
    pub wall_xyz: Vec<[f32; 3]>,
    /// Index into `gt` of each wall sample.
    pub wall_gt: Vec<usize>,
    /// Whether an aerial point lies within τ of each wall sample.
    pub covered: Vec<bool>,
    /// The cell of each wall sample.
    pub cell_of: Vec<usize>,
    /// Wall samples of each cell.
    pub samples: Vec<Vec<usize>>,
    /// Whether each cell is an underside (cut in xy cells).
    pub underside: Vec<bool>,
    /// GT building of each cell.
    pub building: Vec<u32>,
    /// Whether each cell is truly missing.
    pub truly: Vec<bool>,
}

impl WallCells {
    /// Cuts `gt`'s walls in cells and marks those `aerial_xyz` leaves missing.
    pub fn new(gt: &GtSamples, aerial_xyz: &[[f32; 3]]) -> Self {
        let wall_gt: Vec<usize> = (0..gt.len())
            .filter(|&i| gt.kind[i] == SurfaceKind::Wall)
            .collect();
        let wall_xyz: Vec<[f32; 3]> = wall_gt.iter().map(|&i| gt.xyz[i]).collect();
        let covered: Vec<bool> = nearest_distances(&wall_xyz, aerial_xyz)
            .into_iter()
            .map(|d| d <= TAU)
            .collect();
        let mut cell_of_key: HashMap<(u32, i32, i64, i64, i64), usize> = HashMap::new();
        let mut cells = WallCells {
            wall_xyz: Vec::new(),
            wall_gt: Vec::new(),
            covered,
            cell_of: Vec::with_capacity(wall_gt.len()),
            samples: Vec::new(),
            underside: Vec::new(),
            building: Vec::new(),
            truly: Vec::new(),
        };
        for (w, &i) in wall_gt.iter().enumerate() {
            let (key, down) = cell_key(gt, i);
            let k = *cell_of_key.entry(key).or_insert_with(|| {
                cells.underside.push(down);
                cells.samples.push(Vec::new());
                cells.building.push(gt.building[i]);
                cells.samples.len() - 1
            });
            cells.samples[k].push(w);
            cells.cell_of.push(k);
        }
        cells.truly = (0..cells.samples.len())
            .map(|k| {
                let n = cells.samples[k].len();
                n >= MIN_CELL_SAMPLES && cells.covered_share(k) < 0.5
            })
            .collect();
        cells.wall_xyz = wall_xyz;
        cells.wall_gt = wall_gt;
        cells
    }

    /// Whether cell `k` has samples enough to be scored.
    pub fn evaluated(&self, k: usize) -> bool {
        self.samples[k].len() >= MIN_CELL_SAMPLES
    }

    /// Share of cell `k`'s samples the aerial cloud holds.
    pub fn covered_share(&self, k: usize) -> f64 {
        let n = self.samples[k].len();
        let c = self.samples[k].iter().filter(|&&w| self.covered[w]).count();
        if n == 0 { 0.0 } else { c as f64 / n as f64 }
    }

    /// Positions of the samples of every truly missing cell.
    pub fn truly_xyz(&self) -> Vec<[f32; 3]> {
        (0..self.samples.len())
            .filter(|&k| self.truly[k])
            .flat_map(|k| self.samples[k].iter().map(|&w| self.wall_xyz[w]))
            .collect()
    }
}

/// The cell key of wall sample `i` and whether it is an underside.
fn cell_key(gt: &GtSamples, i: usize) -> ((u32, i32, i64, i64, i64), bool) {
    let [x, y, z] = gt.xyz[i];
    let [nx, ny, _] = gt.normal[i];
    let bins = AZIMUTH_BINS as i32;
    let az =
        ((ny.atan2(nx) / std::f32::consts::TAU * AZIMUTH_BINS).round() as i32).rem_euclid(bins);
    let a = az as f32 / AZIMUTH_BINS * std::f32::consts::TAU;
    let (c, s) = (a.cos(), a.sin());
    let offset = ((c * x + s * y) / 0.5).round() as i64;
    let along = ((-s * x + c * y) / CELL).floor() as i64;
    let up = (z / CELL).floor() as i64;
    let down = gt.normal[i][2] <= -0.5;
    if down {
        let f = |v: f32| (v / CELL).floor() as i64;
        ((gt.building[i], -1, f(x), f(y), up), true)
    } else {
        ((gt.building[i], az, offset, along, up), false)
    }
}

/// Scores `missing` against the wall cells of `gt`, covered by `aerial_xyz`
/// (both in the same local frame as `gt`).
pub fn evaluate(
    gt: &GtSamples,
    aerial_xyz: &[[f32; 3]],
    missing: &[MissingPoint],
) -> DetectionScore {
    score_cells(&WallCells::new(gt, aerial_xyz), missing)
}

/// [`evaluate`] on cells already cut.
pub(super) fn score_cells(cells: &WallCells, missing: &[MissingPoint]) -> DetectionScore {
    let missing_xyz: Vec<[f32; 3]> = missing.iter().map(|m| m.xyz).collect();
    let to_missing = nearest_distances(&cells.wall_xyz, &missing_xyz);
    let to_truly = nearest_distances(&missing_xyz, &cells.truly_xyz());
    let evaluated: Vec<usize> = (0..cells.samples.len())
        .filter(|&k| cells.evaluated(k))
        .collect();
    let (underside, truly, cell_samples, cell_building) = (
        &cells.underside,
        &cells.truly,
        &cells.samples,
        &cells.building,
    );

    let mut per: BTreeMap<u32, WallCounts> = BTreeMap::new();
    for &k in evaluated.iter().filter(|&&k| !underside[k]) {
        let s = per.entry(cell_building[k]).or_default();
        s.cells += 1;
        if truly[k] {
            s.truly_missing += 1;
            if cell_samples[k].iter().any(|&w| to_missing[w] <= MATCH_DIST) {
                s.found += 1;
            }
        }
    }
    for (m, d) in missing.iter().zip(&to_truly) {
        let s = per.entry(m.building).or_default();
        s.missing_points += 1;
        if *d <= MATCH_DIST {
            s.correct_points += 1;
        }
    }
    let mut under = [0usize; 3];
    for &k in evaluated.iter().filter(|&&k| underside[k]) {
        under[0] += 1;
        if truly[k] {
            under[1] += 1;
            if cell_samples[k].iter().any(|&w| to_missing[w] <= MATCH_DIST) {
                under[2] += 1;
            }
        }
    }
    let all = per.values().fold(WallCounts::default(), WallCounts::plus);
    DetectionScore {
        walls: all.scored(),
        underside_cells: under[0],
        underside_truly_missing: under[1],
        underside_found: under[2],
        per_building: per
            .into_iter()
            .map(|(building, c)| BuildingScore {
                building,
                walls: c.scored(),
            })
            .collect(),
    }
}
