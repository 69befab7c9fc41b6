//! Closest-hit traversal of a packet of rays that share one origin (a
//! spinning sensor's block of columns).
//!
//! The packet walks the tree once: each node is fetched, ordered and stacked
//! once for all its active rays, and its child boxes are tested four rays at
//! a time (the boxes relative to the shared origin are computed once per
//! node, a triangle's relative vertices once per leaf visit). Each ray keeps
//! its own closest distance, and every box and triangle test is the same
//! arithmetic as the single-ray path, so the hits are the same.

use super::build::MAX_LEAF;
use super::lanes::F4;
use super::traverse::FAR_SCALE;
use super::{Bvh, Node, WIDTH, far_first};
use crate::lidar::triangle::{PreparedRay, by_perm, intersect_rel, relative};

/// Most rays in one packet (bits of the active mask).
pub(crate) const PACKET: usize = 64;
/// Groups of four rays in a full packet.
const QUADS: usize = PACKET / 4;
/// Stack entries kept inline (see `traverse::STACK`).
const STACK: usize = 32;

/// A packet's rays laid out for four-wide box tests.
struct Lanes {
    /// `inv[axis][ray]`; padding rays hold 1.
    inv: [[f32; PACKET]; 3],
    /// Each ray's closest hit so far (its range before the first hit);
    /// padding rays hold −∞, so they enter no box.
    best_t: [f32; PACKET],
    /// Smallest and largest `inv` per axis over the packet's rays.
    inv_lo: [f32; 3],
    inv_hi: [f32; 3],
    /// Largest `best_t` of the active rays (an upper bound).
    best_hi: f32,
}

impl Lanes {
    /// The rays of `mask` whose closest hit is farther than `t`.
    #[inline(always)]
    fn farther_than(&self, t: f32, mask: u64) -> u64 {
        let tv = F4::splat(t);
        let mut out = 0u64;
        for q in 0..QUADS {
            if (mask >> (4 * q)) & 0xF != 0 {
                let b = F4::load(quad(&self.best_t, q));
                out |= u64::from(tv.lt(b).mask()) << (4 * q);
            }
        }
        out & mask
    }
}

/// Triangles whose relative vertices are kept at once (the build's
/// largest leaf).
const LEAF: usize = MAX_LEAF;

/// The closest of the triangles `rel` (relative to the ray's origin) that
/// `ray` hits within `t_max`: `(t, index into rel)`. Dispatches on the ray's
/// permutation once for the whole leaf.
#[inline(always)]
fn closest_in(ray: &PreparedRay, rel: &[[[f32; 3]; 3]], t_max: f32) -> Option<(f32, usize)> {
    by_perm!(ray.perm, closest_in_perm(ray, rel, t_max))
}

/// [`closest_in`] for rays of permutation `(KX, KY, KZ)`.
#[inline(always)]
fn closest_in_perm<const KX: usize, const KY: usize, const KZ: usize>(
    ray: &PreparedRay,
    rel: &[[[f32; 3]; 3]],
    t_max: f32,
) -> Option<(f32, usize)> {
    let mut best = None;
    let mut t_max = t_max;
    for (k, r) in rel.iter().enumerate() {
        if let Some(t) = intersect_rel::<KX, KY, KZ>(ray, r, t_max) {
            t_max = t;
            best = Some((t, k));
        }
    }
    best
}

/// Lanes `4q .. 4q + 4` of `a`.
#[inline(always)]
fn quad(a: &[f32; PACKET], q: usize) -> &[f32; 4] {
    let s = &a[4 * q..4 * q + 4];
    // A slice of four f32 always converts; the fallback is never taken.
    s.try_into().unwrap_or(&[0.0; 4])
}

/// The children of `n` that some ray of the packet may enter: interval
/// arithmetic over the packet's ranges of `1 / d` (rounding is monotonic, so
/// the bounds hold for every ray's own products and no entered box is
/// culled).
#[inline(always)]
fn frustum(n: &Node, org: [f32; 3], l: &Lanes) -> u32 {
    let b = &n.bounds;
    let slab = |k: usize| {
        let o = F4::splat(org[k]);
        let (lo, hi) = (F4::load(&b[k][0]).sub(o), F4::load(&b[k][1]).sub(o));
        let (a, z) = (F4::splat(l.inv_lo[k]), F4::splat(l.inv_hi[k]));
        let (p, q, r, s) = (lo.mul(a), lo.mul(z), hi.mul(a), hi.mul(z));
        (p.min(q).min(r.min(s)), p.max(q).max(r.max(s)))
    };
    let (n0, f0) = slab(0);
    let (n1, f1) = slab(1);
    let (n2, f2) = slab(2);
    let t0 = n0.max(n1).max(n2.max(F4::splat(0.0)));
    let t1 = f0
        .min(f1)
        .min(f2)
        .mul(F4::splat(FAR_SCALE))
        .min(F4::splat(l.best_hi));
    t0.le_mask(t1)
}

/// For each child of `n`: the rays of `mask` that enter its box before their
/// closest hit so far, and the smallest entry distance among the rays
/// tested.
#[inline(always)]
fn enter(n: &Node, org: [f32; 3], l: &Lanes, mask: u64) -> ([u64; WIDTH], [f32; WIDTH]) {
    let mut hits = [0u64; WIDTH];
    let mut near = [f32::INFINITY; WIDTH];
    let zero = F4::splat(0.0);
    let far_scale = F4::splat(FAR_SCALE);
    let inf = F4::splat(f32::INFINITY);
    let b = &n.bounds;
    // Empty slots have inverted boxes, which the sign-free test below
    // would enter.
    let valid = F4::load(&b[0][0]).le_mask(F4::load(&b[0][1]));
    let mut todo = frustum(n, org, l) & valid;
    while todo != 0 {
        let c = todo.trailing_zeros() as usize;
        todo &= todo - 1;
        // Same rounding as the single-ray test: (bound - origin) · (1 / d).
        let lo = [0, 1, 2].map(|k| F4::splat(b[k][0][c] - org[k]));
        let hi = [0, 1, 2].map(|k| F4::splat(b[k][1][c] - org[k]));
        let mut tmin = inf;
        let mut bits = 0u64;
        for q in 0..QUADS {
            let active = ((mask >> (4 * q)) & 0xF) as u32;
            if active == 0 {
                continue;
            }
            #[cfg(test)]
            super::stats::QUADS.with(|c| c.set(c.get() + 1));
            let slab = |k: usize| {
                let inv = F4::load(quad(&l.inv[k], q));
                let (a, b) = (lo[k].mul(inv), hi[k].mul(inv));
                (a.min(b), a.max(b))
            };
            let (n0, f0) = slab(0);
            let (n1, f1) = slab(1);
            let (n2, f2) = slab(2);
            let t0 = n0.max(n1).max(n2.max(zero));
            let t1 = f0
                .min(f1)
                .min(f2)
                .mul(far_scale)
                .min(F4::load(quad(&l.best_t, q)));
            let inside = t0.le(t1);
            bits |= u64::from(inside.mask() & active) << (4 * q);
            // Inactive rays may lower the bound: it only has to be ≤ the
            // active rays' entries.
            tmin = tmin.min(inside.select(t0, inf));
        }
        hits[c] = bits;
        near[c] = tmin
            .to_array()
            .into_iter()
            .fold(f32::INFINITY, |m, x| if x < m { x } else { m });
    }
    (hits, near)
}

impl Bvh {
    /// The closest hit in `(0, t_max[i])` of each ray `rays[i]`, all from
    /// `org`, written to `out[i]` as `(t, leaf-order triangle index)`.
    /// At most [`PACKET`] rays; rays with `t_max ≤ 0` hit nothing.
    pub fn closest_packet(
        &self,
        org: [f32; 3],
        rays: &[PreparedRay],
        t_max: &[f32],
        out: &mut [Option<(f32, usize)>],
    ) {
        let n = rays.len().min(PACKET).min(t_max.len()).min(out.len());
        out.iter_mut().for_each(|o| *o = None);
        if self.nodes.is_empty() || n == 0 {
            return;
        }
        let mut l = Lanes {
            inv: [[1.0; PACKET]; 3],
            best_t: [f32::NEG_INFINITY; PACKET],
            inv_lo: [f32::INFINITY; 3],
            inv_hi: [f32::NEG_INFINITY; 3],
            best_hi: f32::NEG_INFINITY,
        };
        let mut mask = 0u64;
        for i in 0..n {
            if t_max[i] > 0.0 {
                for k in 0..3 {
                    let inv = rays[i].inv[k];
                    l.inv[k][i] = inv;
                    l.inv_lo[k] = l.inv_lo[k].min(inv);
                    l.inv_hi[k] = l.inv_hi[k].max(inv);
                }
                l.best_t[i] = t_max[i];
                l.best_hi = l.best_hi.max(t_max[i]);
                mask |= 1 << i;
            }
        }
        let mut best = [usize::MAX; PACKET];
        let mut stack = [(0u32, 0u64, 0f32); STACK];
        let mut spill: Vec<(u32, u64, f32)> = Vec::new();
        let mut sp = 0usize;
        let mut node = 0usize;
        while mask != 0 {
            let nd = &self.nodes[node];
            #[cfg(test)]
            super::stats::PACKET_NODES.with(|c| c.set(c.get() + 1));
            let (hits, near) = enter(nd, org, &l, mask);
            // Leaves first: they may shorten the rays' closest distances.
            let mut shortened = false;
            for (c, &entered) in hits.iter().enumerate() {
                if nd.leaves & (1 << c) == 0 || entered == 0 {
                    continue;
                }
                let start = nd.child[c] as usize;
                let end = start + nd.count[c] as usize;
                // The leaf's vertices relative to the shared origin, once.
                for (g, group) in self.tris[start..end].chunks(LEAF).enumerate() {
                    let mut rel = [[[0.0f32; 3]; 3]; LEAF];
                    for (r, tri) in rel.iter_mut().zip(group) {
                        *r = relative(tri, org);
                    }
                    let rel = &rel[..group.len()];
                    let mut m = entered;
                    while m != 0 {
                        let i = m.trailing_zeros() as usize;
                        m &= m - 1;
                        #[cfg(test)]
                        super::stats::PACKET_TRIS.with(|c| c.set(c.get() + rel.len() as u64));
                        if let Some((th, k)) = closest_in(&rays[i], rel, l.best_t[i]) {
                            l.best_t[i] = th;
                            best[i] = start + g * LEAF + k;
                            shortened = true;
                        }
                    }
                }
            }
            if shortened {
                l.best_hi = l.best_t.iter().fold(f32::NEG_INFINITY, |m, &t| m.max(t));
            }
            // Inner children entered by some ray, far to near.
            let mut kids = [(0u32, 0u64, f32::INFINITY); WIDTH];
            let mut k = 0;
            for c in 0..WIDTH {
                if nd.leaves & (1 << c) == 0 && hits[c] != 0 {
                    kids[k] = (nd.child[c], hits[c], near[c]);
                    k += 1;
                }
            }
            let kids = &mut kids[..k];
            far_first(kids, |c| c.2);
            for &entry in kids.iter() {
                match stack.get_mut(sp) {
                    Some(slot) => *slot = entry,
                    None => spill.push(entry),
                }
                sp += 1;
            }
            // Pop the nearest entry that still has rays whose closest hit
            // lies beyond it.
            mask = 0;
            while sp > 0 {
                sp -= 1;
                let (nx, m, t) = match stack.get(sp) {
                    Some(&entry) => entry,
                    None => spill.pop().unwrap_or((0, 0, f32::INFINITY)),
                };
                let m = l.farther_than(t, m);
                if m != 0 {
                    node = nx as usize;
                    mask = m;
                    break;
                }
            }
        }
        for i in 0..n {
            if best[i] != usize::MAX {
                out[i] = Some((l.best_t[i], best[i]));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use crate::lidar::spinning::{LidarConfig, cast_revolution, revolution_rays};
    use crate::lidar::synthetic::{SyntheticBuilder, boxes_on_plane};
    use crate::lidar::{Caster, Hit, Pose, Ray};
    use crate::scene::ObjectKind;

    /// Packet results against ray-by-ray ones: the same misses, the same
    /// distances (1e-6 m) and, unless two triangles tie, the same triangle.
    fn assert_same(caster: &Caster, rays: &[Ray], packets: &[Option<Hit>]) {
        assert_eq!(packets.len(), rays.len());
        for (i, (r, p)) in rays.iter().zip(packets).enumerate() {
            let single = caster.cast_ray(r);
            match (single, p) {
                (None, None) => {}
                (Some(s), Some(p)) => {
                    assert!((s.t - p.t).abs() <= 1e-6, "ray {i}: {} vs {}", s.t, p.t);
                    assert!(s.triangle == p.triangle || s.t == p.t, "ray {i}: triangles");
                }
                _ => panic!("ray {i} {r:?}: single {single:?}, packet {p:?}"),
            }
        }
    }

    /// Unit direction at azimuth `az` and elevation `el` (radians).
    fn dir(az: f32, el: f32) -> [f32; 3] {
        [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()]
    }

    #[test]
    fn column_straddling_shared_edges_hits_like_single_rays() {
        // A wall at y = 5 tessellated in 0.5 m cells: many triangles in
        // many leaves, edges at x = 0, 0.5, 1, …
        let mut b = SyntheticBuilder::new();
        let wall = b.object("wall", ObjectKind::Building);
        b.add_box(wall, [-20.0, 5.0, -10.0], [20.0, 5.5, 10.0], 0.5);
        let caster = Caster::new(&b.finish()).unwrap();
        // Columns aimed at the vertical edge x = 1 (and a hair either side),
        // 64 beams each over ±60°: every ray must hit the closed wall.
        let org = [0.0, 0.0, 0.3];
        let edge = (5.0f32).atan2(1.0);
        let mut rays = Vec::new();
        for daz in [-1e-6f32, 0.0, 1e-6] {
            for k in 0..64 {
                let el = (-60.0 + 120.0 * k as f32 / 63.0).to_radians();
                rays.push(Ray::new(org, dir(edge + daz, el), 50.0));
            }
        }
        let packets = caster.cast_many(&rays);
        assert!(packets.iter().all(Option::is_some), "a ray leaked");
        for (r, h) in rays.iter().zip(&packets) {
            // The wall's near face, y = 5: t = 5 / d_y.
            let t = h.map_or(0.0, |h| h.t);
            assert!((t - 5.0 / r.dir[1]).abs() < 1e-3, "{t} along {:?}", r.dir);
        }
        assert_same(&caster, &rays, &packets);
    }

    #[test]
    fn revolution_matches_single_rays_for_any_block_fit() {
        let scene = boxes_on_plane(
            60.0,
            &[
                ([5.0, -4.0, 0.0], [12.0, 4.0, 9.0]),
                ([-20.0, 10.0, 0.0], [-8.0, 30.0, 15.0]),
                ([-3.0, -25.0, 0.0], [3.0, -18.0, 4.0]),
            ],
        );
        let caster = Caster::new(&scene).unwrap();
        // VLP-16 (blocks fit exactly), and 5 beams every 0.7° (they do not).
        let odd = LidarConfig {
            beams: 5,
            azimuth_step_deg: 0.7,
            ..LidarConfig::default()
        };
        for config in [LidarConfig::default(), odd] {
            let pose = Pose::new([1.0, 2.0, 1.8], 0.4);
            let rays = revolution_rays(&config, &pose);
            let packets = cast_revolution(&caster, &config, &rays);
            let hits = packets.iter().flatten().count();
            // Below the horizon every beam meets the ground or a box.
            assert!(hits > rays.len() / 2, "{hits} of {}", rays.len());
            assert_same(&caster, &rays, &packets);
        }
    }

    /// A random triangle soup in [-10, 10]³.
    fn soup() -> impl Strategy<Value = Vec<[[f32; 3]; 3]>> {
        prop::collection::vec(
            prop::array::uniform3(prop::array::uniform3(-10.0f32..10.0)),
            1..120,
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Fans of rays from one origin (packets) hit what they hit one by
        /// one, on random scenes, origins, spreads and ranges.
        #[test]
        fn packets_match_single_rays(
            tris in soup(),
            boxes in prop::collection::vec((prop::array::uniform3(-8.0f32..8.0), prop::array::uniform3(0.1f32..4.0)), 0..4),
            org in prop::array::uniform3(-12.0f32..12.0),
            az0 in -3.2f32..3.2,
            el0 in -1.5f32..1.5,
            spread in 0.0f32..3.2,
            n in 1usize..200,
            ranges in prop::collection::vec(0.0f32..40.0, 1..8),
        ) {
            let mut b = SyntheticBuilder::new();
            let o = b.object("soup", ObjectKind::Building);
            for t in tris {
                b.triangle(o, t);
            }
            for (lo, size) in boxes {
                b.add_box(o, lo, std::array::from_fn(|k| lo[k] + size[k]), 1.0);
            }
            let caster = Caster::new(&b.finish()).unwrap();
            let side = (n as f32).sqrt().ceil() as usize;
            let rays: Vec<Ray> = (0..n)
                .map(|i| {
                    let (u, v) = ((i % side) as f32 / side as f32, (i / side) as f32 / side as f32);
                    let d = dir(az0 + spread * (u - 0.5), el0 + 0.5 * spread * (v - 0.5));
                    // Some rays with no direction: they hit nothing either way.
                    let d = if i % 37 == 36 { [0.0; 3] } else { d };
                    Ray::new(org, d, ranges[i % ranges.len()])
                })
                .collect();
            let packets = caster.cast_many(&rays);
            assert_same(&caster, &rays, &packets);
        }
    }
}
