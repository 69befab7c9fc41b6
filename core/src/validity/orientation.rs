//! Which way a shell's surfaces turn (307): against each other along shared
//! edges, and as a whole by the sign of the enclosed volume.

use super::plane::newell;
use super::surface::{Edges, Face};
use crate::scene::vec3::{dot, sub};
use std::collections::VecDeque;

/// Faces turned against their neighbours: across each shared edge the two
/// faces must run it in opposite directions. Turning is propagated over the
/// manifold edges and the smaller side of each group is to blame (a face
/// that cannot agree with all neighbours is blamed too).
pub(super) fn misturned(n: usize, edges: &Edges) -> Vec<usize> {
    let mut next: Vec<Vec<(usize, bool)>> = vec![Vec::new(); n];
    for uses in edges.values() {
        if let [(f, df), (g, dg)] = uses[..]
            && f != g
        {
            // Opposite directions agree; the same direction means one of the two is flipped.
            let agree = df != dg;
            next[f].push((g, agree));
            next[g].push((f, agree));
        }
    }
    let mut flipped: Vec<Option<bool>> = vec![None; n];
    let mut blamed = Vec::new();
    for root in 0..n {
        if flipped[root].is_some() {
            continue;
        }
        flipped[root] = Some(false);
        let mut group = vec![root];
        let mut queue = VecDeque::from([root]);
        while let Some(f) = queue.pop_front() {
            let mine = flipped[f].unwrap_or(false);
            for &(g, agree) in &next[f] {
                let want = mine ^ !agree;
                match flipped[g] {
                    None => {
                        flipped[g] = Some(want);
                        group.push(g);
                        queue.push_back(g);
                    }
                    Some(have) if have != want => blamed.push(g),
                    Some(_) => {}
                }
            }
        }
        let turned = group.iter().filter(|&&f| flipped[f] == Some(true)).count();
        // The root's side is kept on a tie: nothing tells which half is right.
        let blame_turned = turned * 2 <= group.len();
        blamed.extend(
            group
                .iter()
                .filter(|&&f| flipped[f] == Some(blame_turned))
                .copied(),
        );
    }
    blamed.sort_unstable();
    blamed.dedup();
    blamed
}

/// The volume the faces enclose, positive when their normals point out.
pub(super) fn signed_volume(vertices: &[[f64; 3]], faces: &[Face]) -> f64 {
    // Relative to one vertex of the shell: map coordinates would cancel the small volume away.
    let Some(&origin) = faces
        .first()
        .and_then(|f| f.rings.first())
        .and_then(|r| r.first())
        .and_then(|&i| vertices.get(i))
    else {
        return 0.0;
    };
    let mut six_v = 0.0;
    for ring in faces.iter().flat_map(|f| &f.rings) {
        let pts: Vec<[f64; 3]> = ring.iter().map(|&i| sub(vertices[i], origin)).collect();
        if let Some(&p0) = pts.first() {
            // A planar ring's cone from the origin: a third of (area vector · any point).
            six_v += dot(newell(&pts), p0);
        }
    }
    six_v / 6.0
}
