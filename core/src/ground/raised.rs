//! Ground that stands on a step. Where a roof runs to the survey's edge or
//! to a data void, the cloth finds nothing lower beyond it to fall to and
//! rests on the roof, so the roof's edge becomes "ground" (sample_c.las's
//! east edge, 24 m up; AHN3 Delft 1's south-west corner, 2.8 m up). Such a
//! piece is higher than every bit of ground near it by more than a storey's
//! step, ends in a wall or a void, and lies where the survey ends; terrain,
//! even steep, meets its neighbours' level once the survey's own slope is
//! allowed for, and a terrace over a bank the cloth missed (Autzen's river)
//! slopes down to it. The piece is taken out of the ground and the terrain
//! under it filled from the rest.

use std::collections::{HashMap, HashSet};
use std::num::NonZeroUsize;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use petgraph::unionfind::UnionFind;
use rayon::prelude::*;
use serde::Serialize;

/// Neighbouring ground cells whose lowest points differ by at most this
/// many cell widths (a 45° slope) are one piece: kerbs, ramps and steep
/// banks link, walls do not.
const LINK_SLOPE: f32 = 1.0;
/// A piece is raised when at least this share of its rim is higher than
/// the nearest other ground by more than the step.
const RIM_SHARE: f32 = 0.9;
/// At least this share of a raised piece's cells lie near a data void or
/// the survey's edge.
const EDGE_SHARE: f32 = 0.9;
/// "Near" a void: within this many cloth cells of it.
const NEAR_VOID: f32 = 1.5;
/// Cells (m) over which the survey's terrain slope is measured.
const SLOPE_CELL: f32 = 5.0;
/// The percentile of those slopes the step is widened by, per metre of gap.
const SLOPE_PERCENTILE: f32 = 0.9;

/// What [`find`] took out of the ground.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct Raised {
    /// Pieces of ground found standing on a step.
    pub pieces: usize,
    /// Ground points on them, no longer ground.
    pub points: usize,
}

impl Raised {
    /// What a user is told when pieces were taken out; `None` otherwise.
    pub fn message(&self) -> Option<String> {
        (self.pieces > 0).then(|| {
            format!(
                "the cloth rested on {} roof piece(s) where the survey ends: {} points taken out of the ground, the terrain under them filled from the rest",
                self.pieces, self.points
            )
        })
    }
}

/// How [`find`] looks.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Settings {
    /// Ground cell width, metres.
    pub cell: f32,
    /// The cloth's cell, metres: how far past the nearest ground the
    /// lowest is looked for, and how near a data void a raised piece lies.
    pub band_m: f32,
    /// A `band_m`-wide cell with fewer points is a data void.
    pub void_below: u32,
    /// Least height over the ground near it, metres.
    pub step_m: f32,
    /// Largest piece, m².
    pub max_m2: f32,
}

/// The lowest ground height per square cell.
struct Cells {
    keys: Vec<[i32; 2]>,
    z: Vec<f32>,
    index: HashMap<[i32; 2], usize>,
}

impl Cells {
    fn of(xyz: &[[f32; 3]], is_ground: &[bool], cell: f32) -> Self {
        let mut cells = Self {
            keys: Vec::new(),
            z: Vec::new(),
            index: HashMap::new(),
        };
        for (p, _) in xyz.iter().zip(is_ground).filter(|(_, g)| **g) {
            let key = key_of([p[0], p[1]], cell);
            let k = *cells.index.entry(key).or_insert_with(|| {
                cells.keys.push(key);
                cells.z.push(f32::INFINITY);
                cells.keys.len() - 1
            });
            cells.z[k] = cells.z[k].min(p[2]);
        }
        cells
    }

    fn neighbours(&self, k: usize) -> impl Iterator<Item = usize> + '_ {
        let [i, j] = self.keys[k];
        (-1..=1)
            .flat_map(move |di| (-1..=1).map(move |dj| [i + di, j + dj]))
            .filter(move |n| *n != [i, j])
            .filter_map(|n| self.index.get(&n).copied())
    }
}

/// The `cell`-wide cell holding plan point `p`.
fn key_of(p: [f32; 2], cell: f32) -> [i32; 2] {
    [(p[0] / cell).floor() as i32, (p[1] / cell).floor() as i32]
}

/// The centre of cell `key`.
fn centre_of(key: [i32; 2], cell: f32) -> [f32; 2] {
    [(key[0] as f32 + 0.5) * cell, (key[1] as f32 + 0.5) * cell]
}

/// Per point, whether it is a ground point (`is_ground`) on a raised
/// piece of ground, and how many. Pieces are the ground's `cell`-wide
/// cells linked up to a 45° slope. A piece is raised when
/// - it holds less than half the ground and covers at most `max_m2`;
/// - on at least [`RIM_SHARE`] of its rim it stands more than `step_m`
///   (plus the survey's terrain slope times the gap) over the lowest ground
///   within `band_m` past the nearest, and the lowest points between fall
///   to it somewhere more steeply than 45° (a wall, not a bank);
/// - at least [`EDGE_SHARE`] of its cells lie near a data void or the
///   survey's edge.
pub(crate) fn find(xyz: &[[f32; 3]], is_ground: &[bool], set: &Settings) -> (Vec<bool>, Raised) {
    let Settings {
        cell,
        band_m,
        step_m,
        max_m2,
        ..
    } = *set;
    let none = || (vec![false; xyz.len()], Raised::default());
    if !(step_m > 0.0 && cell > 0.0) {
        return none();
    }
    let cells = Cells::of(xyz, is_ground, cell);
    let n = cells.keys.len();
    if n < 2 {
        return none();
    }
    let mut uf = UnionFind::<usize>::new(n);
    for k in 0..n {
        for m in cells.neighbours(k) {
            if (cells.z[k] - cells.z[m]).abs() <= LINK_SLOPE * cell {
                uf.union(k, m);
            }
        }
    }
    // Each piece is labelled by one of its cells' indices.
    let piece = uf.into_labeling();
    let mut size = vec![0usize; n];
    for &p in &piece {
        size[p] += 1;
    }
    let largest = (max_m2 / (cell * cell)).floor() as usize;
    let candidate = |p: usize| size[p] * 2 < n && size[p] <= largest;
    // A piece's rim: its cells with a neighbour cell that is not its own.
    let rim: Vec<usize> = (0..n)
        .filter(|&k| candidate(piece[k]))
        .filter(|&k| {
            let own = cells.neighbours(k).filter(|&m| piece[m] == piece[k]);
            own.count() < 8
        })
        .collect();
    if rim.is_empty() {
        return none();
    }
    let slope = terrain_slope(&cells, cell);
    let centres: Vec<[f32; 2]> = cells.keys.iter().map(|&k| centre_of(k, cell)).collect();
    let Ok(tree) = ImmutableKdTree::<f32, 2>::new_from_slice(&centres) else {
        return none();
    };
    // Per rim cell: its piece, whether it stands on a step, and the ground
    // it stands over.
    let steps: Vec<(usize, bool, usize, usize)> = rim
        .par_iter()
        .filter_map(|&k| {
            let other = |m: usize| piece[m] != piece[k];
            let (_, d0) = nearest_other(&tree, &centres[k], n, other)?;
            // The lowest ground in a band past the nearest, slope allowed
            // for: the cloth hanging from the piece's edge left "ground" on
            // the wall's foot, higher than the street beyond it.
            let r = d0 + band_m;
            let (rise, m) = tree
                .query(&centres[k])
                .within::<SquaredEuclidean<f32>>(r * r)
                .unsorted()
                .execute()
                .iter()
                .filter(|nb| other(nb.item as usize))
                .map(|nb| {
                    let m = nb.item as usize;
                    (cells.z[k] - cells.z[m] - slope * nb.distance.sqrt(), m)
                })
                .fold((f32::NEG_INFINITY, k), |a, b| if b.0 > a.0 { b } else { a });
            Some((piece[k], rise > step_m, k, m))
        })
        .collect();
    let on_step = pieces_over(steps.iter().map(|&(p, high, _, _)| (p, high)));
    if on_step.is_empty() {
        return none();
    }
    // A roof ends in a wall or a void; a terrace above a bank the cloth
    // missed slopes down to the ground below.
    let lowest = lowest_points(xyz, cell);
    let walled = pieces_over(steps.iter().filter(|(p, ..)| on_step.contains(p)).map(
        |&(p, high, k, m)| {
            let wall = || falls_steeply(&lowest, centres[k], centres[m], cell, step_m / 2.0);
            (p, high && wall())
        },
    ));
    if walled.is_empty() {
        return none();
    }
    let near_void = near_void(xyz, &cells, set);
    let mut near = vec![0usize; n];
    for k in (0..n).filter(|&k| walled.contains(&piece[k]) && near_void(k)) {
        near[piece[k]] += 1;
    }
    let raised: HashSet<usize> = walled
        .into_iter()
        .filter(|&p| near[p] as f32 >= EDGE_SHARE * size[p] as f32)
        .collect();
    if raised.is_empty() {
        return none();
    }
    let on: Vec<bool> = xyz
        .iter()
        .zip(is_ground)
        .map(|(p, &g)| {
            g && cells
                .index
                .get(&key_of([p[0], p[1]], cell))
                .is_some_and(|&k| raised.contains(&piece[k]))
        })
        .collect();
    let points = on.iter().filter(|&&r| r).count();
    let pieces = raised.len();
    (on, Raised { pieces, points })
}

/// The pieces with at least [`RIM_SHARE`] of their rim cells passing.
fn pieces_over(rim: impl Iterator<Item = (usize, bool)>) -> HashSet<usize> {
    let mut tally: HashMap<usize, (usize, usize)> = HashMap::new();
    for (p, pass) in rim {
        let t = tally.entry(p).or_insert((0, 0));
        t.0 += usize::from(pass);
        t.1 += 1;
    }
    tally
        .into_iter()
        .filter(|(_, (pass, all))| *pass as f32 >= RIM_SHARE * *all as f32)
        .map(|(p, _)| p)
        .collect()
}

/// Whether ground cell `k` lies within [`NEAR_VOID`] cloth cells
/// (`band_m`) of a data void (a `band_m` cell with fewer than `void_below`
/// points) or of the survey's edge: only there does the cloth lack a lower
/// support beyond a roof.
fn near_void<'a>(
    xyz: &[[f32; 3]],
    cells: &'a Cells,
    set: &Settings,
) -> impl Fn(usize) -> bool + 'a {
    let mut count: HashMap<[i32; 2], u32> = HashMap::new();
    for p in xyz.iter().filter(|p| p.iter().all(|v| v.is_finite())) {
        *count.entry(key_of([p[0], p[1]], set.band_m)).or_insert(0) += 1;
    }
    let (cell, band, below) = (set.cell, set.band_m, set.void_below);
    let reach = NEAR_VOID * band;
    let r = reach.div_euclid(band) as i32 + 1;
    move |k| {
        let at = centre_of(cells.keys[k], cell);
        let c = key_of(at, band);
        (-r..=r).any(|di| {
            (-r..=r).any(|dj| {
                let v = [c[0] + di, c[1] + dj];
                let void = count.get(&v).is_none_or(|&n| n < below);
                // Plan distance from `at` to that cell's square.
                let gap = |a: f32, lo: f32| (lo - a).max(a - (lo + band)).max(0.0);
                void && gap(at[0], v[0] as f32 * band).hypot(gap(at[1], v[1] as f32 * band))
                    <= reach
            })
        })
    }
}

/// The lowest point's height per `cell`-wide cell, over every finite point.
fn lowest_points(xyz: &[[f32; 3]], cell: f32) -> HashMap<[i32; 2], f32> {
    let mut lowest: HashMap<[i32; 2], f32> = HashMap::new();
    for p in xyz.iter().filter(|p| p.iter().all(|v| v.is_finite())) {
        let z = lowest
            .entry(key_of([p[0], p[1]], cell))
            .or_insert(f32::INFINITY);
        *z = z.min(p[2]);
    }
    lowest
}

/// Whether the surface of lowest points from `a` to `b` (plan) falls by at
/// least `drop_m` between two of its consecutive sampled cells more
/// steeply than [`LINK_SLOPE`]: a wall, or a void with lower ground past
/// it, rather than a slope.
fn falls_steeply(
    lowest: &HashMap<[i32; 2], f32>,
    a: [f32; 2],
    b: [f32; 2],
    cell: f32,
    drop_m: f32,
) -> bool {
    let len = ((b[0] - a[0]).hypot(b[1] - a[1]) / (0.5 * cell))
        .ceil()
        .max(1.0) as usize;
    let mut last: Option<([i32; 2], f32)> = None;
    for s in 0..=len {
        let t = s as f32 / len as f32;
        let key = key_of([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])], cell);
        let Some(&z) = lowest.get(&key) else {
            continue;
        };
        if let Some((prev, zp)) = last {
            if prev == key {
                continue;
            }
            let gap = ((key[0] - prev[0]) as f32).hypot((key[1] - prev[1]) as f32) * cell;
            if zp - z >= drop_m && zp - z >= LINK_SLOPE * gap {
                return true;
            }
        }
        last = Some((key, z));
    }
    false
}

/// The nearest cell (index, plan distance) passing `other`, found by
/// asking for ever more neighbours; `None` when no cell passes.
fn nearest_other(
    tree: &ImmutableKdTree<f32, 2>,
    at: &[f32; 2],
    n: usize,
    other: impl Fn(usize) -> bool,
) -> Option<(usize, f32)> {
    let mut want = 16usize;
    loop {
        let k = NonZeroUsize::new(want.min(n))?;
        let near = tree
            .query(at)
            .nearest_n::<SquaredEuclidean<f32>>(k)
            .execute();
        if let Some(nb) = near.iter().find(|nb| other(nb.item as usize)) {
            return Some((nb.item as usize, nb.distance.sqrt()));
        }
        if want >= n {
            return None;
        }
        want = want.saturating_mul(4);
    }
}

/// The survey's steep-end terrain slope (m per m): the
/// [`SLOPE_PERCENTILE`] of the height differences between neighbouring
/// [`SLOPE_CELL`]-wide cells of mean ground height. A hillside survey then
/// asks a piece across a gap to stand higher before calling it raised.
fn terrain_slope(cells: &Cells, cell: f32) -> f32 {
    let mut coarse: HashMap<[i32; 2], (f64, u32)> = HashMap::new();
    for (key, &z) in cells.keys.iter().zip(&cells.z) {
        let c = key_of(centre_of(*key, cell), SLOPE_CELL);
        let e = coarse.entry(c).or_insert((0.0, 0));
        e.0 += f64::from(z);
        e.1 += 1;
    }
    let mean = |c: &[i32; 2]| coarse.get(c).map(|(s, n)| s / f64::from(*n));
    let mut slopes: Vec<f32> = coarse
        .keys()
        .flat_map(|&[i, j]| {
            let here = mean(&[i, j]);
            [[i + 1, j], [i, j + 1]].into_iter().filter_map(move |n| {
                Some(((here? - mean(&n)?).abs() / f64::from(SLOPE_CELL)) as f32)
            })
        })
        .collect();
    if slopes.is_empty() {
        return 0.0;
    }
    let at = ((slopes.len() - 1) as f32 * SLOPE_PERCENTILE).round() as usize;
    let (_, v, _) = slopes.select_nth_unstable_by(at, f32::total_cmp);
    *v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(step_m: f32, max_m2: f32) -> Settings {
        Settings {
            cell: 1.0,
            band_m: 4.0,
            void_below: 6,
            step_m,
            max_m2,
        }
    }

    /// A street 40 × 30 m at height `street(x)`, and a piece 4 m wide at
    /// height `far(x)` running to the survey's east edge, `gap` m past the
    /// street; both ground, as the cloth left them.
    fn scene(street: impl Fn(f32) -> f32, gap: f32, far: impl Fn(f32) -> f32) -> Vec<[f32; 3]> {
        let mut pts = Vec::new();
        for i in 0..80 {
            for j in 0..60 {
                let (x, y) = (i as f32 * 0.5, j as f32 * 0.5);
                pts.push([x, y, street(x)]);
            }
        }
        for i in 0..8 {
            for j in 0..60 {
                let (x, y) = (40.0 + gap + i as f32 * 0.5, j as f32 * 0.5);
                pts.push([x, y, far(x)]);
            }
        }
        pts
    }

    #[test]
    fn a_roof_at_the_edge_is_raised_and_the_street_is_not() {
        let pts = scene(|_| 0.0, 6.0, |_| 9.0);
        let ground = vec![true; pts.len()];
        let (on, r) = find(&pts, &ground, &set(2.0, 10_000.0));
        assert_eq!(r.pieces, 1);
        assert_eq!(r.points, 8 * 60);
        assert!(on.iter().zip(&pts).all(|(&o, p)| o == (p[2] > 1.0)));
        // Below the step it stays ground; so does any point not ground.
        let (_, r) = find(&pts, &ground, &set(10.0, 10_000.0));
        assert_eq!(r, Raised::default());
        let (on, r) = find(&pts, &vec![false; pts.len()], &set(2.0, 10_000.0));
        assert_eq!((r.points, on.iter().any(|&o| o)), (0, false));
        // A step of 0 turns the check off; a piece over max_m2 is never raised.
        assert_eq!(find(&pts, &ground, &set(0.0, 1e4)).1, Raised::default());
        assert_eq!(find(&pts, &ground, &set(2.0, 100.0)).1, Raised::default());
    }

    #[test]
    fn terrain_across_a_gap_on_a_hillside_is_not_raised() {
        // A 30 % slope with a 10 m gap (a wood with no ground returns): the
        // far side stands 3 m higher than the near edge, a step on flat
        // land, but the survey's own slope allows for it.
        let hill = |x: f32| 0.3 * x;
        let pts = scene(hill, 10.0, hill);
        let ground = vec![true; pts.len()];
        let slope = terrain_slope(&Cells::of(&pts, &ground, 1.0), 1.0);
        assert!((slope - 0.3).abs() < 0.02, "{slope}");
        let (_, r) = find(&pts, &ground, &set(2.0, 10_000.0));
        assert_eq!(r, Raised::default());
    }

    #[test]
    fn a_terrace_above_a_bank_the_cloth_missed_is_not_raised() {
        // Flat ground at 0, a 4 m strip of ground at 6 m on the survey's
        // east edge and, between them, 15 m of returns the cloth did not
        // take for ground: a roof at 6 m ending in a wall, or a bank
        // falling 0.4 m per metre.
        let with_gap = |gap_z: &dyn Fn(f32) -> f32| {
            let mut pts = scene(|_| 0.0, 15.0, |_| 6.0);
            let ground = vec![true; pts.len()];
            for i in 0..30 {
                for j in 0..60 {
                    let (x, y) = (40.0 + i as f32 * 0.5, j as f32 * 0.5);
                    pts.push([x, y, gap_z(x)]);
                }
            }
            let ground: Vec<bool> = (0..pts.len())
                .map(|k| ground.get(k) == Some(&true))
                .collect();
            find(&pts, &ground, &set(2.0, 10_000.0)).1
        };
        assert_eq!(with_gap(&|_| 6.0).pieces, 1);
        assert_eq!(with_gap(&|x| 0.4 * (x - 40.0)), Raised::default());
    }

    #[test]
    fn a_raised_piece_inside_the_survey_stays_ground() {
        // A 20 m roof at 9 m amid streets, its middle 8 m taken for ground
        // (a cloth too fine for it sagged there): the cloth had support all
        // round, so this is not a roof where the survey ends.
        let (mut pts, mut ground) = (Vec::new(), Vec::new());
        for i in 0..120 {
            for j in 0..120 {
                let (x, y) = (i as f32 * 0.5, j as f32 * 0.5);
                let on = |lo: f32, hi: f32| (lo..hi).contains(&x) && (lo..hi).contains(&y);
                pts.push([x, y, if on(20.0, 40.0) { 9.0 } else { 0.0 }]);
                ground.push(!on(20.0, 40.0) || on(26.0, 34.0));
            }
        }
        let (_, r) = find(&pts, &ground, &set(2.0, 10_000.0));
        assert_eq!(r, Raised::default());
        // Cut at x = 30 m, the same roof is raised.
        let cut: Vec<usize> = (0..pts.len()).filter(|&k| pts[k][0] < 30.0).collect();
        let pts: Vec<[f32; 3]> = cut.iter().map(|&k| pts[k]).collect();
        let ground: Vec<bool> = cut.iter().map(|&k| ground[k]).collect();
        let (_, r) = find(&pts, &ground, &set(2.0, 10_000.0));
        assert_eq!(r.pieces, 1);
    }

    #[test]
    fn a_courtyard_at_street_level_is_not_raised() {
        // A piece cut off by buildings, level with the street: not raised.
        let pts = scene(|_| 5.0, 12.0, |_| 5.2);
        let (_, r) = find(&pts, &vec![true; pts.len()], &set(2.0, 10_000.0));
        assert_eq!(r, Raised::default());
    }
}
