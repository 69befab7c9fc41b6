//! The closed LoD2 solid on a planar partition: a roof face per region at
//! its plane's height, a vertical face along every boundary segment whose
//! two sides differ in height (down to the base on the outline), and the
//! base as the ground face. Heights met at a 2D vertex become shared
//! levels, so every edge is used by exactly two faces, in opposite
//! directions, by construction.

use std::collections::HashMap;

use geo::{Coord, LineString, MultiPolygon, Polygon};

use super::partition::Partition;

/// Two heights at one 2D vertex closer than this (m) are one vertex; under
/// val3dity's 1 cm planarity tolerance, so a roof face moved onto a merged
/// level stays planar.
const LEVEL_EPS: f64 = 0.008;

/// What a face of a model is (CityJSON semantic surface).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
pub enum SurfaceType {
    /// A roof face.
    RoofSurface,
    /// A vertical face.
    WallSurface,
    /// The base.
    GroundSurface,
}

/// One planar face: outer ring then holes, indices into the model's
/// vertices, counter-clockwise seen from outside.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelFace {
    /// Roof, wall or ground.
    pub kind: SurfaceType,
    /// Outer ring, then holes (first vertex not repeated).
    pub rings: Vec<Vec<u32>>,
}

/// Vertices and faces of one closed solid.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Shell {
    /// Vertex positions, local frame.
    pub vertices: Vec<[f64; 3]>,
    /// Faces.
    pub faces: Vec<ModelFace>,
}

/// Edge-use counts of a shell (see [`Shell::check`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct SolidCheck {
    /// Undirected edges used by one face only (holes in the surface).
    pub boundary_edges: usize,
    /// Undirected edges used by more than two faces.
    pub non_manifold_edges: usize,
    /// Edges used twice in the same direction (faces turned inconsistently).
    pub misoriented_edges: usize,
    /// Faces with fewer than three distinct vertices.
    pub degenerate_faces: usize,
}

impl SolidCheck {
    /// Closed: every edge used by exactly two faces, in opposite directions.
    pub fn watertight(&self) -> bool {
        self.boundary_edges == 0 && self.non_manifold_edges == 0 && self.misoriented_edges == 0
    }

    /// Watertight with no degenerate face.
    pub fn valid(&self) -> bool {
        self.watertight() && self.degenerate_faces == 0
    }
}

impl Shell {
    /// Counts how each edge of the face rings is used.
    pub fn check(&self) -> SolidCheck {
        let mut uses: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
        let mut out = SolidCheck::default();
        for f in &self.faces {
            let mut distinct: Vec<u32> = f.rings.iter().flatten().copied().collect();
            distinct.sort_unstable();
            distinct.dedup();
            if distinct.len() < 3 {
                out.degenerate_faces += 1;
            }
            for r in &f.rings {
                for k in 0..r.len() {
                    let (a, b) = (r[k], r[(k + 1) % r.len()]);
                    if a == b {
                        continue;
                    }
                    let e = uses.entry((a.min(b), a.max(b))).or_default();
                    if a < b {
                        e.0 += 1;
                    } else {
                        e.1 += 1;
                    }
                }
            }
        }
        for (fwd, back) in uses.values() {
            match fwd + back {
                1 => out.boundary_edges += 1,
                2 if *fwd != 1 => out.misoriented_edges += 1,
                2 => {}
                _ => out.non_manifold_edges += 1,
            }
        }
        out
    }

    /// Replaces each roof face farther than `tol` m from planar (a plane
    /// clamped to the building's height range at some corners) by its
    /// triangles, so every face is planar as ISO 19107 asks; the boundary
    /// edges stay, so the shell stays closed.
    pub(crate) fn split_warped_roofs(&mut self, tol: f64) {
        let mut out = Vec::with_capacity(self.faces.len());
        for f in std::mem::take(&mut self.faces) {
            let rings: Vec<Vec<[f64; 3]>> = f
                .rings
                .iter()
                .map(|r| r.iter().map(|&v| self.vertices[v as usize]).collect())
                .collect();
            let flat: Vec<[f64; 3]> = rings.iter().flatten().copied().collect();
            let warped = f.kind == SurfaceType::RoofSurface
                && crate::validity::flatness(&flat).is_some_and(|d| d > tol);
            if !warped {
                out.push(f);
                continue;
            }
            let ids: Vec<u32> = f.rings.iter().flatten().copied().collect();
            // In plan, not on the best-fit plane: a roof is a polygon in plan,
            // and a node on a straight wall (three corners in a line in
            // plan, at warped heights) is then no ear, where on the tilted
            // plane it gave a vertical sliver lying in that wall (306).
            let plan: Vec<[f64; 2]> = flat.iter().map(|p| [p[0], p[1]]).collect();
            let mut index_rings = Vec::with_capacity(rings.len());
            let mut start = 0;
            for r in &rings {
                index_rings.push((start..start + r.len()).collect::<Vec<_>>());
                start += r.len();
            }
            let mut tris = crate::scene::polygon::triangulate_2d(&plan, &index_rings);
            // Triangles turn counter-clockwise in plan; a ring turning the
            // other way keeps its own direction.
            let ccw = index_rings.first().is_some_and(|r| {
                (0..r.len())
                    .map(|k| {
                        let (a, b) = (plan[r[k]], plan[r[(k + 1) % r.len()]]);
                        a[0] * b[1] - b[0] * a[1]
                    })
                    .sum::<f64>()
                    > 0.0
            });
            flip_slivers(&plan, &mut tris);
            if !ccw {
                tris.iter_mut().for_each(|t| t.reverse());
            }
            if tris.is_empty() {
                out.push(f);
                continue;
            }
            for t in tris {
                out.push(ModelFace {
                    kind: f.kind,
                    rings: vec![t.iter().map(|&i| ids[i]).collect()],
                });
            }
        }
        self.faces = out;
    }

    /// Merges vertices closer than `tol` m into one (the partition can give
    /// one corner twice, a few ulps apart), drops the repeats this leaves in
    /// a ring and the faces left with no area (their edges pair up on the
    /// neighbours), and keeps only the vertices in use. val3dity counts
    /// vertices within its snapping tolerance as one; unwelded, the corner
    /// fails 101/102.
    pub(crate) fn weld(&mut self, tol: f64) {
        let cell = |p: [f64; 3]| p.map(|c| (c / tol).floor() as i64);
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        let mut map: Vec<u32> = Vec::with_capacity(self.vertices.len());
        let mut kept: Vec<[f64; 3]> = Vec::new();
        for &p in &self.vertices {
            let c = cell(p);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let Some(ids) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                            continue;
                        };
                        for &k in ids {
                            let q = kept[k as usize];
                            let d2 = (0..3).map(|i| (p[i] - q[i]).powi(2)).sum::<f64>();
                            if d2 <= tol * tol {
                                found = Some(k);
                                break 'search;
                            }
                        }
                    }
                }
            }
            let k = found.unwrap_or_else(|| {
                let k = u32::try_from(kept.len()).unwrap_or(u32::MAX);
                kept.push(p);
                grid.entry(c).or_default().push(k);
                k
            });
            map.push(k);
        }
        let mut faces = Vec::with_capacity(self.faces.len());
        for f in std::mem::take(&mut self.faces) {
            let mut rings = Vec::with_capacity(f.rings.len());
            for (i, r) in f.rings.iter().enumerate() {
                let mut out: Vec<u32> = r.iter().map(|&v| map[v as usize]).collect();
                out.dedup();
                while out.len() > 1 && out.first() == out.last() {
                    out.pop();
                }
                if out.len() >= 3 {
                    rings.push(out);
                } else if i == 0 {
                    break;
                }
            }
            if !rings.is_empty() {
                faces.push(ModelFace {
                    kind: f.kind,
                    rings,
                });
            }
        }
        // Keep only the vertices the faces use, in first-use order.
        let mut renum: HashMap<u32, u32> = HashMap::new();
        let mut vertices = Vec::new();
        for f in &mut faces {
            for r in &mut f.rings {
                for v in r.iter_mut() {
                    let n = *renum.entry(*v).or_insert_with(|| {
                        vertices.push(kept[*v as usize]);
                        u32::try_from(vertices.len() - 1).unwrap_or(u32::MAX)
                    });
                    *v = n;
                }
            }
        }
        self.vertices = vertices;
        self.faces = faces;
    }

    /// The enclosed volume, m³ (divergence theorem over the triangles;
    /// positive for outward faces).
    pub fn volume(&self) -> f64 {
        self.triangles()
            .iter()
            .map(|(t, _)| {
                let [a, b, c] = *t;
                (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0]))
                    / 6.0
            })
            .sum()
    }

    /// The faces as triangles with their kind.
    pub fn triangles(&self) -> Vec<([[f64; 3]; 3], SurfaceType)> {
        let mut out = Vec::new();
        for f in &self.faces {
            let rings: Vec<Vec<[f64; 3]>> = f
                .rings
                .iter()
                .map(|r| r.iter().map(|&v| self.vertices[v as usize]).collect())
                .collect();
            let refs: Vec<&[[f64; 3]]> = rings.iter().map(|r| r.as_slice()).collect();
            let flat: Vec<[f64; 3]> = rings.iter().flatten().copied().collect();
            for t in crate::scene::polygon::triangulate_3d(&refs) {
                out.push((t.map(|i| flat[i]), f.kind));
            }
        }
        out
    }
}

/// A triangle this close to flat in plan (its height over its longest
/// edge, m) is a sliver: a node on a straight wall, a few ulps off the line.
const SLIVER_M: f64 = 1e-6;

/// Flips away the slivers of a plan triangulation (counter-clockwise): a
/// triangle a-b-c with b on a-c and its neighbour a-c-d across a-c become
/// a-b-d and b-c-d. A sliver at warped heights stands vertical in the wall
/// along a-c and crosses it (306).
fn flip_slivers(plan: &[[f64; 2]], tris: &mut [[usize; 3]]) {
    let orient = |a: usize, b: usize, c: usize| {
        let (p, q, r) = (plan[a], plan[b], plan[c]);
        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    };
    for _ in 0..tris.len() {
        let mut flipped = false;
        for i in 0..tris.len() {
            let t = tris[i];
            let len = |a: usize, b: usize| (plan[a][0] - plan[b][0]).hypot(plan[a][1] - plan[b][1]);
            // The longest edge is c-a, b the vertex opposite it.
            let k = (0..3)
                .max_by(|&x, &y| len(t[x], t[(x + 1) % 3]).total_cmp(&len(t[y], t[(y + 1) % 3])))
                .unwrap_or(0);
            let (c, a, b) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            let long = len(c, a);
            if long <= 0.0 || orient(a, b, c).abs() > SLIVER_M * long {
                continue;
            }
            let Some((j, d)) = tris.iter().enumerate().find_map(|(j, u)| {
                (0..3)
                    .find(|&m| u[m] == a && u[(m + 1) % 3] == c)
                    .map(|m| (j, u[(m + 2) % 3]))
            }) else {
                continue;
            };
            if j == i || orient(a, b, d) <= 0.0 || orient(b, c, d) <= 0.0 {
                continue;
            }
            tris[i] = [a, b, d];
            tris[j] = [b, c, d];
            flipped = true;
        }
        if !flipped {
            break;
        }
    }
}

/// Merged heights at each 2D vertex, and each region's level among them.
pub(crate) struct Levels {
    /// Sorted level heights per vertex.
    heights: Vec<Vec<f64>>,
    /// (vertex, region) → index into that vertex's levels.
    of: HashMap<(u32, u32), usize>,
}

impl Levels {
    /// The levels of every vertex of `p` for the regions' heights.
    pub(crate) fn new(p: &Partition, height: &dyn Fn(u32, [f64; 2]) -> f64) -> Self {
        let mut at: Vec<Vec<u32>> = vec![Vec::new(); p.verts.len()];
        for c in &p.chains {
            for &v in &c.verts {
                for r in [c.left, c.right] {
                    if !at[v as usize].contains(&r) {
                        at[v as usize].push(r);
                    }
                }
            }
        }
        let mut heights = Vec::with_capacity(at.len());
        let mut of = HashMap::new();
        for (v, regions) in at.iter().enumerate() {
            let xy = p.verts[v];
            let mut zs: Vec<(f64, u32)> = regions.iter().map(|&r| (height(r, xy), r)).collect();
            zs.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut lv: Vec<f64> = Vec::new();
            for (z, r) in zs {
                if lv.last().is_none_or(|last| z - last > LEVEL_EPS) {
                    lv.push(z);
                }
                of.insert((v as u32, r), lv.len() - 1);
            }
            heights.push(lv);
        }
        Levels { heights, of }
    }

    /// The level of region `r` at vertex `v` (0 where `r` is not there).
    pub(crate) fn of(&self, v: u32, r: u32) -> usize {
        self.of.get(&(v, r)).copied().unwrap_or(0)
    }

    /// The height of region `r`'s level at vertex `v`.
    pub(crate) fn height(&self, v: u32, r: u32) -> f64 {
        self.heights
            .get(v as usize)
            .and_then(|h| h.get(self.of(v, r)))
            .copied()
            .unwrap_or(0.0)
    }
}

/// Inserts a vertex where a boundary segment's two sides swap which is
/// higher (two roof planes crossing), so no wall face twists. Which side is
/// higher is read from the merged levels the shell is built on: two
/// heights a few millimetres apart can fall on different levels when a
/// third region's height lies between them, and a twist there opens the
/// shell as surely as a large one.
pub(crate) fn split_crossings(p: &mut Partition, height: &dyn Fn(u32, [f64; 2]) -> f64) {
    // Each pass can only add crossings on segments a previous pass left
    // straight, because new vertices have one level per side pair; a few
    // passes settle it.
    for _ in 0..4 {
        let lv = Levels::new(p, height);
        let mut inserted = false;
        for c in 0..p.chains.len() {
            let (l, r) = (p.chains[c].left, p.chains[c].right);
            let old = p.chains[c].verts.clone();
            let mut verts = Vec::with_capacity(old.len());
            for (k, &a) in old.iter().enumerate() {
                verts.push(a);
                let Some(&b) = old.get(k + 1) else { break };
                let da = lv.of(a, l) as i64 - lv.of(a, r) as i64;
                let db = lv.of(b, l) as i64 - lv.of(b, r) as i64;
                if da * db >= 0 {
                    continue;
                }
                let (pa, pb) = (p.verts[a as usize], p.verts[b as usize]);
                let fa = height(l, pa) - height(r, pa);
                let fb = height(l, pb) - height(r, pb);
                // Level order follows height order, so fa and fb differ in
                // sign and t lies inside; the guard is for rounding only.
                let t = fa / (fa - fb);
                let t = if t > 0.0 && t < 1.0 { t } else { 0.5 };
                p.verts
                    .push([pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])]);
                verts.push((p.verts.len() - 1) as u32);
                inserted = true;
            }
            p.chains[c].verts = verts;
        }
        if !inserted {
            break;
        }
    }
}

/// Builds the shell on `p`: region r's surface at `height(r, xy)`, the
/// outside (region 0) at `height(0, xy)` (the base).
pub(crate) fn build_shell(p: &Partition, height: &dyn Fn(u32, [f64; 2]) -> f64) -> Shell {
    let lv = Levels::new(p, height);
    let levels = &lv.heights;
    let mut shell = Shell::default();
    let mut ids: HashMap<(u32, usize), u32> = HashMap::new();
    let mut vid = |v: u32, level: usize, shell: &mut Shell| -> u32 {
        *ids.entry((v, level)).or_insert_with(|| {
            let xy = p.verts[v as usize];
            shell
                .vertices
                .push([xy[0], xy[1], levels[v as usize][level]]);
            (shell.vertices.len() - 1) as u32
        })
    };
    let level = |v: u32, r: u32| lv.of(v, r);
    // Roofs: region rings at the region's level.
    for r in 1..=p.regions {
        for group in group_rings(p, p.rings(r), 1.0) {
            let rings = group
                .iter()
                .map(|ring| {
                    ring.iter()
                        .map(|&v| vid(v, level(v, r), &mut shell))
                        .collect()
                })
                .collect();
            shell.faces.push(ModelFace {
                kind: SurfaceType::RoofSurface,
                rings,
            });
        }
    }
    // Base: the outside's rings (clockwise from above = counter-clockwise from below).
    for group in group_rings(p, p.rings(0), -1.0) {
        let rings = group
            .iter()
            .map(|ring| {
                ring.iter()
                    .map(|&v| vid(v, level(v, 0), &mut shell))
                    .collect()
            })
            .collect();
        shell.faces.push(ModelFace {
            kind: SurfaceType::GroundSurface,
            rings,
        });
    }
    // Walls: a vertical face per segment whose sides differ.
    for c in &p.chains {
        for w in c.verts.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (la, ra, lb, rb) = (
                level(a, c.left),
                level(a, c.right),
                level(b, c.left),
                level(b, c.right),
            );
            if la == ra && lb == rb {
                continue;
            }
            let left_higher = la > ra || lb > rb;
            let (top_a, bot_a) = (la.max(ra), la.min(ra));
            let (top_b, bot_b) = (lb.max(rb), lb.min(rb));
            let mut ring = Vec::new();
            for l in (bot_a..=top_a).rev() {
                ring.push(vid(a, l, &mut shell));
            }
            for l in bot_b..=top_b {
                ring.push(vid(b, l, &mut shell));
            }
            if !left_higher {
                ring.reverse();
            }
            shell.faces.push(ModelFace {
                kind: SurfaceType::WallSurface,
                rings: vec![ring],
            });
        }
    }
    shell
}

/// Groups rings into faces: rings whose signed area has the sign of
/// `outer_sign` are outer rings, the others holes of the outer ring that
/// holds them.
fn group_rings(p: &Partition, rings: Vec<Vec<u32>>, outer_sign: f64) -> Vec<Vec<Vec<u32>>> {
    let (outers, holes): (Vec<_>, Vec<_>) = rings
        .into_iter()
        .partition(|r| p.ring_area(r) * outer_sign > 0.0);
    let mut groups: Vec<Vec<Vec<u32>>> = outers.into_iter().map(|o| vec![o]).collect();
    for h in holes {
        let q = p.verts[h[0] as usize];
        // A hole's vertex lies on its outer ring's boundary only at a
        // node, so test the hole's centroid-ish point: its first edge's midpoint nudged inward.
        let q2 = p.verts[h[1 % h.len()] as usize];
        let mid = [(q[0] + q2[0]) * 0.5, (q[1] + q2[1]) * 0.5];
        let best = groups
            .iter()
            .enumerate()
            .filter(|(_, g)| contains(p, &g[0], mid))
            .min_by(|a, b| {
                p.ring_area(&a.1[0])
                    .abs()
                    .total_cmp(&p.ring_area(&b.1[0]).abs())
            })
            .map(|(k, _)| k);
        if let Some(k) = best {
            groups[k].push(h);
        }
    }
    groups
}

/// Whether `q` lies inside the partition ring `ring` (vertex indices).
fn contains(p: &Partition, ring: &[u32], q: [f64; 2]) -> bool {
    let points: Vec<[f64; 2]> = ring.iter().map(|&v| p.verts[v as usize]).collect();
    crate::geom::ring::contains(&points, q)
}

/// The partition's footprint: the outside's rings turned into polygons.
pub(crate) fn outline(p: &Partition) -> MultiPolygon<f64> {
    let ls = |ring: &Vec<u32>| {
        let mut c: Vec<Coord<f64>> = ring
            .iter()
            .rev()
            .map(|&v| Coord {
                x: p.verts[v as usize][0],
                y: p.verts[v as usize][1],
            })
            .collect();
        if let Some(&f) = c.first() {
            c.push(f);
        }
        LineString::new(c)
    };
    MultiPolygon::new(
        group_rings(p, p.rings(0), -1.0)
            .iter()
            .map(|g| Polygon::new(ls(&g[0]), g[1..].iter().map(ls).collect()))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::super::partition::block_partition as partition;
    use super::*;

    /// A 2 m cube whose top corner 4 is given twice, 1e-12 m apart, as
    /// the partition can give a corner; one wall uses the copy.
    fn cube_with_a_twin_corner() -> Shell {
        let mut vertices: Vec<[f64; 3]> = (0..8)
            .map(|k| {
                let [x, y] = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]][k % 4];
                [x, y, if k < 4 { 0.0 } else { 2.0 }]
            })
            .collect();
        vertices.push([1e-12, 0.0, 2.0]);
        let face = |kind, ring: &[u32]| ModelFace {
            kind,
            rings: vec![ring.to_vec()],
        };
        use SurfaceType::{GroundSurface as G, RoofSurface as R, WallSurface as W};
        Shell {
            vertices,
            faces: vec![
                face(G, &[0, 3, 2, 1]),
                face(R, &[4, 8, 5, 6, 7]),
                face(W, &[0, 1, 5, 8]),
                face(W, &[1, 2, 6, 5]),
                face(W, &[2, 3, 7, 6]),
                face(W, &[3, 0, 4, 7]),
            ],
        }
    }

    #[test]
    fn a_warped_roof_splits_into_triangles_none_of_them_vertical() {
        // A roof whose first corner lies on the straight edge between its
        // last and second in plan, 0.5 m below them: on the tilted best-fit
        // plane it is an ear, whose triangle would stand vertical in the wall.
        let mut s = Shell {
            vertices: vec![
                [1.0, 0.0, -0.5],
                [2.0, 0.0, 0.0],
                [1.0, 2.0, 2.0],
                [0.0, 0.0, 0.0],
            ],
            faces: vec![ModelFace {
                kind: SurfaceType::RoofSurface,
                rings: vec![vec![0, 1, 2, 3]],
            }],
        };
        s.split_warped_roofs(0.005);
        assert_eq!(s.faces.len(), 2);
        for f in &s.faces {
            let p: Vec<[f64; 3]> = f.rings[0].iter().map(|&v| s.vertices[v as usize]).collect();
            let plan = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
            assert!(plan > 0.1, "{p:?}");
        }
    }

    #[test]
    fn a_sliver_across_a_node_on_a_straight_edge_is_flipped_away() {
        // b sits on a-c a few ulps off the line; a-b-c and a-c-d become
        // a-b-d and b-c-d.
        let plan = [[0.0, 0.0], [1.0, 1e-15], [2.0, 0.0], [1.0, 2.0]];
        let mut tris = [[0, 1, 2], [0, 2, 3]];
        flip_slivers(&plan, &mut tris);
        assert_eq!(tris, [[0, 1, 3], [1, 2, 3]]);
        // A real triangle stays.
        let mut fat = [[0, 2, 3]];
        flip_slivers(&plan, &mut fat);
        assert_eq!(fat, [[0, 2, 3]]);
    }

    #[test]
    fn welding_merges_a_twin_corner_into_a_valid_cube() {
        let mut s = cube_with_a_twin_corner();
        let before = super::super::validity_codes(&s);
        assert!(before.contains(&102), "{before:?}");
        assert!(!s.check().watertight());
        s.weld(0.001);
        assert_eq!(s.vertices.len(), 8);
        assert!(s.faces.iter().all(|f| f.rings[0].len() == 4));
        assert!(s.check().valid(), "{:?}", s.check());
        assert_eq!(super::super::validity_codes(&s), Vec::<u16>::new());
    }

    #[test]
    fn welding_drops_a_face_that_collapses_and_keeps_the_shell_closed() {
        let mut s = cube_with_a_twin_corner();
        // A sliver wall between the corner and its twin: no area once welded.
        s.faces.push(ModelFace {
            kind: SurfaceType::WallSurface,
            rings: vec![vec![4, 0, 8]],
        });
        s.weld(0.001);
        assert_eq!(s.faces.len(), 6);
        assert!(s.check().valid(), "{:?}", s.check());
    }

    #[test]
    fn gable_and_tower_shells_are_closed() {
        // Two gable halves (1, 2) and a tower (3) on the south half.
        let (mut p, code) = partition(|i, j| {
            if (7..10).contains(&i) && (2..4).contains(&j) {
                3
            } else if j < 5 {
                1
            } else {
                2
            }
        });
        let h = move |r: u32, xy: [f64; 2]| match r {
            0 => 0.0,
            r => match code[r as usize - 1] {
                1 => 10.0 - 0.5 * (5.0 - xy[1]),
                2 => 10.0 - 0.5 * (xy[1] - 5.0),
                _ => 15.0,
            },
        };
        split_crossings(&mut p, &h);
        let s = build_shell(&p, &h);
        let check = s.check();
        assert!(check.valid(), "{check:?}");
        // Volume by the divergence theorem: gable box 10 × 8 × (8..10) plus the tower.
        let vol = s.volume();
        let gable = 10.0 * 8.0 * 8.0 + 10.0 * 8.0 * 2.0 * 0.5;
        // The tower replaces 3 × 2 m of roof (heights 8.5..9.5 at y 2..4) by 15 m.
        let tower = 3.0 * 2.0 * (15.0 - 9.0);
        assert!(
            (vol - gable - tower).abs() < 1e-6,
            "{vol} vs {}",
            gable + tower
        );
        let o = outline(&p);
        assert!((geo::Area::unsigned_area(&o) - 80.0).abs() < 1e-9);
    }

    #[test]
    fn a_crossing_hidden_by_level_merging_is_split() {
        let (mut p, code) = partition(|i, j| {
            if j >= 7 {
                3
            } else if i < 6 {
                1
            } else {
                2
            }
        });
        // Where regions 1, 2 and 3 meet (y = 7), 1 is 1 cm above 2 but
        // 2 merges into 3's level and 1 does not, so 1 reads higher there;
        // at the south end 2 is a metre higher.
        let h = move |r: u32, xy: [f64; 2]| match r {
            0 => 0.0,
            r => match code[r as usize - 1] {
                1 => 10.025 + (xy[1] - 7.0) / 6.0,
                2 => 10.015,
                _ => 10.0,
            },
        };
        let before = build_shell(&p, &h).check();
        split_crossings(&mut p, &h);
        let after = build_shell(&p, &h).check();
        assert!(!before.valid(), "the case no longer twists: {before:?}");
        assert!(after.valid(), "{after:?}");
    }
}
