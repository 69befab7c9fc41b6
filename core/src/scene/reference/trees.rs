//! The reference scene's trees: rows along some facades (trunks 2–5 m from
//! the wall, crowns 4–9 m wide) and free-standing trees in the parks.

use super::buildings::{PARKS, Plan};
use super::terrain::SIZE;
use crate::geom::{ring, segment};
use crate::rng::Rng;

/// One tree: trunk position, trunk height (to the crown's bottom), crown
/// radius and vertical squash of the crown.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreeSpec {
    /// Trunk centre.
    pub xy: [f64; 2],
    /// Height of the crown's bottom above the ground, m.
    pub trunk_h: f64,
    /// Horizontal crown radius, m.
    pub crown_r: f64,
    /// Vertical / horizontal crown radius.
    pub squash: f64,
}

/// Streets (x or y in this band) stay free of trees.
const STREET: (f64, f64) = (93.0, 107.0);

/// The trees of `seed` around the planned buildings.
pub fn plan_trees(seed: u64, buildings: &[Plan]) -> Vec<TreeSpec> {
    let mut r = Rng::new(seed, 0x7433);
    let outlines: Vec<Vec<[f64; 2]>> = buildings.iter().map(Plan::outline).collect();
    let mut trees: Vec<TreeSpec> = Vec::new();
    for outline in &outlines {
        let n = outline.len();
        for k in 0..n {
            let (a, b) = (outline[k], outline[(k + 1) % n]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let len = (dx * dx + dy * dy).sqrt();
            if len < 10.0 || !r.chance(0.25) {
                continue;
            }
            let normal = [dy / len, -dx / len];
            let spacing = r.range(7.0, 10.0);
            let mut t = r.range(3.0, 5.0);
            while t < len - 3.0 {
                let crown_r = r.range(2.0, 4.5);
                let d = (crown_r + r.range(0.3, 0.5)).clamp(2.0, 5.0);
                let xy = [
                    a[0] + dx * t / len + normal[0] * d,
                    a[1] + dy * t / len + normal[1] * d,
                ];
                let tree = TreeSpec {
                    xy,
                    trunk_h: r.range(2.0, 3.5),
                    crown_r,
                    squash: r.range(0.8, 1.1),
                };
                if fits(&tree, &outlines, &trees) {
                    trees.push(tree);
                }
                t += spacing;
            }
        }
    }
    for park in PARKS {
        for _ in 0..6 {
            let crown_r = r.range(2.0, 4.5);
            let tree = TreeSpec {
                xy: [r.range(park.x0, park.x1), r.range(park.y0, park.y1)],
                trunk_h: r.range(2.0, 4.0),
                crown_r,
                squash: r.range(0.8, 1.1),
            };
            if fits(&tree, &outlines, &trees) {
                trees.push(tree);
            }
        }
    }
    trees
}

/// The crown keeps 0.3 m off every building, the tree stays in the scene and
/// off the streets, and trunks keep apart.
fn fits(tree: &TreeSpec, outlines: &[Vec<[f64; 2]>], trees: &[TreeSpec]) -> bool {
    let [x, y] = tree.xy;
    let r = tree.crown_r;
    let in_scene = x - r > 1.0 && y - r > 1.0 && x + r < SIZE - 1.0 && y + r < SIZE - 1.0;
    let on_street = |v: f64| v > STREET.0 && v < STREET.1;
    if !in_scene || on_street(x) || on_street(y) {
        return false;
    }
    let clear = outlines
        .iter()
        .all(|o| !ring::contains(o, tree.xy) && segment::ring_distance(tree.xy, o) >= r + 0.3);
    let apart = trees.iter().all(|t| {
        let (dx, dy) = (t.xy[0] - x, t.xy[1] - y);
        (dx * dx + dy * dy).sqrt() >= t.crown_r.max(r)
    });
    clear && apart
}
