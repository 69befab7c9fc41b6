//! Closest-hit traversal of the 4-wide hierarchy.

use super::lanes::F4;
use super::{Bvh, Node, WIDTH, far_first};
use crate::lidar::triangle::{PreparedRay, intersect, intersect_any};

/// Far-plane factor making the slab test conservative under rounding
/// (1 + 2γ₃, Ize 2013): a ray grazing a box face is never wrongly culled.
pub(super) const FAR_SCALE: f32 = 1.0 + 4.0 * f32::EPSILON;

/// Stack entries kept inline; deeper stacks (only pathological trees: each
/// level pushes at most `WIDTH - 1` entries and real trees are ~15 levels
/// deep) spill to the heap.
const STACK: usize = 32;

/// Entry distances of the ray into the child boxes of `n` and the mask of
/// children it enters before `t_max`.
#[inline(always)]
fn enter(n: &Node, r: &PreparedRay, t_max: f32) -> ([f32; WIDTH], u32) {
    let [sx, sy, sz] = r.sign;
    let b = &n.bounds;
    let o = r.org.map(F4::splat);
    let inv = r.inv.map(F4::splat);
    let slab = |axis: usize, side: usize| F4::load(&b[axis][side]).sub(o[axis]).mul(inv[axis]);
    let t0 = slab(0, sx)
        .max(slab(1, sy))
        .max(slab(2, sz).max(F4::splat(0.0)));
    let far = F4::splat(FAR_SCALE);
    let t1 = slab(0, 1 - sx)
        .min(slab(1, 1 - sy))
        .min(slab(2, 1 - sz))
        .mul(far)
        .min(F4::splat(t_max));
    (t0.to_array(), t0.le_mask(t1))
}

impl Bvh {
    /// The closest hit in `(0, t_max)`: `(t, leaf-order triangle index)`.
    pub fn closest(&self, r: &PreparedRay, t_max: f32) -> Option<(f32, usize)> {
        match r.perm {
            0 => self.closest_in::<1, 2, 0>(r, t_max),
            1 => self.closest_in::<2, 1, 0>(r, t_max),
            2 => self.closest_in::<2, 0, 1>(r, t_max),
            3 => self.closest_in::<0, 2, 1>(r, t_max),
            4 => self.closest_in::<0, 1, 2>(r, t_max),
            _ => self.closest_in::<1, 0, 2>(r, t_max),
        }
    }

    /// [`Bvh::closest`] for rays of permutation `(KX, KY, KZ)`.
    fn closest_in<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        r: &PreparedRay,
        t_max: f32,
    ) -> Option<(f32, usize)> {
        if self.nodes.is_empty() {
            return None;
        }
        let mut stack = [(0u32, 0f32); STACK];
        let mut spill: Vec<(u32, f32)> = Vec::new();
        let mut sp = 0usize;
        let mut best_t = t_max;
        let mut best = None;
        let mut node = 0usize;
        loop {
            #[cfg(test)]
            stats::NODES.with(|c| c.set(c.get() + 1));
            let n = &self.nodes[node];
            let (t, hit) = enter(n, r, best_t);
            // Leaves first: they may shorten best_t.
            let mut leaves = hit & u32::from(n.leaves);
            while leaves != 0 {
                let c = leaves.trailing_zeros() as usize;
                leaves &= leaves - 1;
                let start = n.child[c] as usize;
                let end = start + n.count[c] as usize;
                for (i, tri) in self.tris[start..end].iter().enumerate() {
                    #[cfg(test)]
                    stats::TRIS.with(|c| c.set(c.get() + 1));
                    if let Some(th) = intersect::<KX, KY, KZ>(r, tri, best_t) {
                        best_t = th;
                        best = Some(start + i);
                    }
                }
            }
            let mut inner = hit & !u32::from(n.leaves);
            let next = if inner == 0 {
                None
            } else if inner & (inner - 1) == 0 {
                // One child: no ordering needed.
                let c = inner.trailing_zeros() as usize;
                (t[c] < best_t).then_some(n.child[c])
            } else {
                // Several: push far to near, descend into the nearest.
                let mut kids = [(0u32, f32::INFINITY); WIDTH];
                let mut k = 0;
                while inner != 0 {
                    let c = inner.trailing_zeros() as usize;
                    inner &= inner - 1;
                    if t[c] < best_t {
                        kids[k] = (n.child[c], t[c]);
                        k += 1;
                    }
                }
                let kids = &mut kids[..k];
                far_first(kids, |c| c.1);
                let (&nearest, farther) = match kids.split_last() {
                    Some(split) => split,
                    None => (&(0, 0.0), &[][..]),
                };
                for &entry in farther {
                    match stack.get_mut(sp) {
                        Some(slot) => *slot = entry,
                        None => spill.push(entry),
                    }
                    sp += 1;
                }
                (k > 0).then_some(nearest.0)
            };
            node = match next {
                Some(nx) => nx as usize,
                None => loop {
                    if sp == 0 {
                        return best.map(|i| (best_t, i));
                    }
                    sp -= 1;
                    let (nx, tn) = match stack.get(sp) {
                        Some(&entry) => entry,
                        None => spill.pop().unwrap_or((0, f32::INFINITY)),
                    };
                    if tn < best_t {
                        break nx as usize;
                    }
                },
            };
        }
    }

    /// The closest hit by testing every one of `tris` (reference for tests).
    pub fn closest_among(
        tris: &[[[f32; 3]; 3]],
        r: &PreparedRay,
        t_max: f32,
    ) -> Option<(f32, usize)> {
        let mut best_t = t_max;
        let mut best = None;
        for (i, tri) in tris.iter().enumerate() {
            if let Some(th) = intersect_any(r, tri, best_t) {
                best_t = th;
                best = Some(i);
            }
        }
        best.map(|i| (best_t, i))
    }
}

#[cfg(test)]
pub(crate) mod stats {
    use std::cell::Cell;
    thread_local! {
        pub static NODES: Cell<u64> = const { Cell::new(0) };
        pub static TRIS: Cell<u64> = const { Cell::new(0) };
        pub static PACKET_NODES: Cell<u64> = const { Cell::new(0) };
        pub static QUADS: Cell<u64> = const { Cell::new(0) };
        pub static PACKET_TRIS: Cell<u64> = const { Cell::new(0) };
    }
}
