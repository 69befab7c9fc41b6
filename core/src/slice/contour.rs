//! Boundary of an occupancy grid as polygons: cell edges with an occupied
//! cell on the left are linked into rings (outer rings counter-clockwise,
//! courtyards clockwise), the staircase is simplified away, and each hole is
//! attached to the outer ring that contains it.

use geo::{Area, Contains, Coord, LineString, MultiPolygon, Point, Polygon, Simplify};

use super::raster::Raster;

const NONE: u32 = u32::MAX;

/// The outline of the occupied cells of `raster` (only cells whose entry in
/// `keep` is true, when given), simplified with tolerance `simplify_m`.
/// Rings enclosing less than `min_area` m² are dropped.
pub fn occupancy_contour(
    raster: &Raster,
    keep: Option<&dyn Fn(usize) -> bool>,
    simplify_m: f64,
    min_area: f64,
) -> MultiPolygon<f64> {
    let occ = |i: isize, j: isize| -> bool {
        raster.get(i, j) && keep.is_none_or(|k| k(j as usize * raster.frame.nx + i as usize))
    };
    let rings = trace_rings(raster.frame.nx, raster.frame.ny, &occ);
    let to_world = |v: [i32; 2]| {
        let [x, y] = raster.frame.corner(f64::from(v[0]), f64::from(v[1]));
        Coord { x, y }
    };
    let mut outers: Vec<Polygon<f64>> = Vec::new();
    let mut holes: Vec<LineString<f64>> = Vec::new();
    for ring in rings {
        let mut coords: Vec<Coord<f64>> = ring.iter().map(|&v| to_world(v)).collect();
        if let Some(&first) = coords.first() {
            coords.push(first);
        }
        let ls = LineString::new(coords);
        let poly = Polygon::new(ls.clone(), vec![]);
        let area = poly.signed_area();
        if area.abs() < min_area {
            continue;
        }
        if area > 0.0 {
            outers.push(poly);
        } else {
            holes.push(ls);
        }
    }
    let mut interiors: Vec<Vec<LineString<f64>>> = vec![Vec::new(); outers.len()];
    for hole in holes {
        let Some(probe) = hole.0.first().map(|c| Point::from(*c)) else {
            continue;
        };
        // The hole's corner lies strictly inside its outer ring, so the
        // smallest outer ring containing it is its owner.
        let owner = outers
            .iter()
            .enumerate()
            .filter(|(_, o)| o.contains(&probe))
            .min_by(|a, b| a.1.unsigned_area().total_cmp(&b.1.unsigned_area()))
            .map(|(k, _)| k);
        if let Some(k) = owner {
            interiors[k].push(hole);
        }
    }
    let polys = outers
        .into_iter()
        .zip(interiors)
        .map(|(o, h)| {
            let (ext, _) = o.into_inner();
            Polygon::new(ext, h).simplify(simplify_m)
        })
        .filter(|p| p.exterior().0.len() >= 4 && p.unsigned_area() >= min_area)
        .collect();
    MultiPolygon(polys)
}

/// Rings of grid-corner coordinates, each a sequence of corners without the
/// closing repeat, collinear corners removed. At a corner shared by two
/// diagonal cells the trace turns right, keeping those cells apart.
fn trace_rings(nx: usize, ny: usize, occ: &dyn Fn(isize, isize) -> bool) -> Vec<Vec<[i32; 2]>> {
    let vx = nx + 1;
    let vid = |x: i32, y: i32| y as usize * vx + x as usize;
    let mut out_edges: Vec<[u32; 2]> = vec![[NONE; 2]; vx * (ny + 1)];
    let mut push = |from: [i32; 2], to: [i32; 2]| {
        let slot = &mut out_edges[vid(from[0], from[1])];
        let t = vid(to[0], to[1]) as u32;
        if slot[0] == NONE {
            slot[0] = t;
        } else {
            slot[1] = t;
        }
    };
    for j in 0..ny as isize {
        for i in 0..nx as isize {
            if !occ(i, j) {
                continue;
            }
            let (x, y) = (i as i32, j as i32);
            if !occ(i, j - 1) {
                push([x, y], [x + 1, y]);
            }
            if !occ(i + 1, j) {
                push([x + 1, y], [x + 1, y + 1]);
            }
            if !occ(i, j + 1) {
                push([x + 1, y + 1], [x, y + 1]);
            }
            if !occ(i - 1, j) {
                push([x, y + 1], [x, y]);
            }
        }
    }
    let pos = |v: u32| [(v as usize % vx) as i32, (v as usize / vx) as i32];
    let mut used: Vec<[bool; 2]> = vec![[false; 2]; out_edges.len()];
    let choose = |at: u32, dir: [i32; 2], out_edges: &[[u32; 2]]| -> usize {
        let slots = out_edges[at as usize];
        if slots[1] == NONE {
            return 0;
        }
        let p = pos(at);
        let right = [dir[1], -dir[0]];
        let d0 = {
            let q = pos(slots[0]);
            [q[0] - p[0], q[1] - p[1]]
        };
        if d0 == right { 0 } else { 1 }
    };
    let mut rings = Vec::new();
    for start in 0..out_edges.len() {
        for s in 0..2 {
            if out_edges[start][s] == NONE || used[start][s] {
                continue;
            }
            let mut ring = Vec::new();
            let (mut at, mut slot) = (start as u32, s);
            // Bounded walk: a ring can't have more edges than the grid.
            for _ in 0..out_edges.len() * 2 {
                if used[at as usize][slot] {
                    break;
                }
                used[at as usize][slot] = true;
                let next = out_edges[at as usize][slot];
                ring.push(pos(at));
                let (p, q) = (pos(at), pos(next));
                let dir = [q[0] - p[0], q[1] - p[1]];
                at = next;
                if out_edges[at as usize][0] == NONE {
                    break;
                }
                slot = choose(at, dir, &out_edges);
            }
            let ring = drop_collinear(ring);
            if ring.len() >= 3 {
                rings.push(ring);
            }
        }
    }
    rings
}

fn drop_collinear(ring: Vec<[i32; 2]>) -> Vec<[i32; 2]> {
    let n = ring.len();
    if n < 3 {
        return ring;
    }
    (0..n)
        .filter(|&k| {
            let a = ring[(k + n - 1) % n];
            let b = ring[k];
            let c = ring[(k + 1) % n];
            (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) != 0
        })
        .map(|k| ring[k])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fill(r: &mut Raster, f: impl Fn(f64, f64) -> bool) {
        for j in 0..r.frame.ny {
            for i in 0..r.frame.nx {
                let [x, y] = r.frame.corner(i as f64 + 0.5, j as f64 + 0.5);
                r.occupied[j * r.frame.nx + i] = f(x, y);
            }
        }
    }

    #[test]
    fn courtyard_square_has_one_hole_and_right_area() {
        let mut r = Raster::covering([0.0, 0.0], [30.0, 30.0], 0.5, 2);
        fill(&mut r, |x, y| {
            let inside = |a: f64, b: f64| (a..b).contains(&x) && (a..b).contains(&y);
            inside(0.0, 30.0) && !inside(10.0, 20.0)
        });
        let mp = occupancy_contour(&r, None, 0.3, 1.0);
        assert_eq!(mp.0.len(), 1);
        assert_eq!(mp.0[0].interiors().len(), 1);
        assert!(
            (mp.unsigned_area() - 800.0).abs() < 1.0,
            "{}",
            mp.unsigned_area()
        );
        // counter-clockwise outer ring
        assert!(Polygon::new(mp.0[0].exterior().clone(), vec![]).signed_area() > 0.0);
    }

    #[test]
    fn two_blocks_give_two_polygons_and_empty_gives_none() {
        let mut r = Raster::covering([0.0, 0.0], [30.0, 10.0], 1.0, 2);
        fill(&mut r, |x, y| {
            y < 10.0 && y > 0.0 && ((0.0..10.0).contains(&x) || (20.0..30.0).contains(&x))
        });
        assert_eq!(occupancy_contour(&r, None, 0.5, 1.0).0.len(), 2);
        fill(&mut r, |_, _| false);
        assert!(occupancy_contour(&r, None, 0.5, 1.0).0.is_empty());
    }
}
