//! Pruning: leaf branches shorter than a length are boundary noise of the
//! triangulation (every small contour bump grows one), not structure.

use super::graph::Skeleton;

/// Removes leaf branches (leaf up to the first junction) shorter than
/// `min_branch`, twice so spurs exposed by the first pass go too, then drops
/// unused nodes. A skeleton that is one branch is kept whole.
pub fn prune_spurs(skeleton: Skeleton, min_branch: f64) -> Skeleton {
    let Skeleton { nodes, mut edges } = skeleton;
    for _ in 0..2 {
        let mut adj: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
        for (k, &[a, b]) in edges.iter().enumerate() {
            adj[a].push(k);
            adj[b].push(k);
        }
        let mut drop = vec![false; edges.len()];
        for leaf in 0..nodes.len() {
            if adj[leaf].len() != 1 {
                continue;
            }
            let mut path = Vec::new();
            let (mut at, mut via) = (leaf, adj[leaf][0]);
            let mut length = 0.0;
            let reached_junction = loop {
                path.push(via);
                let [a, b] = edges[via];
                let next = if a == at { b } else { a };
                let (p, q) = (nodes[at], nodes[next]);
                length += ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
                at = next;
                if adj[at].len() != 2 || length >= min_branch {
                    break adj[at].len() >= 3;
                }
                via = if adj[at][0] == via {
                    adj[at][1]
                } else {
                    adj[at][0]
                };
            };
            if reached_junction && length < min_branch {
                path.iter().for_each(|&e| drop[e] = true);
            }
        }
        let mut k = 0;
        edges.retain(|_| {
            k += 1;
            !drop[k - 1]
        });
    }
    let mut new_index = vec![usize::MAX; nodes.len()];
    let mut kept = Vec::new();
    for e in &mut edges {
        for v in e.iter_mut() {
            if new_index[*v] == usize::MAX {
                new_index[*v] = kept.len();
                kept.push(nodes[*v]);
            }
            *v = new_index[*v];
        }
    }
    if edges.is_empty() {
        // No edges left (one triangle, or a tiny outline): keep the nodes so
        // callers still have an interior point.
        return Skeleton { nodes, edges };
    }
    Skeleton { nodes: kept, edges }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_spur_goes_long_branches_stay() {
        // a long line 0-1-2-3 with a 0.5 m spur at node 1 and a 5 m branch at node 2
        let sk = Skeleton {
            nodes: vec![
                [0.0, 0.0],
                [10.0, 0.0],
                [20.0, 0.0],
                [30.0, 0.0],
                [10.0, 0.5],
                [20.0, 5.0],
            ],
            edges: vec![[0, 1], [1, 2], [2, 3], [1, 4], [2, 5]],
        };
        let p = prune_spurs(sk, 2.0);
        assert_eq!(p.edges.len(), 4);
        assert!(!p.nodes.contains(&[10.0, 0.5]));
        assert!(p.nodes.contains(&[20.0, 5.0]));
    }
}
