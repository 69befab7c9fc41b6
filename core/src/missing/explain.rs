//! Where the missing points that are not missing lie: the false ones of
//! [`super::evaluate`] by cause, height, facing, distance to the true wall
//! and nearness to trees, so a precision figure says why it is what it is.

use serde::{Deserialize, Serialize};

use super::detection::MissingPoint;
use super::eval::{DetectionScore, MATCH_DIST, WallCells, score_cells};
use crate::metrics::{GtSamples, nearest_distances, nearest_indices};

/// A cell the aerial cloud holds on at least this share of its samples is
/// held fully; below, thinly (truly missing cells are under 0.5).
pub const THIN_SHARE: f64 = 0.75;
/// Vegetation this close (3D) to a missing point puts it near a tree, metres.
pub const TREE_REACH: f32 = 3.0;
/// Upper ends of the height bands over the building's lowest wall sample, metres.
const HEIGHTS: [f32; 4] = [3.0, 6.0, 10.0, 20.0];
/// Upper ends of the distance bands to the nearest true wall sample, metres.
const OFFSETS: [f32; 3] = [0.25, 0.5, 1.0];

/// One line of a breakdown: the missing points it holds and how many are false.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// What the line counts.
    pub label: String,
    /// Missing points in it.
    pub points: usize,
    /// Of which not within [`MATCH_DIST`] of a truly missing cell.
    pub false_points: usize,
}

/// The missing points of a detection broken down.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Breakdown {
    /// Of the false points: why they are false (one row each, adding up).
    pub cause: Vec<Row>,
    /// Height over the ground-truth building's lowest wall sample.
    pub height: Vec<Row>,
    /// Facing (the point's outward direction): north, east, south, west.
    pub facing: Vec<Row>,
    /// Distance in 3D to the nearest true wall sample.
    pub wall_distance: Vec<Row>,
    /// With vegetation within [`TREE_REACH`] or not (the prior's porous crowns).
    pub trees: Vec<Row>,
    /// Per ground-truth building (the one whose nearest sample the point is near).
    pub building: Vec<Row>,
}

/// Why a false point is false.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Cause {
    /// No true wall within reach: the outline stands off the walls (a
    /// derived footprint's edge, a roof edge, clutter called building).
    OffWall,
    /// Its nearest wall sample is in a cell left out of scoring (too few samples).
    EdgeCell,
    /// Its nearest cell is held, on under [`THIN_SHARE`] of its samples.
    Thin,
    /// Its nearest cell is held on [`THIN_SHARE`] or more.
    Held,
}

const CAUSES: [(Cause, &str); 4] = [
    (
        Cause::OffWall,
        "no true wall within 1 m (outline off the walls)",
    ),
    (Cause::EdgeCell, "nearest wall cell too small to score"),
    (Cause::Thin, "nearest wall cell held thinly (50-75 %)"),
    (Cause::Held, "nearest wall cell held (>= 75 %)"),
];

/// [`super::evaluate`] with the breakdown of its missing points;
/// `vegetation` (the prior's tree points, same frame) tells those near trees.
pub fn evaluate_explained(
    gt: &GtSamples,
    aerial_xyz: &[[f32; 3]],
    missing: &[MissingPoint],
    vegetation: &[[f32; 3]],
) -> (DetectionScore, Breakdown) {
    let cells = WallCells::new(gt, aerial_xyz);
    let score = score_cells(&cells, missing);
    let xyz: Vec<[f32; 3]> = missing.iter().map(|m| m.xyz).collect();
    let is_false: Vec<bool> = nearest_distances(&xyz, &cells.truly_xyz())
        .into_iter()
        .map(|d| d > MATCH_DIST)
        .collect();
    let wall = nearest_indices(&xyz, &cells.wall_xyz);
    let near_tree: Vec<bool> = nearest_distances(&xyz, vegetation)
        .into_iter()
        .map(|d| d <= TREE_REACH)
        .collect();
    // The lowest wall sample of each GT building: its foot.
    let mut foot: std::collections::HashMap<u32, f32> = Default::default();
    for (w, &i) in cells.wall_gt.iter().enumerate() {
        let z = foot.entry(gt.building[i]).or_insert(f32::INFINITY);
        *z = z.min(cells.wall_xyz[w][2]);
    }
    let mut b = Breakdown::default();
    let mut by_building: std::collections::BTreeMap<u32, Row> = Default::default();
    for (i, m) in missing.iter().enumerate() {
        let f = is_false[i];
        let owner = wall[i].map(|(w, _)| gt.building[cells.wall_gt[w]]);
        let d = wall[i].map_or(f32::INFINITY, |(_, d)| d);
        if f {
            let cause = match wall[i] {
                Some((w, d)) if d <= MATCH_DIST => {
                    let k = cells.cell_of[w];
                    if !cells.evaluated(k) {
                        Cause::EdgeCell
                    } else if cells.covered_share(k) < THIN_SHARE {
                        Cause::Thin
                    } else {
                        Cause::Held
                    }
                }
                _ => Cause::OffWall,
            };
            let label = CAUSES.iter().find(|(c, _)| *c == cause).map_or("", |c| c.1);
            add(&mut b.cause, label, true);
        }
        let h = owner
            .and_then(|o| foot.get(&o))
            .map_or(f32::NAN, |z| m.xyz[2] - z);
        add(&mut b.height, &band_label(h, &HEIGHTS, "m up"), f);
        add(&mut b.facing, facing(m.normal), f);
        add(&mut b.wall_distance, &band_label(d, &OFFSETS, "m off"), f);
        add(
            &mut b.trees,
            if near_tree[i] {
                "near trees"
            } else {
                "clear of trees"
            },
            f,
        );
        let row = by_building
            .entry(owner.unwrap_or(0))
            .or_insert_with(|| Row {
                label: owner.map_or_else(|| "none".into(), |o| format!("building {o}")),
                points: 0,
                false_points: 0,
            });
        row.points += 1;
        row.false_points += usize::from(f);
    }
    b.building = by_building.into_values().collect();
    for rows in [&mut b.cause, &mut b.height, &mut b.wall_distance] {
        rows.sort_by(|x, y| x.label.cmp(&y.label));
    }
    (score, b)
}

/// Counts one point in the row `label` of `rows`.
fn add(rows: &mut Vec<Row>, label: &str, is_false: bool) {
    let i = match rows.iter().position(|r| r.label == label) {
        Some(i) => i,
        None => {
            rows.push(Row {
                label: label.to_string(),
                points: 0,
                false_points: 0,
            });
            rows.len() - 1
        }
    };
    rows[i].points += 1;
    rows[i].false_points += usize::from(is_false);
}

/// The band of `v` among upper ends `ends`, as "a-b unit" (sortable).
fn band_label(v: f32, ends: &[f32], unit: &str) -> String {
    if !v.is_finite() {
        return format!("unknown {unit}");
    }
    let mut lo = 0.0;
    for &hi in ends {
        if v < hi {
            return format!("{lo:05.2}-{hi:05.2} {unit}");
        }
        lo = hi;
    }
    format!("{lo:05.2}+ {unit}")
}

/// Compass facing of an outward direction (x east, y north).
fn facing(n: [f32; 2]) -> &'static str {
    if n[1].abs() >= n[0].abs() {
        if n[1] >= 0.0 { "north" } else { "south" }
    } else if n[0] >= 0.0 {
        "east"
    } else {
        "west"
    }
}
