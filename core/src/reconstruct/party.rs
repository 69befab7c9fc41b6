//! Party walls: where two footprints share a stretch of boundary (terraced
//! houses), how the two models' ground plans meet along it. A sample every
//! [`STEP_M`] along the stretch looks across it for each plan's edge: the
//! distance between the two edges there is a gap (the plans stop short of
//! each other) or an overlap (they cross), integrated into areas.

use geo::{Area, BooleanOps, Contains, Coord, LineString, MultiPolygon, Polygon};

use super::solid::{Shell, SurfaceType};
use crate::footprint::Footprint;

/// Two footprint edges closer than this (m) are one shared boundary.
pub const SHARED_TOL_M: f64 = 0.01;

/// Stretches shorter than this in total (m) are corners touching, not a wall.
const MIN_SHARED_M: f64 = 0.1;

/// Edges sharing a stretch are parallel within this sine (~3°).
const MAX_SINE: f64 = 0.05;

/// A plan's vertex this close (m) to a footprint corner is that corner:
/// val3dity's snapping tolerance, the most welding moves one.
pub const CORNER_TOL_M: f64 = 0.001;

/// Spacing of the samples along a stretch (m).
const STEP_M: f64 = 0.05;

/// How far across the stretch a plan's edge is looked for (m): beyond the
/// farthest a wall moves when it is fitted (1.5 × the 1 m wall band).
const REACH_M: f64 = 1.5;

/// A piece of a shared stretch: a segment on the first footprint's
/// boundary and the unit normal pointing out of it (into the second).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SharedPiece {
    /// Start of the piece (local frame).
    pub from: [f64; 2],
    /// End of the piece.
    pub to: [f64; 2],
    /// Unit normal out of the first footprint.
    pub out: [f64; 2],
}

/// Two footprints that share a stretch of boundary.
#[derive(Debug, Clone, PartialEq)]
pub struct SharedStretch {
    /// First footprint's id.
    pub a: u32,
    /// Second footprint's id.
    pub b: u32,
    /// The stretch, as pieces of `a`'s edges.
    pub pieces: Vec<SharedPiece>,
}

impl SharedStretch {
    /// Total length of the stretch (m).
    pub fn length(&self) -> f64 {
        self.pieces.iter().map(|p| dist(p.from, p.to)).sum()
    }
}

/// How two plans meet along a shared stretch.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct PartyGap {
    /// Length of the stretch (m).
    pub length_m: f64,
    /// Area between the two plans along the stretch (m²).
    pub gap_m2: f64,
    /// Area both plans cover along the stretch (m²).
    pub overlap_m2: f64,
    /// Largest distance between the two plans' edges across the stretch (m).
    pub max_offset_m: f64,
    /// Area both plans cover anywhere (m²), by polygon intersection.
    pub intersection_m2: f64,
    /// Corners of either footprint on the stretch that one of the plans
    /// has no vertex at (within [`CORNER_TOL_M`]): the two do not share
    /// the stretch vertex for vertex.
    pub missing_corners: usize,
}

/// One pair of neighbouring footprints and how their models meet.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PartyWall {
    /// First footprint's id.
    pub a: u32,
    /// Second footprint's id.
    pub b: u32,
    /// The two input footprints against each other.
    pub footprints: PartyGap,
    /// The two models' ground plans against each other.
    pub models: PartyGap,
}

/// Every pair of `footprints` sharing a stretch of boundary (within
/// [`SHARED_TOL_M`], [`MIN_SHARED_M`] or longer), in id order.
pub fn shared_stretches(footprints: &[Footprint]) -> Vec<SharedStretch> {
    let rings: Vec<Vec<Ring>> = footprints.iter().map(|f| rings(&f.polygon)).collect();
    let boxes: Vec<Option<[f64; 4]>> = footprints.iter().map(Footprint::bounds).collect();
    let mut out = Vec::new();
    for i in 0..footprints.len() {
        for j in i + 1..footprints.len() {
            let (Some(bi), Some(bj)) = (boxes[i], boxes[j]) else {
                continue;
            };
            let t = SHARED_TOL_M;
            if bi[0] > bj[2] + t || bj[0] > bi[2] + t || bi[1] > bj[3] + t || bj[1] > bi[3] + t {
                continue;
            }
            let pieces = shared_pieces(&rings[i], &rings[j]);
            let s = SharedStretch {
                a: footprints[i].id,
                b: footprints[j].id,
                pieces,
            };
            if s.length() >= MIN_SHARED_M {
                out.push(s);
            }
        }
    }
    out.sort_by_key(|s| (s.a.min(s.b), s.a.max(s.b)));
    out
}

/// How plan `pa` (of the stretch's first footprint) and `pb` (its second)
/// meet along `s`.
pub fn measure(s: &SharedStretch, pa: &MultiPolygon<f64>, pb: &MultiPolygon<f64>) -> PartyGap {
    let (ea, eb) = (edges(pa), edges(pb));
    let mut g = PartyGap {
        length_m: s.length(),
        intersection_m2: pa.intersection(pb).unsigned_area(),
        ..PartyGap::default()
    };
    for p in &s.pieces {
        let len = dist(p.from, p.to);
        let n = (len / STEP_M).ceil().max(1.0) as usize;
        let w = len / n as f64;
        for k in 0..n {
            let t = (k as f64 + 0.5) / n as f64;
            let q = [
                p.from[0] + t * (p.to[0] - p.from[0]),
                p.from[1] + t * (p.to[1] - p.from[1]),
            ];
            // `a` covers the side against `out` up to ta, `b` the side
            // along it from tb: tb > ta is a gap, tb < ta an overlap.
            let ta = across(q, p.out, &ea, || contains(pa, q), 1.0);
            let tb = across(q, p.out, &eb, || contains(pb, q), -1.0);
            let d = tb - ta;
            g.gap_m2 += d.max(0.0) * w;
            g.overlap_m2 += (-d).max(0.0) * w;
            g.max_offset_m = g.max_offset_m.max(d.abs());
        }
    }
    g
}

/// Every shared stretch of `footprints` with the two footprints and the two
/// models' ground plans (`plans`, by footprint id) measured along it; pairs
/// where either model is missing are left out.
pub fn party_walls(footprints: &[Footprint], plans: &[(u32, MultiPolygon<f64>)]) -> Vec<PartyWall> {
    let fp = |id: u32| footprints.iter().find(|f| f.id == id).map(|f| &f.polygon);
    let plan = |id: u32| plans.iter().find(|p| p.0 == id).map(|p| &p.1);
    shared_stretches(footprints)
        .iter()
        .filter_map(|s| {
            let (fa, fb) = (fp(s.a)?, fp(s.b)?);
            let (ma, mb) = (plan(s.a)?, plan(s.b)?);
            let corners = corners_on(s, fa, fb);
            let missing = |pa: &MultiPolygon<f64>, pb: &MultiPolygon<f64>| {
                missing(&corners, pa) + missing(&corners, pb)
            };
            Some(PartyWall {
                a: s.a,
                b: s.b,
                footprints: PartyGap {
                    missing_corners: missing(fa, fb),
                    ..measure(s, fa, fb)
                },
                models: PartyGap {
                    missing_corners: missing(ma, mb),
                    ..measure(s, ma, mb)
                },
            })
        })
        .collect()
}

/// The corners of `fa` and `fb` on the stretch `s`.
fn corners_on(s: &SharedStretch, fa: &MultiPolygon<f64>, fb: &MultiPolygon<f64>) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = Vec::new();
    for c in vertices(fa).into_iter().chain(vertices(fb)) {
        let on = s
            .pieces
            .iter()
            .any(|p| crate::geom::segment::distance(c, p.from, p.to) <= SHARED_TOL_M);
        if on && !out.iter().any(|o| dist(*o, c) <= CORNER_TOL_M) {
            out.push(c);
        }
    }
    out
}

/// How many of `corners` `plan` has no vertex at.
fn missing(corners: &[[f64; 2]], plan: &MultiPolygon<f64>) -> usize {
    let v = vertices(plan);
    corners
        .iter()
        .filter(|c| !v.iter().any(|q| dist(**c, *q) <= CORNER_TOL_M))
        .count()
}

fn vertices(mp: &MultiPolygon<f64>) -> Vec<[f64; 2]> {
    mp.0.iter()
        .flat_map(|p| std::iter::once(p.exterior()).chain(p.interiors()))
        .flat_map(|ls| ls.coords().map(|c| [c.x, c.y]))
        .collect()
}

/// A shell's ground faces in plan: the model's footprint as written.
pub fn ground_plan(shell: &Shell) -> MultiPolygon<f64> {
    let ring = |r: &Vec<u32>| -> LineString<f64> {
        r.iter()
            .filter_map(|&v| shell.vertices.get(v as usize))
            .map(|p| Coord { x: p[0], y: p[1] })
            .collect()
    };
    MultiPolygon::new(
        shell
            .faces
            .iter()
            .filter(|f| f.kind == SurfaceType::GroundSurface)
            .filter_map(|f| {
                let (outer, holes) = f.rings.split_first()?;
                Some(Polygon::new(ring(outer), holes.iter().map(ring).collect()))
            })
            .collect(),
    )
}

/// A ring's vertices (open) and whether the polygon's inside is on the
/// left of its edges.
struct Ring {
    pts: Vec<[f64; 2]>,
    inside_left: bool,
}

fn rings(mp: &MultiPolygon<f64>) -> Vec<Ring> {
    let mut out = Vec::new();
    for poly in &mp.0 {
        for (k, ls) in std::iter::once(poly.exterior())
            .chain(poly.interiors())
            .enumerate()
        {
            let mut pts: Vec<[f64; 2]> = ls.coords().map(|c| [c.x, c.y]).collect();
            if pts.len() > 1 && pts.first() == pts.last() {
                pts.pop();
            }
            if pts.len() < 3 {
                continue;
            }
            // An exterior counter-clockwise, or a hole clockwise, has the
            // polygon on its left.
            let ccw = crate::scene::reference::solids::ring_area(&pts) > 0.0;
            out.push(Ring {
                pts,
                inside_left: ccw == (k == 0),
            });
        }
    }
    out
}

/// The pieces of `a`'s edges within [`SHARED_TOL_M`] of one of `b`'s.
fn shared_pieces(a: &[Ring], b: &[Ring]) -> Vec<SharedPiece> {
    let mut out = Vec::new();
    for ra in a {
        let n = ra.pts.len();
        for k in 0..n {
            let (p0, p1) = (ra.pts[k], ra.pts[(k + 1) % n]);
            let len = dist(p0, p1);
            if len <= 0.0 {
                continue;
            }
            let u = [(p1[0] - p0[0]) / len, (p1[1] - p0[1]) / len];
            let left = [-u[1], u[0]];
            let out_n = if ra.inside_left {
                [-left[0], -left[1]]
            } else {
                left
            };
            let mut spans: Vec<(f64, f64)> = Vec::new();
            for rb in b {
                let m = rb.pts.len();
                for l in 0..m {
                    if let Some(s) = near_span(p0, u, len, rb.pts[l], rb.pts[(l + 1) % m]) {
                        spans.push(s);
                    }
                }
            }
            for (s0, s1) in union(spans) {
                out.push(SharedPiece {
                    from: [p0[0] + s0 * u[0], p0[1] + s0 * u[1]],
                    to: [p0[0] + s1 * u[0], p0[1] + s1 * u[1]],
                    out: out_n,
                });
            }
        }
    }
    out
}

/// The span `[s0, s1]` of the edge `p0 + s·u`, `s` in `[0, len]`, lying
/// within [`SHARED_TOL_M`] of segment `r0`–`r1` and beside it.
fn near_span(
    p0: [f64; 2],
    u: [f64; 2],
    len: f64,
    r0: [f64; 2],
    r1: [f64; 2],
) -> Option<(f64, f64)> {
    let lf = dist(r0, r1);
    if lf <= 0.0 {
        return None;
    }
    let uf = [(r1[0] - r0[0]) / lf, (r1[1] - r0[1]) / lf];
    let nf = [-uf[1], uf[0]];
    let w = [p0[0] - r0[0], p0[1] - r0[1]];
    // Distance from f's line and position along f are both linear in s.
    let across = (dot(nf, w), dot(nf, u));
    // Edges crossing at a corner come within the tolerance over a
    // centimetre or two: only (nearly) parallel edges share a stretch.
    if across.1.abs() > MAX_SINE {
        return None;
    }
    let along = (dot(uf, w), dot(uf, u));
    let (a0, a1) = linear_within(across, -SHARED_TOL_M, SHARED_TOL_M)?;
    let (b0, b1) = linear_within(along, 0.0, lf)?;
    let (s0, s1) = (a0.max(b0).max(0.0), a1.min(b1).min(len));
    (s1 > s0).then_some((s0, s1))
}

/// The `s` where `v.0 + s·v.1` lies in `[lo, hi]`.
fn linear_within(v: (f64, f64), lo: f64, hi: f64) -> Option<(f64, f64)> {
    if v.1.abs() < 1e-12 {
        return (v.0 >= lo && v.0 <= hi).then_some((f64::NEG_INFINITY, f64::INFINITY));
    }
    let (x, y) = ((lo - v.0) / v.1, (hi - v.0) / v.1);
    Some((x.min(y), x.max(y)))
}

/// Overlapping spans merged, in order.
fn union(mut spans: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    spans.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut out: Vec<(f64, f64)> = Vec::new();
    for s in spans {
        match out.last_mut() {
            Some(l) if s.0 <= l.1 => l.1 = l.1.max(s.1),
            _ => out.push(s),
        }
    }
    out
}

/// Every edge of a plan.
fn edges(mp: &MultiPolygon<f64>) -> Vec<([f64; 2], [f64; 2])> {
    mp.0.iter()
        .flat_map(|p| std::iter::once(p.exterior()).chain(p.interiors()))
        .flat_map(|ls| ls.lines())
        .map(|l| ([l.start.x, l.start.y], [l.end.x, l.end.y]))
        .collect()
}

fn contains(mp: &MultiPolygon<f64>, q: [f64; 2]) -> bool {
    mp.contains(&Coord { x: q[0], y: q[1] })
}

/// Where along `q + t·n` (|t| ≤ [`REACH_M`]) the plan's edge nearest `q`
/// crosses. With no edge in reach the plan covers the whole line or none
/// of it: `side` is +1 for a plan on the −n side (its edge is then at
/// +reach when it covers `q`), −1 for one on the +n side.
fn across(
    q: [f64; 2],
    n: [f64; 2],
    edges: &[([f64; 2], [f64; 2])],
    covers: impl Fn() -> bool,
    side: f64,
) -> f64 {
    let mut best: Option<f64> = None;
    for &(p0, p1) in edges {
        let d = [p1[0] - p0[0], p1[1] - p0[1]];
        let den = cross(n, d);
        if den.abs() < 1e-12 {
            continue;
        }
        let w = [p0[0] - q[0], p0[1] - q[1]];
        let (t, s) = (cross(w, d) / den, cross(w, n) / den);
        if (0.0..=1.0).contains(&s) && t.abs() <= REACH_M && best.is_none_or(|b| t.abs() < b.abs())
        {
            best = Some(t);
        }
    }
    best.unwrap_or_else(|| {
        if covers() {
            side * REACH_M
        } else {
            -side * REACH_M
        }
    })
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::polygon;

    fn fp(id: u32, x0: f64, x1: f64, y1: f64) -> Footprint {
        Footprint {
            id,
            name: id.to_string(),
            polygon: MultiPolygon::new(vec![polygon![
                (x: x0, y: 0.0), (x: x1, y: 0.0), (x: x1, y: y1), (x: x0, y: y1)
            ]]),
        }
    }

    fn rect(x0: f64, x1: f64, y0: f64, y1: f64) -> MultiPolygon<f64> {
        MultiPolygon::new(vec![polygon![
            (x: x0, y: y0), (x: x1, y: y0), (x: x1, y: y1), (x: x0, y: y1)
        ]])
    }

    #[test]
    fn terraced_houses_share_their_common_wall_and_corners_do_not_count() {
        // Three houses in a row, 6 m deep; the third is 8 m deep and its
        // wall with the second is 6 m long; a fourth touches the third at
        // one corner only.
        let fps = [
            fp(1, 0.0, 5.0, 6.0),
            fp(2, 5.0, 10.0, 6.0),
            fp(3, 10.0, 15.0, 8.0),
            fp(4, 15.0, 20.0, -3.0),
        ];
        let s = shared_stretches(&fps);
        let pairs: Vec<(u32, u32)> = s.iter().map(|s| (s.a, s.b)).collect();
        assert_eq!(pairs, vec![(1, 2), (2, 3)]);
        assert!((s[0].length() - 6.0).abs() < 1e-9);
        assert!((s[1].length() - 6.0).abs() < 1e-9);
        // The normal points out of the first house, into the second.
        assert_eq!(s[0].pieces[0].out, [1.0, 0.0]);
        // A neighbour 8 mm off still shares the wall; 2 cm off does not.
        let off = [fp(1, 0.0, 5.0, 6.0), fp(2, 5.008, 10.0, 6.0)];
        assert!((shared_stretches(&off)[0].length() - 6.0).abs() < 1e-9);
        let apart = [fp(1, 0.0, 5.0, 6.0), fp(2, 5.02, 10.0, 6.0)];
        assert!(shared_stretches(&apart).is_empty());
    }

    #[test]
    fn a_gap_an_overlap_and_a_tilt_between_two_plans_are_measured() {
        let fps = [fp(1, 0.0, 5.0, 6.0), fp(2, 5.0, 10.0, 6.0)];
        let s = &shared_stretches(&fps)[0];
        // The footprints themselves meet exactly.
        let g = measure(s, &fps[0].polygon, &fps[1].polygon);
        assert!(
            g.gap_m2 < 1e-9 && g.overlap_m2 < 1e-9 && g.max_offset_m < 1e-9,
            "{g:?}"
        );
        // The first model's wall 0.2 m short of the line: a 0.2 × 6 m gap.
        let g = measure(s, &rect(0.0, 4.8, 0.0, 6.0), &fps[1].polygon);
        assert!((g.gap_m2 - 1.2).abs() < 1e-6, "{g:?}");
        assert!(g.overlap_m2 < 1e-9 && (g.max_offset_m - 0.2).abs() < 1e-9);
        assert!(g.intersection_m2 < 1e-9);
        // The second model reaching 0.1 m into the first: 0.6 m² overlap.
        let g = measure(s, &fps[0].polygon, &rect(4.9, 10.0, 0.0, 6.0));
        assert!(
            (g.overlap_m2 - 0.6).abs() < 1e-6 && g.gap_m2 < 1e-9,
            "{g:?}"
        );
        assert!((g.intersection_m2 - 0.6).abs() < 1e-4, "{g:?}");
        // A wall tilted from 0 to 0.3 m across: a triangle of 0.9 m².
        let tilted = MultiPolygon::new(vec![polygon![
            (x: 0.0, y: 0.0), (x: 5.0, y: 0.0), (x: 4.7, y: 6.0), (x: 0.0, y: 6.0)
        ]]);
        let g = measure(s, &tilted, &fps[1].polygon);
        assert!((g.gap_m2 - 0.9).abs() < 1e-3, "{g:?}");
        assert!((g.max_offset_m - 0.3).abs() < 0.01, "{g:?}");
        // A model missing its side of the stretch entirely: the whole
        // reach counts as gap.
        let g = measure(s, &rect(0.0, 2.0, 0.0, 6.0), &fps[1].polygon);
        assert!((g.gap_m2 - REACH_M * 6.0).abs() < 1e-6, "{g:?}");
    }

    #[test]
    fn a_shell_ground_plan_is_its_base_in_plan() {
        let sq = fp(1, 0.0, 2.0, 3.0);
        let shell = super::super::prism::prism(&sq.polygon, 0.0, 5.0);
        let plan = ground_plan(&shell);
        assert!((plan.unsigned_area() - 6.0).abs() < 1e-9);
        let walls = party_walls(
            &[sq.clone(), fp(2, 2.0, 4.0, 3.0)],
            &[(1, plan), (2, fp(2, 2.0, 4.0, 3.0).polygon)],
        );
        assert_eq!(walls.len(), 1);
        assert!(walls[0].models.gap_m2 < 1e-9 && walls[0].models.overlap_m2 < 1e-9);
        assert_eq!(walls[0].models.missing_corners, 0);
    }

    #[test]
    fn a_corner_of_one_footprint_inside_the_others_edge_is_missing_there() {
        // The second house has a corner half-way up the shared wall (a
        // T-junction): the walls meet, but not vertex for vertex.
        let a = fp(1, 0.0, 5.0, 6.0);
        let b = Footprint {
            id: 2,
            name: "2".into(),
            polygon: MultiPolygon::new(vec![polygon![
                (x: 5.0, y: 0.0), (x: 10.0, y: 0.0), (x: 10.0, y: 6.0), (x: 5.0, y: 6.0), (x: 5.0, y: 3.0)
            ]]),
        };
        let plans = [(1, a.polygon.clone()), (2, b.polygon.clone())];
        let w = party_walls(&[a, b], &plans);
        assert_eq!(w[0].footprints.missing_corners, 1, "{w:?}");
        assert!(w[0].footprints.gap_m2 < 1e-9 && w[0].footprints.max_offset_m < 1e-9);
    }
}
