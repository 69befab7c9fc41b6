//! The parts of a scene that lie far apart in plan: a city model's buildings
//! scattered over kilometres are surveyed patch by patch instead of over
//! their whole bounding box, where almost every pulse would hit nothing
//! (or the streets that join them, which no prior needs whole).

use crate::scene::ObjectKind;

/// Cells of this size, metres, that hold a building triangle join their
/// neighbours' patch: patches' buildings lie at least this far apart.
pub const PATCH_GAP_M: f32 = 100.0;

/// A patch reaches this far beyond its buildings, metres: the ground a
/// city model's terrain is built over around them.
pub const APRON_M: f32 = 30.0;

/// Beyond this many cells the scene is one patch (a kilometre-wide grid at
/// 100 m is 10⁴ cells; this bound keeps a scene with wild coordinates cheap).
const MAX_CELLS: usize = 4_000_000;

/// One connected part of a scene in plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    /// Lower corner of its buildings' bounds and apron.
    pub lo: [f32; 3],
    /// Upper corner of its buildings' bounds and apron.
    pub hi: [f32; 3],
    /// Highest vertex of the ground triangles in it; `None` without ground.
    pub ground_top: Option<f32>,
}

impl Patch {
    fn of(t: &[[f32; 3]; 3]) -> Self {
        Self {
            lo: std::array::from_fn(|k| t[0][k].min(t[1][k]).min(t[2][k])),
            hi: std::array::from_fn(|k| t[0][k].max(t[1][k]).max(t[2][k])),
            ground_top: None,
        }
    }

    fn join(&mut self, o: &Patch) {
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(o.lo[k]);
            self.hi[k] = self.hi[k].max(o.hi[k]);
        }
        self.ground_top = match (self.ground_top, o.ground_top) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
    }

    /// Plan area of its bounds, m².
    pub fn area(&self) -> f64 {
        f64::from(self.hi[0] - self.lo[0]) * f64::from(self.hi[1] - self.lo[1])
    }

    fn overlaps(&self, o: &Patch, pad: f32) -> bool {
        (0..2).all(|k| self.lo[k] - pad <= o.hi[k] + pad && o.lo[k] - pad <= self.hi[k] + pad)
    }
}

/// The patches of the building triangles among `tris` (`kind[i]`: triangle
/// i's object kind), each grown by [`APRON_M`], with the highest vertex of
/// the ground triangles inside it as its ground; in order of their lowest
/// cell; none without buildings.
pub fn patches(tris: &[[[f32; 3]; 3]], kind: &[ObjectKind]) -> Vec<Patch> {
    let is = |i: usize, k: ObjectKind| kind.get(i) == Some(&k);
    let is_building = |i: usize| is(i, ObjectKind::Building);
    let boxes: Vec<Patch> = tris
        .iter()
        .enumerate()
        .filter(|&(i, _)| is_building(i))
        .map(|(_, t)| Patch::of(t))
        .collect();
    let Some(all) = boxes.iter().copied().reduce(|mut a, b| {
        a.join(&b);
        a
    }) else {
        return Vec::new();
    };
    let cells = |k: usize| ((all.hi[k] - all.lo[k]) / PATCH_GAP_M).floor() as usize + 1;
    let (nx, ny) = (cells(0), cells(1));
    let mut out = if nx.saturating_mul(ny) > MAX_CELLS {
        vec![all]
    } else {
        components(&boxes, &all, nx, ny)
    };
    for p in &mut out {
        for k in 0..2 {
            p.lo[k] -= APRON_M;
            p.hi[k] += APRON_M;
        }
    }
    for (i, t) in tris.iter().enumerate() {
        if !is(i, ObjectKind::Ground) {
            continue;
        }
        for p in out.iter_mut() {
            let top = t
                .iter()
                .filter(|v| (0..2).all(|k| p.lo[k] <= v[k] && v[k] <= p.hi[k]))
                .map(|v| v[2])
                .reduce(f32::max);
            if let Some(top) = top {
                p.ground_top = Some(p.ground_top.map_or(top, |g| g.max(top)));
                p.lo[2] = p.lo[2].min(top);
            }
        }
    }
    out
}

/// The 8-connected components of the `nx` × `ny` cells of `all` that the
/// `boxes` cover, each as the union of its boxes.
fn components(boxes: &[Patch], all: &Patch, nx: usize, ny: usize) -> Vec<Patch> {
    let cell = |v: f32, k: usize| {
        (((v - all.lo[k]) / PATCH_GAP_M).floor().max(0.0) as usize).min([nx, ny][k] - 1)
    };
    // Each box covers a rectangle of cells: a difference array, then its
    // prefix sums, marks them all in time linear in boxes plus cells.
    let mut diff = vec![0i32; (nx + 1) * (ny + 1)];
    let at = |x: usize, y: usize| y * (nx + 1) + x;
    for b in boxes {
        let (x0, x1, y0, y1) = (
            cell(b.lo[0], 0),
            cell(b.hi[0], 0),
            cell(b.lo[1], 1),
            cell(b.hi[1], 1),
        );
        diff[at(x0, y0)] += 1;
        diff[at(x1 + 1, y0)] -= 1;
        diff[at(x0, y1 + 1)] -= 1;
        diff[at(x1 + 1, y1 + 1)] += 1;
    }
    for y in 0..=ny {
        for x in 1..=nx {
            diff[at(x, y)] += diff[at(x - 1, y)];
        }
    }
    for y in 1..=ny {
        for x in 0..=nx {
            diff[at(x, y)] += diff[at(x, y - 1)];
        }
    }
    // Components of occupied cells, 8-connected.
    let mut comp = vec![u32::MAX; nx * ny];
    let mut count = 0u32;
    let mut stack = Vec::new();
    for start in 0..nx * ny {
        if comp[start] != u32::MAX || diff[at(start % nx, start / nx)] <= 0 {
            continue;
        }
        comp[start] = count;
        stack.push(start);
        while let Some(c) = stack.pop() {
            let (x, y) = ((c % nx) as i64, (c / nx) as i64);
            for (dx, dy) in [
                (-1, -1),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                let (qx, qy) = (x + dx, y + dy);
                if qx < 0 || qy < 0 || qx >= nx as i64 || qy >= ny as i64 {
                    continue;
                }
                let q = qy as usize * nx + qx as usize;
                if comp[q] == u32::MAX && diff[at(q % nx, q / nx)] > 0 {
                    comp[q] = count;
                    stack.push(q);
                }
            }
        }
        count += 1;
    }
    let mut out: Vec<Option<Patch>> = vec![None; count as usize];
    for b in boxes {
        let c = comp[cell(b.lo[1], 1) * nx + cell(b.lo[0], 0)] as usize;
        match &mut out[c] {
            Some(p) => p.join(b),
            slot => *slot = Some(*b),
        }
    }
    out.into_iter().flatten().collect()
}

/// `patches` joined until none lies within `pad` of another, so that the
/// flight lines of one never sweep over the next.
pub fn joined(mut patches: Vec<Patch>, pad: f32) -> Vec<Patch> {
    loop {
        let pair = (0..patches.len()).find_map(|i| {
            (i + 1..patches.len())
                .find(|&j| patches[i].overlaps(&patches[j], pad))
                .map(|j| (i, j))
        });
        let Some((i, j)) = pair else {
            return patches;
        };
        let b = patches.remove(j);
        patches[i].join(&b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f32, y: f32, s: f32, z: f32) -> [[[f32; 3]; 3]; 2] {
        [
            [[x, y, z], [x + s, y, z], [x + s, y + s, z + 5.0]],
            [[x, y, z], [x + s, y + s, z + 5.0], [x, y + s, z]],
        ]
    }

    #[test]
    fn far_apart_buildings_are_patches_of_their_own() {
        let mut tris = Vec::new();
        for (x, y) in [(0.0, 0.0), (30.0, 10.0), (2000.0, 0.0), (2000.0, 3000.0)] {
            tris.extend(square(x, y, 20.0, 0.0));
        }
        let mut kind = vec![ObjectKind::Building; tris.len()];
        // Ground: a street joining them all, and a patch under the first two at 2 m.
        tris.push([
            [0.0, 0.0, 1.0],
            [2000.0, 3000.0, 1.0],
            [2010.0, 3000.0, 1.0],
        ]);
        tris.extend(square(-10.0, -10.0, 5.0, 2.0));
        kind.extend([ObjectKind::Ground; 3]);
        let p = patches(&tris, &kind);
        assert_eq!(p.len(), 3, "{p:?}");
        assert_eq!(p[0].lo, [-30.0, -30.0, 0.0]);
        assert_eq!(p[0].hi, [80.0, 60.0, 5.0]);
        // The street's corner at the origin and the 2 m patch (7 m at its top) lie in it.
        assert_eq!(p[0].ground_top, Some(7.0));
        assert_eq!(p[1].ground_top, None, "no ground vertex near (2000, 0)");
        assert_eq!(p[2].ground_top, Some(1.0));
        let total: f64 = p.iter().map(Patch::area).sum();
        assert!(
            (total - (110.0 * 90.0 + 2.0 * 80.0 * 80.0)).abs() < 1e-6,
            "{total}"
        );
        // Padded by 600 m, the two at x = 2000 m still lie apart (3 km); 2 km joins them all.
        assert_eq!(joined(p.clone(), 600.0).len(), 3);
        assert_eq!(joined(p, 2000.0).len(), 1);
    }

    #[test]
    fn no_buildings_no_patches() {
        let tris = vec![[[0.0, 0.0, 0.0], [5000.0, 0.0, 0.0], [0.0, 5000.0, 1.0]]];
        assert!(patches(&tris, &[ObjectKind::Ground]).is_empty());
        assert!(patches(&[], &[]).is_empty());
    }

    #[test]
    fn wild_coordinates_stay_one_patch() {
        let tris = vec![
            [
                [-2.0e9, 0.0, 0.0],
                [-2.0e9 + 1.0, 0.0, 0.0],
                [-2.0e9, 1.0, 0.0],
            ],
            [
                [2.0e9, 0.0, 0.0],
                [2.0e9 + 1.0, 0.0, 0.0],
                [2.0e9, 1.0, 0.0],
            ],
        ];
        assert_eq!(patches(&tris, &[ObjectKind::Building; 2]).len(), 1);
    }
}
