//! Walls where the points put them: each boundary segment between parts of
//! different height moves onto the vertical plane of the wall points along
//! it (a resistant line through them: offset and direction). A segment
//! with no wall points keeps the footprint's line, so a wall the cloud
//! missed stays where the roof edge alone suggests. Ridges move onto the
//! intersection of their two planes.

use super::params::ReconstructParams;
use super::partition::Partition;

/// What the boundary segments are fitted to.
pub(crate) struct Support<'a> {
    /// Wall points (local frame) and their unit normals.
    pub wall: &'a [[f64; 3]],
    /// Normals of `wall`.
    pub wall_normal: &'a [[f64; 3]],
    /// Samples along the footprint's outline with the outline's unit direction.
    pub outline: &'a [([f64; 2], [f64; 2])],
    /// The footprint was given: its outline wins over wall points.
    pub outline_first: bool,
}

/// How many boundary segments were fitted to what.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct WallFit {
    /// Segments between parts of different height, 1 m or longer.
    pub segments: usize,
    /// Of those, moved onto wall points.
    pub on_wall_points: usize,
    /// Of those, moved onto the footprint's outline.
    pub on_outline: usize,
}

/// A bucket grid over 2D positions for range queries.
struct Buckets {
    cell: f64,
    map: std::collections::HashMap<(i64, i64), Vec<u32>>,
}

impl Buckets {
    fn new(xy: impl Iterator<Item = [f64; 2]>, cell: f64) -> Self {
        let mut map: std::collections::HashMap<(i64, i64), Vec<u32>> = Default::default();
        for (i, p) in xy.enumerate() {
            map.entry(Self::key(p, cell)).or_default().push(i as u32);
        }
        Self { cell, map }
    }

    fn key(p: [f64; 2], cell: f64) -> (i64, i64) {
        ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64)
    }

    fn in_box(&self, lo: [f64; 2], hi: [f64; 2], mut f: impl FnMut(usize)) {
        let (a, b) = (Self::key(lo, self.cell), Self::key(hi, self.cell));
        for i in a.0..=b.0 {
            for j in a.1..=b.1 {
                if let Some(v) = self.map.get(&(i, j)) {
                    v.iter().for_each(|&k| f(k as usize));
                }
            }
        }
    }
}

/// A fitted segment may turn at most this much (tan of ~17°) from the
/// traced one: a raster staircase tilts a short edge near a corner by up to
/// a cell over a few metres.
const MAX_TILT: f64 = 0.3;

/// Tukey's resistant line `off = a + s · along` through `(along, off)`
/// pairs: the slope joins the medians of the outer thirds, the intercept is
/// the median residual. Outliers (a tree, a balcony) move neither; with too
/// few points in either third, a steeper slope than [`MAX_TILT`] or one
/// that moves an end by more than `reach`, the traced direction stays
/// (`s = 0`).
fn resistant_line(pts: &[(f64, f64)], len: f64, reach: f64) -> Option<(f64, f64)> {
    const MIN_THIRD: usize = 4;
    let third = |lo: f64, hi: f64| -> Option<(f64, f64)> {
        let (mut a, mut o): (Vec<f64>, Vec<f64>) = pts
            .iter()
            .filter(|p| p.0 >= lo && p.0 < hi)
            .copied()
            .unzip();
        (a.len() >= MIN_THIRD).then_some(())?;
        Some((median(&mut a)?, median(&mut o)?))
    };
    let slope = match (
        third(f64::NEG_INFINITY, len / 3.0),
        third(2.0 * len / 3.0, f64::INFINITY),
    ) {
        (Some(l), Some(r)) if r.0 - l.0 > len / 4.0 => {
            let s = (r.1 - l.1) / (r.0 - l.0);
            if s.abs() <= MAX_TILT && s.abs() * len <= reach {
                s
            } else {
                0.0
            }
        }
        _ => 0.0,
    };
    let mut res: Vec<f64> = pts.iter().map(|p| p.1 - slope * p.0).collect();
    Some((median(&mut res)?, slope))
}

fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let m = v.len() / 2;
    v.select_nth_unstable_by(m, f64::total_cmp);
    Some(v[m])
}

/// Moves boundary vertices onto the fitted wall lines (see the module docs).
pub(crate) fn snap_walls(
    p: &mut Partition,
    height: &dyn Fn(u32, [f64; 2]) -> f64,
    support: &Support,
    params: &ReconstructParams,
) -> WallFit {
    let band = params.wall_band_m;
    let walls = Buckets::new(support.wall.iter().map(|q| [q[0], q[1]]), 2.0);
    let outline = Buckets::new(support.outline.iter().map(|s| s.0), 2.0);
    let mut fit = WallFit::default();
    // Per vertex: lines n·x = c it should lie on.
    let mut lines: Vec<Vec<([f64; 2], f64)>> = vec![Vec::new(); p.verts.len()];
    for c in &p.chains {
        for w in c.verts.windows(2) {
            let (a, b) = (p.verts[w[0] as usize], p.verts[w[1] as usize]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
            if len < 1.0 {
                continue;
            }
            let za = [height(c.left, a), height(c.right, a)];
            let zb = [height(c.left, b), height(c.right, b)];
            if (za[0] - za[1]).abs() < params.min_step_m
                || (zb[0] - zb[1]).abs() < params.min_step_m
            {
                continue;
            }
            fit.segments += 1;
            let u = [d[0] / len, d[1] / len];
            let n = [u[1], -u[0]];
            let lo = [a[0].min(b[0]) - band, a[1].min(b[1]) - band];
            let hi = [a[0].max(b[0]) + band, a[1].max(b[1]) + band];
            let frame = |q: [f64; 2]| {
                let r = [q[0] - a[0], q[1] - a[1]];
                (r[0] * u[0] + r[1] * u[1], r[0] * n[0] + r[1] * n[1])
            };
            let from_walls = || {
                let mut across = Vec::new();
                let bins = (len / 0.5).ceil() as usize;
                let mut hit = vec![false; bins.max(1)];
                walls.in_box(lo, hi, |k| {
                    let q = support.wall[k];
                    let (along, off) = frame([q[0], q[1]]);
                    if along < 0.25 || along > len - 0.25 || off.abs() > band {
                        return;
                    }
                    let t = along / len;
                    let zl = za[0].min(za[1]) * (1.0 - t) + zb[0].min(zb[1]) * t;
                    let zh = za[0].max(za[1]) * (1.0 - t) + zb[0].max(zb[1]) * t;
                    let nq = support.wall_normal[k];
                    if q[2] < zl + 0.2
                        || q[2] > zh - 0.2
                        || (nq[0] * u[0] + nq[1] * u[1]).abs() > 0.5
                    {
                        return;
                    }
                    across.push((along, off));
                    hit[((along / 0.5) as usize).min(bins.max(1) - 1)] = true;
                });
                let covered = hit.iter().filter(|h| **h).count() as f64 / hit.len() as f64;
                (across.len() >= params.min_wall_points && covered >= 0.25)
                    .then(|| resistant_line(&across, len, band))
                    .flatten()
            };
            let from_outline = || {
                if c.left != 0 && c.right != 0 {
                    return None;
                }
                let mut across = Vec::new();
                outline.in_box(lo, hi, |k| {
                    let (q, dir) = support.outline[k];
                    let (along, off) = frame(q);
                    let parallel = (dir[0] * u[1] - dir[1] * u[0]).abs() < 0.3;
                    if parallel && along >= 0.0 && along <= len && off.abs() <= band {
                        across.push((along, off));
                    }
                });
                (across.len() >= 3)
                    .then(|| resistant_line(&across, len, band))
                    .flatten()
            };
            let chosen = if support.outline_first {
                from_outline()
                    .map(|o| (o, false))
                    .or_else(|| from_walls().map(|o| (o, true)))
            } else {
                from_walls()
                    .map(|o| (o, true))
                    .or_else(|| from_outline().map(|o| (o, false)))
            };
            let Some(((off, slope), on_wall)) = chosen else {
                continue;
            };
            if on_wall {
                fit.on_wall_points += 1;
            } else {
                fit.on_outline += 1;
            }
            // The line through a + off·n along u + slope·n.
            let k = (1.0 + slope * slope).sqrt();
            let nl = [(n[0] - slope * u[0]) / k, (n[1] - slope * u[1]) / k];
            let cst = nl[0] * (a[0] + off * n[0]) + nl[1] * (a[1] + off * n[1]);
            lines[w[0] as usize].push((nl, cst));
            lines[w[1] as usize].push((nl, cst));
        }
    }
    for (v, ls) in lines.iter().enumerate() {
        if let Some(q) = meet(p.verts[v], ls) {
            let dd = ((q[0] - p.verts[v][0]).powi(2) + (q[1] - p.verts[v][1]).powi(2)).sqrt();
            if dd <= 1.5 * band.max(0.1) {
                p.verts[v] = q;
            }
        }
    }
    fit
}

/// Where `x` should go to lie on the lines `ls` (n·x = c): their
/// intersection when two cross at a real angle, else its projection onto
/// each, averaged.
fn meet(x: [f64; 2], ls: &[([f64; 2], f64)]) -> Option<[f64; 2]> {
    if ls.is_empty() {
        return None;
    }
    let mut best: Option<(f64, usize, usize)> = None;
    for i in 0..ls.len() {
        for j in i + 1..ls.len() {
            let det = ls[i].0[0] * ls[j].0[1] - ls[i].0[1] * ls[j].0[0];
            if det.abs() > 0.34 && best.is_none_or(|b| det.abs() > b.0) {
                best = Some((det.abs(), i, j));
            }
        }
    }
    if let Some((_, i, j)) = best {
        let ((n1, c1), (n2, c2)) = (ls[i], ls[j]);
        let det = n1[0] * n2[1] - n1[1] * n2[0];
        return Some([
            (c1 * n2[1] - c2 * n1[1]) / det,
            (n1[0] * c2 - n2[0] * c1) / det,
        ]);
    }
    let mut s = [0.0; 2];
    for (n, c) in ls {
        let e = n[0] * x[0] + n[1] * x[1] - c;
        s[0] += x[0] - e * n[0];
        s[1] += x[1] - e * n[1];
    }
    Some([s[0] / ls.len() as f64, s[1] / ls.len() as f64])
}

/// Moves the inner vertices of chains between two roof regions onto the
/// line where their planes meet, when it is within `reach` (m).
pub(crate) fn snap_ridges(
    p: &mut Partition,
    plane_of: &dyn Fn(u32) -> Option<[f64; 3]>,
    reach: f64,
) {
    for c in 0..p.chains.len() {
        let (l, r) = (p.chains[c].left, p.chains[c].right);
        let (Some(a), Some(b)) = (plane_of(l), plane_of(r)) else {
            continue;
        };
        // z = a0 x + a1 y + a2; the planes meet where g·x + h = 0.
        let g = [a[0] - b[0], a[1] - b[1]];
        let h = a[2] - b[2];
        let g2 = g[0] * g[0] + g[1] * g[1];
        if g2 < 0.01 {
            continue;
        }
        let n = p.chains[c].verts.len();
        for k in 1..n.saturating_sub(1) {
            let v = p.chains[c].verts[k] as usize;
            let x = p.verts[v];
            let e = (g[0] * x[0] + g[1] * x[1] + h) / g2;
            let q = [x[0] - e * g[0], x[1] - e * g[1]];
            if e.abs() * g2.sqrt() <= reach {
                p.verts[v] = q;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_meet_at_corners_and_average_when_parallel() {
        let ls = [([1.0, 0.0], 2.0), ([0.0, 1.0], 3.0)];
        assert_eq!(meet([0.0, 0.0], &ls), Some([2.0, 3.0]));
        let par = [([1.0, 0.0], 2.0), ([-1.0, 0.0], -2.2)];
        let q = meet([0.0, 5.0], &par).unwrap();
        assert!((q[0] - 2.1).abs() < 1e-12 && (q[1] - 5.0).abs() < 1e-12);
        assert_eq!(meet([0.0, 0.0], &[]), None);
    }

    #[test]
    fn a_tilted_trace_turns_onto_its_wall_points_and_outliers_do_not_move_it() {
        // A 14 m edge traced from a raster: the wall points lie on
        // off = 0.3 − 0.03·along (0.42 m of tilt over its length), with
        // ±1 cm noise and a tree's points 0.8 m out along its middle.
        let mut pts: Vec<(f64, f64)> = (0..140)
            .map(|k| {
                let along = 0.1 * f64::from(k);
                let noise = 0.01 * (f64::from(k) * 1.7).sin();
                (along, 0.3 - 0.03 * along + noise)
            })
            .collect();
        pts.extend((0..20).map(|k| (6.0 + 0.05 * f64::from(k), 0.8)));
        let (a, s) = resistant_line(&pts, 14.0, 1.0).unwrap();
        assert!((s + 0.03).abs() < 0.003, "slope {s}");
        assert!((a - 0.3).abs() < 0.02, "intercept {a}");
        // A tilt that would move an end farther than the reach keeps the
        // traced direction; so do points in one third only.
        let (_, s) = resistant_line(&pts, 14.0, 0.2).unwrap();
        assert_eq!(s, 0.0);
        let one_end: Vec<(f64, f64)> = pts.iter().filter(|p| p.0 < 4.0).copied().collect();
        let (a, s) = resistant_line(&one_end, 14.0, 1.0).unwrap();
        assert_eq!(s, 0.0);
        assert!(a > 0.2 && a < 0.31, "{a}");
        assert_eq!(resistant_line(&[], 14.0, 1.0), None);
    }
}
