//! Closed solids the reference scene is built from: prisms (with holes),
//! podium + towers, a slab on pillars, a gable-roofed house, a tree.
//!
//! Each function returns one closed, outward-oriented mesh (every edge shared
//! by exactly two triangles, in opposite directions).

use crate::scene::builder::MeshPart;

/// An axis-aligned rectangle `[x0, x1] × [y0, y1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    /// Minimum x.
    pub x0: f64,
    /// Minimum y.
    pub y0: f64,
    /// Maximum x.
    pub x1: f64,
    /// Maximum y.
    pub y1: f64,
}

impl Rect {
    /// The rectangle with corner `(x, y)` and size `w × d`.
    pub fn at(x: f64, y: f64, w: f64, d: f64) -> Self {
        Self {
            x0: x,
            y0: y,
            x1: x + w,
            y1: y + d,
        }
    }

    /// Corners counter-clockwise seen from above.
    pub fn ring(&self) -> Vec<[f64; 2]> {
        vec![
            [self.x0, self.y0],
            [self.x1, self.y0],
            [self.x1, self.y1],
            [self.x0, self.y1],
        ]
    }
}

/// Signed area of a ring (positive when counter-clockwise).
pub fn ring_area(ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|k| {
            let (a, b) = (ring[k], ring[(k + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}

/// `ring` turned counter-clockwise.
pub fn ccw(ring: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut r = ring.to_vec();
    if ring_area(&r) < 0.0 {
        r.reverse();
    }
    r
}

/// A vertical prism over `outline` (with `holes`, e.g. a courtyard) from `z0` to `z1`.
pub fn prism(outline: &[[f64; 2]], holes: &[Vec<[f64; 2]>], z0: f64, z1: f64) -> MeshPart {
    let mut m = MeshPart::default();
    let outer = ccw(outline);
    // Holes clockwise, so their walls face into the hole.
    let holes: Vec<Vec<[f64; 2]>> = holes
        .iter()
        .map(|h| {
            let mut h = ccw(h);
            h.reverse();
            h
        })
        .collect();
    let ob = m.ring(&outer, z0);
    let ot = m.ring(&outer, z1);
    let hb: Vec<Vec<u32>> = holes.iter().map(|h| m.ring(h, z0)).collect();
    let ht: Vec<Vec<u32>> = holes.iter().map(|h| m.ring(h, z1)).collect();
    let mut bottom: Vec<&[u32]> = vec![&ob];
    bottom.extend(hb.iter().map(Vec::as_slice));
    let mut top: Vec<&[u32]> = vec![&ot];
    top.extend(ht.iter().map(Vec::as_slice));
    m.cap(&bottom, false);
    m.cap(&top, true);
    m.walls(&ob, &ot);
    for (b, t) in hb.iter().zip(&ht) {
        m.walls(b, t);
    }
    m
}

/// A podium over `podium` from `z0` to `z_roof` with towers standing on its
/// roof (`(footprint inside the podium, top height)`), as one closed surface.
pub fn podium_with_towers(podium: Rect, z0: f64, z_roof: f64, towers: &[(Rect, f64)]) -> MeshPart {
    let mut m = MeshPart::default();
    let base = m.ring(&podium.ring(), z0);
    let roof = m.ring(&podium.ring(), z_roof);
    m.cap(&[&base], false);
    m.walls(&base, &roof);
    let feet: Vec<Vec<u32>> = towers
        .iter()
        .map(|(r, _)| m.ring(&r.ring(), z_roof))
        .collect();
    let mut roof_rings: Vec<&[u32]> = vec![&roof];
    roof_rings.extend(feet.iter().map(Vec::as_slice));
    m.cap(&roof_rings, true);
    for ((rect, top), foot) in towers.iter().zip(&feet) {
        let head = m.ring(&rect.ring(), *top);
        m.walls(foot, &head);
        m.cap(&[&head], true);
    }
    m
}

/// A slab over `slab` from `z_floor` to `z_top` carried by `pillars` standing
/// from `z0`: an open ground floor (hollow base) under a closed body.
pub fn slab_on_pillars(
    slab: Rect,
    pillars: &[Rect],
    z0: f64,
    z_floor: f64,
    z_top: f64,
) -> MeshPart {
    let mut m = MeshPart::default();
    let mut heads = Vec::with_capacity(pillars.len());
    for p in pillars {
        let foot = m.ring(&p.ring(), z0);
        let head = m.ring(&p.ring(), z_floor);
        m.cap(&[&foot], false);
        m.walls(&foot, &head);
        heads.push(head);
    }
    let under = m.ring(&slab.ring(), z_floor);
    let top = m.ring(&slab.ring(), z_top);
    let mut under_rings: Vec<&[u32]> = vec![&under];
    under_rings.extend(heads.iter().map(Vec::as_slice));
    m.cap(&under_rings, false);
    m.walls(&under, &top);
    m.cap(&[&top], true);
    m
}

/// A house over `r` from `z0`, walls up to `z_eave`, a gable roof with its
/// ridge at `z_ridge` running along x (`ridge_along_x`) or y.
pub fn gable_house(r: Rect, z0: f64, z_eave: f64, z_ridge: f64, ridge_along_x: bool) -> MeshPart {
    if !ridge_along_x {
        // Build it mirrored in x = y, then mirror back (which flips the turn).
        let swapped = Rect {
            x0: r.y0,
            y0: r.x0,
            x1: r.y1,
            y1: r.x1,
        };
        let mut m = gable_house(swapped, z0, z_eave, z_ridge, true);
        for p in &mut m.vertices {
            p.swap(0, 1);
        }
        for t in &mut m.triangles {
            t.swap(1, 2);
        }
        return m;
    }
    let mut m = MeshPart::default();
    let b = m.ring(&r.ring(), z0);
    let e = m.ring(&r.ring(), z_eave);
    let ym = (r.y0 + r.y1) / 2.0;
    let r0 = m.vertex([r.x0, ym, z_ridge]);
    let r1 = m.vertex([r.x1, ym, z_ridge]);
    m.quad(b[0], b[3], b[2], b[1]);
    m.quad(b[0], b[1], e[1], e[0]);
    m.quad(b[2], b[3], e[3], e[2]);
    for &(p, q, eq, ridge, ep) in &[(b[1], b[2], e[2], r1, e[1]), (b[3], b[0], e[0], r0, e[3])] {
        m.triangle(p, q, eq);
        m.triangle(p, eq, ridge);
        m.triangle(p, ridge, ep);
    }
    m.quad(e[0], e[1], r1, r0);
    m.quad(e[2], e[3], r0, r1);
    m
}

/// A tree at `(x, y)` on ground height `ground`: a hexagonal trunk and a
/// crown (an icosphere, radius `crown_r`, vertical radius `crown_r * squash`)
/// whose bottom is `trunk_h` above the ground. Two closed parts.
pub fn tree(x: f64, y: f64, ground: f64, trunk_h: f64, crown_r: f64, squash: f64) -> MeshPart {
    let rt = 0.12 + 0.03 * crown_r;
    let h = 3.0_f64.sqrt() / 2.0;
    let hex: Vec<[f64; 2]> = [
        (1.0, 0.0),
        (0.5, h),
        (-0.5, h),
        (-1.0, 0.0),
        (-0.5, -h),
        (0.5, -h),
    ]
    .iter()
    .map(|&(c, s)| [x + rt * c, y + rt * s])
    .collect();
    let crown_z = ground + trunk_h + crown_r * squash;
    let mut m = prism(&hex, &[], ground - 0.3, crown_z);
    let mut crown = icosphere();
    for p in &mut crown.vertices {
        *p = [
            x + crown_r * p[0],
            y + crown_r * p[1],
            crown_z + crown_r * squash * p[2],
        ];
    }
    m.append(&crown);
    m
}

/// A unit icosphere: the icosahedron subdivided once (42 vertices, 80 triangles).
pub fn icosphere() -> MeshPart {
    let phi = (1.0 + 5.0_f64.sqrt()) / 2.0;
    let mut m = MeshPart::default();
    let raw = [
        [-1.0, phi, 0.0],
        [1.0, phi, 0.0],
        [-1.0, -phi, 0.0],
        [1.0, -phi, 0.0],
        [0.0, -1.0, phi],
        [0.0, 1.0, phi],
        [0.0, -1.0, -phi],
        [0.0, 1.0, -phi],
        [phi, 0.0, -1.0],
        [phi, 0.0, 1.0],
        [-phi, 0.0, -1.0],
        [-phi, 0.0, 1.0],
    ];
    for p in raw {
        m.vertex(unit(p));
    }
    let faces: [[u32; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut mids = std::collections::HashMap::new();
    for [a, b, c] in faces {
        let mut mid = |p: u32, q: u32| {
            *mids.entry((p.min(q), p.max(q))).or_insert_with(|| {
                let (u, v) = (m.vertices[p as usize], m.vertices[q as usize]);
                m.vertex(unit([u[0] + v[0], u[1] + v[1], u[2] + v[2]]))
            })
        };
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        m.triangle(a, ab, ca);
        m.triangle(b, bc, ab);
        m.triangle(c, ca, bc);
        m.triangle(ab, bc, ca);
    }
    m
}

fn unit(p: [f64; 3]) -> [f64; 3] {
    let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    [p[0] / n, p[1] / n, p[2] / n]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{ObjectKind, SceneBuilder};

    fn check_closed(m: &MeshPart, volume: f64) {
        let mut b = SceneBuilder::new([0.0; 3]);
        let o = b.add("building_test", ObjectKind::Building, 1, m);
        let s = b.finish();
        let d = s.edge_defects(o);
        assert!(d.is_closed(), "{d:?}");
        let v = s.signed_volume(o);
        assert!(
            (v - volume).abs() < 1e-3 * volume.max(1.0),
            "volume {v}, want {volume}"
        );
    }

    #[test]
    fn solids_are_closed_with_outward_normals() {
        let l = [
            [0.0, 0.0],
            [0.0, 10.0],
            [4.0, 10.0],
            [4.0, 4.0],
            [10.0, 4.0],
            [10.0, 0.0],
        ];
        check_closed(&prism(&l, &[], 0.0, 3.0), 3.0 * 64.0);
        let court = Rect::at(4.0, 4.0, 4.0, 4.0).ring();
        check_closed(
            &prism(&Rect::at(0.0, 0.0, 12.0, 12.0).ring(), &[court], 0.0, 2.0),
            2.0 * 128.0,
        );
        let towers = [
            (Rect::at(2.0, 2.0, 3.0, 3.0), 20.0),
            (Rect::at(7.0, 2.0, 2.0, 5.0), 15.0),
        ];
        let want = 500.0 + 9.0 * 15.0 + 10.0 * 10.0;
        check_closed(
            &podium_with_towers(Rect::at(0.0, 0.0, 10.0, 10.0), 0.0, 5.0, &towers),
            want,
        );
        let pillars = [
            Rect::at(1.0, 1.0, 1.0, 1.0),
            Rect::at(8.0, 1.0, 1.0, 1.0),
            Rect::at(4.0, 6.0, 1.0, 1.0),
        ];
        check_closed(
            &slab_on_pillars(Rect::at(0.0, 0.0, 10.0, 8.0), &pillars, -1.0, 4.0, 10.0),
            480.0 + 15.0,
        );
        let house = Rect::at(0.0, 0.0, 10.0, 6.0);
        check_closed(&gable_house(house, 0.0, 5.0, 8.0, true), 300.0 + 90.0);
        check_closed(&gable_house(house, 0.0, 5.0, 8.0, false), 300.0 + 90.0);
    }

    #[test]
    fn icosphere_is_closed() {
        let s = icosphere();
        assert_eq!((s.vertices.len(), s.triangles.len()), (42, 80));
        let mut b = SceneBuilder::new([0.0; 3]);
        let o = b.add("tree", ObjectKind::Vegetation, 0, &s);
        let scene = b.finish();
        assert!(scene.edge_defects(o).is_closed());
        assert!(scene.signed_volume(o) > 3.5);
    }
}
