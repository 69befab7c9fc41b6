//! Partition nodes where the roof parts around alternate in height (high,
//! low, high, low): every wall between two neighbours there spans the
//! heights between the low and the high parts, so the vertical edge at the
//! node is used by four walls or more, and the solid is not a 2-manifold
//! (val3dity's 303). Two high parts touching at one corner make such a
//! node; smaller roof parts make them often.
//!
//! The node is split in two a centimetre or two apart, joined by a short
//! new boundary: one part's corner moves off the node (it loses a sliver
//! of a few cm²) and the two parts beside it meet along the new boundary,
//! with a wall of its own. Each node then has three parts or alternates no
//! more, and the edges at it are used twice. The outline is never moved:
//! only nodes whose split leaves the outside's boundary as it is are split.

use super::partition::{Chain, Partition};
use super::solid::Levels;

/// How far (m) the split-off corner moves at most: far above val3dity's
/// 1 mm snapping (so the two nodes stay two vertices), far below the
/// roof's accuracy.
const SPLIT_M: f64 = 0.02;

/// A split shorter than this (m) would be welded back into the node.
const MIN_SPLIT_M: f64 = 0.005;

/// One chain end at a node, seen from the node.
#[derive(Debug, Clone, Copy)]
struct Dart {
    /// The chain.
    chain: usize,
    /// The node is the chain's first vertex (else its last).
    start: bool,
    /// Direction of the chain's first segment from the node (rad).
    angle: f64,
    /// Length of that segment (m).
    len: f64,
    /// Region on the left looking out along the chain from the node.
    left: u32,
}

/// Splits every node of `p` where the parts around alternate in height
/// (by the merged levels the shell is built on), so the shell
/// [`super::solid::build_shell`] makes is manifold there; returns the
/// number of splits.
pub(crate) fn split_saddles(p: &mut Partition, height: &dyn Fn(u32, [f64; 2]) -> f64) -> usize {
    let mut splits = 0;
    // Each split leaves its node one part fewer, and the new node has
    // three: a node of k parts takes at most k - 3 splits.
    let guard = 4 * p.verts.len() + 16;
    while splits < guard {
        let lv = Levels::new(p, height);
        let Some((node, darts, j)) = next_saddle(p, &lv) else {
            break;
        };
        split_node(p, node, &darts, j);
        splits += 1;
    }
    splits
}

/// The first node that alternates and can be split, its darts in
/// counter-clockwise order and which sector to move off it.
fn next_saddle(p: &Partition, lv: &Levels) -> Option<(u32, Vec<Dart>, usize)> {
    let mut nodes: Vec<(u32, Vec<Dart>)> = darts_by_node(p).into_iter().collect();
    nodes.sort_unstable_by_key(|n| n.0);
    nodes.into_iter().find_map(|(node, darts)| {
        if darts.len() < 4 {
            return None;
        }
        let levels: Vec<usize> = darts.iter().map(|d| lv.of(node, d.left)).collect();
        if max_crossings(&levels) <= 2 {
            return None;
        }
        let j = choose_sector(node, &darts, &levels, lv)?;
        Some((node, darts, j))
    })
}

/// Chain ends at each vertex where chains end, counter-clockwise.
fn darts_by_node(p: &Partition) -> std::collections::HashMap<u32, Vec<Dart>> {
    let mut out: std::collections::HashMap<u32, Vec<Dart>> = Default::default();
    for (k, c) in p.chains.iter().enumerate() {
        let n = c.verts.len();
        if n < 2 {
            continue;
        }
        for start in [true, false] {
            let (node, next, left) = if start {
                (c.verts[0], c.verts[1], c.left)
            } else {
                (c.verts[n - 1], c.verts[n - 2], c.right)
            };
            let (a, b) = (p.verts[node as usize], p.verts[next as usize]);
            let d = [b[0] - a[0], b[1] - a[1]];
            out.entry(node).or_default().push(Dart {
                chain: k,
                start,
                angle: d[1].atan2(d[0]),
                len: d[0].hypot(d[1]),
                left,
            });
        }
    }
    for darts in out.values_mut() {
        darts.sort_by(|a, b| a.angle.total_cmp(&b.angle));
    }
    out
}

/// The most times any interval between two levels is spanned by the walls
/// between cyclically consecutive sectors (2 where the node is manifold).
fn max_crossings(levels: &[usize]) -> usize {
    let k = levels.len();
    let top = levels.iter().copied().max().unwrap_or(0);
    (0..top)
        .map(|t| {
            (0..k)
                .filter(|&j| {
                    let (a, b) = (levels[j], levels[(j + 1) % k]);
                    a.min(b) <= t && a.max(b) > t
                })
                .count()
        })
        .max()
        .unwrap_or(0)
}

/// The sector whose corner moves off the node: none of it and its two
/// neighbours the outside (the outline stays), its corner's two chains
/// long enough, and of those, the one leaving the node manifold with the
/// lowest new wall (the two neighbours closest in height at the node).
fn choose_sector(node: u32, darts: &[Dart], levels: &[usize], lv: &Levels) -> Option<usize> {
    let k = darts.len();
    let sector = |j: usize| darts[j % k].left;
    (0..k)
        .filter(|&j| {
            [sector(j + k - 1), sector(j), sector(j + 1)]
                .iter()
                .all(|&r| r != 0)
        })
        .filter(|&j| split_length(darts[j], darts[(j + 1) % k]) >= MIN_SPLIT_M)
        .min_by_key(|&j| {
            let rest: Vec<usize> = (0..k).filter(|&i| i != j).map(|i| levels[i]).collect();
            let (a, b) = (sector(j + k - 1), sector(j + 1));
            let step = lv.height(node, a) - lv.height(node, b);
            // Millimetres, as an integer key.
            (max_crossings(&rest), (step.abs() * 1e3) as i64)
        })
}

/// How far the corner between darts `a` and `b` (counter-clockwise) moves.
fn split_length(a: Dart, b: Dart) -> f64 {
    SPLIT_M.min(0.3 * a.len.min(b.len))
}

/// Cuts the corner of sector `j` (between darts `j` and `j + 1`) off
/// `node`: its two chains now start a split length out along their first
/// segments, both from a new vertex on the sector's bisector, which a new
/// chain joins to the node between the two sectors beside it. The sector
/// loses a triangle of a few cm² to them; the chains keep their lines.
fn split_node(p: &mut Partition, node: u32, darts: &[Dart], j: usize) {
    let k = darts.len();
    let (a, b) = (darts[j], darts[(j + 1) % k]);
    let mut width = b.angle - a.angle;
    if width <= 0.0 {
        width += std::f64::consts::TAU;
    }
    let mid = a.angle + 0.5 * width;
    let len = split_length(a, b);
    let o = p.verts[node as usize];
    let at = |angle: f64, r: f64| [o[0] + r * angle.cos(), o[1] + r * angle.sin()];
    p.verts.push(at(mid, 0.5 * len));
    let corner = (p.verts.len() - 1) as u32;
    for d in [a, b] {
        p.verts.push(at(d.angle, len));
        let on_chain = (p.verts.len() - 1) as u32;
        let verts = &mut p.chains[d.chain].verts;
        if d.start {
            verts[0] = corner;
            verts.insert(1, on_chain);
        } else {
            let n = verts.len();
            verts[n - 1] = corner;
            verts.insert(n - 1, on_chain);
        }
    }
    let (before, after) = (darts[(j + k - 1) % k].left, b.left);
    // The same region on both sides is no boundary: it now runs between
    // the node and the cut corner.
    if before != after {
        p.chains.push(Chain {
            verts: vec![node, corner],
            left: after,
            right: before,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::super::partition::block_partition;
    use super::super::solid::{build_shell, outline};
    use super::*;

    /// A 10 × 8 m block on a 1 m grid in four quadrants, two high roofs
    /// touching at the centre corner (6, 5) and two low ones between them.
    fn quadrants() -> (Partition, impl Fn(u32, [f64; 2]) -> f64) {
        let (p, code) = block_partition(|i, j| match (i < 6, j < 5) {
            (true, true) => 1,
            (false, true) => 2,
            (false, false) => 3,
            (true, false) => 4,
        });
        let h = move |r: u32, _: [f64; 2]| match r {
            0 => 0.0,
            r => [8.0, 5.0, 8.3, 5.2][code[r as usize - 1] as usize - 1],
        };
        (p, h)
    }

    #[test]
    fn two_high_roofs_touching_at_a_corner_give_a_manifold_solid() {
        let (mut p, h) = quadrants();
        let before = build_shell(&p, &h);
        assert!(
            before.check().non_manifold_edges > 0,
            "{:?}",
            before.check()
        );
        assert!(super::super::validity_codes(&before).contains(&303));
        assert_eq!(split_saddles(&mut p, &h), 1);
        let after = build_shell(&p, &h);
        assert!(after.check().valid(), "{:?}", after.check());
        assert_eq!(super::super::validity_codes(&after), Vec::<u16>::new());
        // The outline stays; the volume moves by the split's sliver only
        // (a few cm² at most 3.3 m high).
        assert!((geo::Area::unsigned_area(&outline(&p)) - 80.0).abs() < 1e-9);
        let exact = 20.0 * (8.0 + 5.0 + 8.3 + 5.2);
        assert!((after.volume() - exact).abs() < 0.01, "{}", after.volume());
        // A node where the heights do not alternate is left alone.
        let (mut q, _) = quadrants();
        let steps = |r: u32, _: [f64; 2]| f64::from(r);
        assert_eq!(split_saddles(&mut q, &steps), 0);
    }
}
