//! A ground surface around loaded buildings: a regular grid over each
//! building's footprint box plus a margin, through the buildings' base
//! vertices (and any ground surface vertices the file has).
//!
//! Height at a grid vertex: inside the convex hull of the base samples, the
//! Delaunay (barycentric) interpolation of their heights, so the ground
//! follows a sloped street along the walls; outside, the height at the
//! nearest point of the hull (continuous across it). Vertices more than a
//! cell away from every footprint box are then smoothed. Without samples
//! (or with fewer than three not in a line) every vertex takes an
//! inverse-distance blend of the buildings' bases: inside one or more
//! footprint boxes the highest of their bases, so no wall floats. Buildings
//! far apart (a city-wide sample) get separate patches.

use std::collections::{BTreeSet, HashMap};

use spade::{DelaunayTriangulation, FloatTriangulation, HasPosition, Point2, Triangulation};

use super::base::Footprint;
use super::streets::{length, street_cells, streets};
use crate::scene::builder::MeshPart;

/// How the ground under loaded buildings is made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TerrainOptions {
    /// Ground reaches this far beyond each footprint box, metres.
    pub margin: f64,
    /// Grid cell size, metres (grown when the grid would exceed 4 M cells).
    pub cell: f64,
    /// Smoothing passes over the vertices away from the buildings.
    pub smoothing: usize,
    /// The surface is lowered by this much, metres (under a file's own ground).
    pub drop: f64,
    /// Width of the streets built between clusters whose patches do not
    /// meet, metres (0: none; each cluster stands on its own island).
    pub street: f64,
}

impl Default for TerrainOptions {
    fn default() -> Self {
        Self {
            margin: 30.0,
            cell: 2.0,
            smoothing: 8,
            drop: 0.0,
            street: STREET_WIDTH,
        }
    }
}

/// A base sample for the Delaunay triangulation: its xy and height.
struct Sample {
    at: Point2<f64>,
    z: f64,
}

impl HasPosition for Sample {
    type Scalar = f64;

    fn position(&self) -> Point2<f64> {
        self.at
    }
}

/// Heights through base samples: Delaunay inside their convex hull, the
/// nearest point of the hull outside (continuous across it).
struct Surface {
    tri: DelaunayTriangulation<Sample>,
    /// Hull edges: ends and their heights.
    hull: Vec<([f64; 2], f64, [f64; 2], f64)>,
}

impl Surface {
    /// The triangulation of `samples`, `None` when it has no triangle.
    fn new(samples: &[[f64; 3]]) -> Option<Self> {
        let mut tri = DelaunayTriangulation::<Sample>::new();
        for p in samples {
            if p.iter().all(|v| v.is_finite()) {
                // Duplicate xy positions keep one sample: a wall's base.
                let _ = tri.insert(Sample {
                    at: Point2::new(p[0], p[1]),
                    z: p[2],
                });
            }
        }
        if tri.num_inner_faces() == 0 {
            return None;
        }
        let hull = tri
            .convex_hull()
            .map(|e| {
                let [a, b] = e.vertices().map(|v| (v.position(), v.data().z));
                ([a.0.x, a.0.y], a.1, [b.0.x, b.0.y], b.1)
            })
            .collect();
        Some(Self { tri, hull })
    }

    fn height(&self, x: f64, y: f64) -> f64 {
        if let Some(z) = self
            .tri
            .barycentric()
            .interpolate(|v| v.data().z, Point2::new(x, y))
        {
            return z;
        }
        let mut best = (f64::INFINITY, 0.0);
        for (a, za, b, zb) in &self.hull {
            let (c, t) = crate::geom::segment::closest([x, y], *a, *b);
            let dist2 = (c[0] - x).powi(2) + (c[1] - y).powi(2);
            if dist2 < best.0 {
                best = (dist2, za + t * (zb - za));
            }
        }
        best.1
    }
}

const MAX_CELLS: usize = 4_000_000;
/// A two-lane street with its verges: room for the vehicle and its graph's
/// clearance, and for the airborne survey to see it as ground.
const STREET_WIDTH: f64 = 10.0;
const BUCKET: f64 = 128.0;

/// The cells of the ground grid: `(j, i)` is the square from
/// `(x0 + i cell, y0 + j cell)`.
struct Cells {
    x0: f64,
    y0: f64,
    cell: f64,
    cells: BTreeSet<(i64, i64)>,
}

impl Cells {
    /// Each footprint box grown by `margin`, and the streets of `width`
    /// between clusters; the cell grows from `cell` until they fit in
    /// [`MAX_CELLS`]. `None` without footprints.
    fn new(footprints: &[Footprint], margin: f64, width: f64, mut cell: f64) -> Option<Self> {
        let x0 = footprints
            .iter()
            .map(|f| f.min[0] - margin)
            .min_by(f64::total_cmp)?;
        let y0 = footprints
            .iter()
            .map(|f| f.min[1] - margin)
            .fold(f64::INFINITY, f64::min);
        let roads = if width > 0.0 {
            streets(footprints, margin)
        } else {
            Vec::new()
        };
        let cells_at = |cell: f64| -> f64 {
            let patches: f64 = footprints
                .iter()
                .map(|f| {
                    ((f.max[0] - f.min[0] + 2.0 * margin) / cell + 2.0)
                        * ((f.max[1] - f.min[1] + 2.0 * margin) / cell + 2.0)
                })
                .sum();
            let along: f64 = roads.iter().map(|r| (length(r) + width) / cell + 2.0).sum();
            patches + along * (width / cell + 2.0)
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
        for r in &roads {
            cells.extend(street_cells(r, width, cell, [x0, y0]));
        }
        Some(Self {
            x0,
            y0,
            cell,
            cells,
        })
    }
}

/// A finite, non-negative `v`, else `fallback`.
fn non_negative(v: f64, fallback: f64) -> f64 {
    if v.is_finite() { v.max(0.0) } else { fallback }
}

/// The ground mesh around `footprints` through the base `samples` (empty
/// when there are no footprints).
pub fn terrain_around(
    footprints: &[Footprint],
    samples: &[[f64; 3]],
    options: &TerrainOptions,
) -> MeshPart {
    let mut m = MeshPart::default();
    let margin = non_negative(options.margin, 30.0);
    let cell = if options.cell.is_finite() && options.cell > 0.01 {
        options.cell
    } else {
        2.0
    };
    let width = non_negative(options.street, 0.0);
    let Some(grid) = Cells::new(footprints, margin, width, cell) else {
        return m;
    };
    let (x0, y0, cell) = (grid.x0, grid.y0, grid.cell);
    let near = Buckets::new(footprints, margin + 2.0 * cell);
    let surface = Surface::new(samples);
    let mut ids: HashMap<(i64, i64), u32> = HashMap::new();
    let mut vertex = |m: &mut MeshPart, i: i64, j: i64| -> u32 {
        *ids.entry((i, j)).or_insert_with(|| {
            let (x, y) = (x0 + i as f64 * cell, y0 + j as f64 * cell);
            let z = match &surface {
                Some(s) => s.height(x, y),
                None => near.height(footprints, x, y),
            };
            m.vertex([x, y, z])
        })
    };
    for &(j, i) in &grid.cells {
        let v00 = vertex(&mut m, i, j);
        let v10 = vertex(&mut m, i + 1, j);
        let v11 = vertex(&mut m, i + 1, j + 1);
        let v01 = vertex(&mut m, i, j + 1);
        m.triangle(v00, v10, v11);
        m.triangle(v00, v11, v01);
    }
    if surface.is_some() {
        smooth(&mut m, &ids, footprints, cell, options.smoothing);
    }
    if options.drop.is_finite() && options.drop > 0.0 {
        for p in &mut m.vertices {
            p[2] -= options.drop;
        }
    }
    m
}

/// Averages each grid vertex more than a cell away from every footprint box
/// with its four neighbours, `passes` times (Jacobi).
fn smooth(
    m: &mut MeshPart,
    ids: &HashMap<(i64, i64), u32>,
    footprints: &[Footprint],
    cell: f64,
    passes: usize,
) {
    let near = Buckets::new(footprints, cell);
    let free: Vec<(u32, [Option<u32>; 4])> = ids
        .iter()
        .filter(|&(_, &v)| {
            let p = m.vertices[v as usize];
            !near.within(footprints, p[0], p[1], cell)
        })
        .map(|(&(i, j), &v)| {
            let n = [(i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)].map(|k| ids.get(&k).copied());
            (v, n)
        })
        .collect();
    for _ in 0..passes {
        let next: Vec<f64> = free
            .iter()
            .map(|(v, n)| {
                let (mut sum, mut count) = (m.vertices[*v as usize][2], 1.0);
                for k in n.iter().flatten() {
                    sum += m.vertices[*k as usize][2];
                    count += 1.0;
                }
                sum / count
            })
            .collect();
        for ((v, _), z) in free.iter().zip(next) {
            m.vertices[*v as usize][2] = z;
        }
    }
}

/// Footprints registered in square buckets, for finding those near a point.
struct Buckets {
    map: HashMap<(i64, i64), Vec<usize>>,
    /// Footprints whose box spans more than [`MAX_BUCKETS`] buckets (a
    /// damaged vertex kilometres away): looked at for every point instead
    /// of filling the map (one such box asked for 5.5 GB).
    large: Vec<usize>,
}

/// Most buckets one footprint's box is registered in.
const MAX_BUCKETS: i128 = 4096;

impl Buckets {
    fn new(footprints: &[Footprint], reach: f64) -> Self {
        let mut map: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        let mut large = Vec::new();
        let b = |v: f64| (v / BUCKET).floor() as i64;
        for (k, f) in footprints.iter().enumerate() {
            let (xs, ys) = (
                b(f.min[0] - reach)..=b(f.max[0] + reach),
                b(f.min[1] - reach)..=b(f.max[1] + reach),
            );
            let span = |r: &std::ops::RangeInclusive<i64>| {
                i128::from(*r.end()) - i128::from(*r.start()) + 1
            };
            if span(&xs).saturating_mul(span(&ys)) > MAX_BUCKETS {
                large.push(k);
                continue;
            }
            for by in ys {
                for bx in xs.clone() {
                    map.entry((bx, by)).or_default().push(k);
                }
            }
        }
        Self { map, large }
    }

    /// True when `(x, y)` lies within `reach` of a registered footprint box.
    fn within(&self, footprints: &[Footprint], x: f64, y: f64, reach: f64) -> bool {
        let key = ((x / BUCKET).floor() as i64, (y / BUCKET).floor() as i64);
        let near = |k: &usize| footprints[*k].distance(x, y) <= reach;
        self.map.get(&key).is_some_and(|c| c.iter().any(near)) || self.large.iter().any(near)
    }

    fn height(&self, footprints: &[Footprint], x: f64, y: f64) -> f64 {
        let key = ((x / BUCKET).floor() as i64, (y / BUCKET).floor() as i64);
        let term = |k: usize| {
            let f = &footprints[k];
            let d = f.distance(x, y);
            (d * d, f.base)
        };
        // Called for every grid vertex: no list is built per call.
        match self.map.get(&key) {
            Some(c) => blend_bases(c.iter().chain(&self.large).map(|&k| term(k))),
            None => blend_bases((0..footprints.len()).map(term)),
        }
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
        let m = terrain_around(&[f], &[], &TerrainOptions::default());
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
            terrain_around(&[], &[], &TerrainOptions::default())
                .triangles
                .is_empty()
        );
    }

    /// A building on a street that climbs 1 m per 10 m in x: its base
    /// vertices are on the slope.
    fn sloped() -> (Footprint, Vec<[f64; 3]>) {
        let f = Footprint {
            min: [0.0, 0.0],
            max: [20.0, 10.0],
            base: 100.0,
        };
        let corners = [
            [0.0, 0.0],
            [20.0, 0.0],
            [20.0, 10.0],
            [0.0, 10.0],
            [10.0, 0.0],
            [10.0, 10.0],
        ];
        let samples = corners.map(|[x, y]| [x, y, 100.0 + x / 10.0]).to_vec();
        (f, samples)
    }

    #[test]
    fn ground_follows_sloped_base_vertices() {
        let (f, samples) = sloped();
        let m = terrain_around(&[f], &samples, &TerrainOptions::default());
        let at = |x: f64, y: f64| {
            m.vertices
                .iter()
                .find(|p| (p[0] - x).abs() < 1e-9 && (p[1] - y).abs() < 1e-9)
                .map(|p| p[2])
        };
        // Along the walls the ground is at the base vertices' heights.
        for [x, y, z] in &samples {
            let g = at(*x, *y).unwrap_or(f64::NAN);
            assert!((g - z).abs() < 1e-9, "ground {g} at ({x}, {y}), base {z}");
        }
        assert!((at(4.0, 0.0).unwrap_or(f64::NAN) - 100.4).abs() < 1e-9);
        // Far away it stays within the bases' range and changes smoothly.
        let heights: Vec<f64> = m.vertices.iter().map(|p| p[2]).collect();
        assert!(heights.iter().all(|z| (99.99..=102.01).contains(z)));
        for t in &m.triangles {
            let z = t.map(|i| m.vertices[i as usize][2]);
            let spread = z.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
                - z.iter().fold(f64::INFINITY, |a, &b| a.min(b));
            assert!(spread < 0.5, "step of {spread} m in one 2 m cell");
        }
    }

    /// Pieces of `m` whose triangles share vertices.
    fn pieces(m: &MeshPart) -> usize {
        let mut parent: Vec<usize> = (0..m.vertices.len()).collect();
        fn find(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        for t in &m.triangles {
            for k in 1..3 {
                let (a, b) = (
                    find(&mut parent, t[0] as usize),
                    find(&mut parent, t[k] as usize),
                );
                parent[a] = b;
            }
        }
        let used: BTreeSet<usize> = m.triangles.iter().flatten().map(|&v| v as usize).collect();
        let roots: BTreeSet<usize> = used.into_iter().map(|v| find(&mut parent, v)).collect();
        roots.len()
    }

    /// Four clusters of two buildings at the corners of a 500 m × 380 m
    /// rectangle, each cluster on ground 4–6 m above or below the others.
    fn corners() -> (Vec<Footprint>, Vec<[f64; 3]>) {
        let mut fps = Vec::new();
        let mut samples = Vec::new();
        for (cx, cy, z) in [
            (0.0, 0.0, 400.0),
            (500.0, 0.0, 406.0),
            (0.0, 380.0, 396.0),
            (500.0, 380.0, 403.0),
        ] {
            for dx in [0.0, 40.0] {
                let f = Footprint {
                    min: [cx + dx, cy],
                    max: [cx + dx + 15.0, cy + 12.0],
                    base: z,
                };
                for x in [f.min[0], f.max[0]] {
                    for y in [f.min[1], f.max[1]] {
                        samples.push([x, y, z]);
                    }
                }
                fps.push(f);
            }
        }
        (fps, samples)
    }

    #[test]
    fn clusters_far_apart_stand_on_one_piece_of_ground() {
        let (fps, samples) = corners();
        for s in [&samples[..], &[]] {
            let m = terrain_around(&fps, s, &TerrainOptions::default());
            assert_eq!(pieces(&m), 1, "with {} samples", s.len());
            let islands = TerrainOptions {
                street: 0.0,
                ..TerrainOptions::default()
            };
            assert_eq!(pieces(&terrain_around(&fps, s, &islands)), 4);
            // The streets climb no more than the clusters differ: 10 m over
            // 380 m, nowhere a step the vehicle (20°) cannot drive.
            for t in &m.triangles {
                let p = t.map(|i| m.vertices[i as usize]);
                let dz = (0..3)
                    .map(|k| (p[k][2] - p[(k + 1) % 3][2]).abs())
                    .fold(0.0, f64::max);
                assert!(dz < 0.5, "a step of {dz} m in a 2 m cell at {:?}", p[0]);
            }
        }
        // The middle of the rectangle, 190 m from every street, has no ground.
        let m = terrain_around(&fps, &samples, &TerrainOptions::default());
        assert!(
            m.vertices
                .iter()
                .all(|p| (p[0] - 257.0).hypot(p[1] - 196.0) > 100.0)
        );
    }

    #[test]
    fn lowered_under_a_files_own_ground() {
        let (f, samples) = sloped();
        let options = TerrainOptions {
            drop: 0.05,
            ..TerrainOptions::default()
        };
        let low = terrain_around(&[f], &samples, &options);
        let high = terrain_around(&[f], &samples, &TerrainOptions::default());
        for (a, b) in low.vertices.iter().zip(&high.vertices) {
            assert!((b[2] - a[2] - 0.05).abs() < 1e-9);
        }
    }
}
