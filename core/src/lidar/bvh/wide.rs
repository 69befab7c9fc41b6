//! Collapsing the binary build tree into 4-wide nodes.
//!
//! Each wide node takes a binary node's two children and keeps opening the
//! inner child with the largest surface area until it holds four children
//! (or only leaves remain). Unused slots get an inverted box that no ray
//! enters.

use super::Node;
use super::build::{Aabb, BNode};

/// Flattens the tree rooted at `root` (bounds `root_box`) depth first; node 0
/// is the root.
pub(super) fn flatten(root: BNode, root_box: Aabb) -> Vec<Node> {
    let mut nodes = Vec::new();
    match root {
        BNode::Inner(kids) => {
            emit(&kids, &mut nodes);
        }
        leaf @ BNode::Leaf { .. } => {
            let kids = [
                (leaf, root_box),
                (BNode::Leaf { start: 0, count: 0 }, Aabb::EMPTY),
            ];
            emit(&kids, &mut nodes);
        }
    }
    nodes
}

/// Appends the wide node for a binary node with children `kids` (and its
/// subtrees); returns its index.
fn emit(kids: &[(BNode, Aabb); 2], nodes: &mut Vec<Node>) -> u32 {
    let mut slots: Vec<&(BNode, Aabb)> = kids.iter().collect();
    while slots.len() < 4 {
        let widest = slots
            .iter()
            .enumerate()
            .filter(|(_, (n, _))| matches!(n, BNode::Inner(_)))
            .max_by(|a, b| a.1.1.half_area().total_cmp(&b.1.1.half_area()))
            .map(|(i, _)| i);
        let Some(i) = widest else { break };
        let BNode::Inner(grand) = &slots[i].0 else {
            break;
        };
        slots.swap_remove(i);
        slots.extend(grand.iter());
    }
    let me = nodes.len();
    nodes.push(Node::EMPTY);
    let mut node = Node::EMPTY;
    for (c, (kid, b)) in slots.into_iter().enumerate() {
        for k in 0..3 {
            node.bounds[k][0][c] = b.lo[k];
            node.bounds[k][1][c] = b.hi[k];
        }
        match kid {
            // An empty leaf keeps the inverted box, so it is never entered.
            BNode::Leaf { start, count } => {
                node.child[c] = *start;
                // Leaves hold at most MAX_LEAF (8) triangles.
                node.count[c] = *count as u8;
                if *count > 0 {
                    node.leaves |= 1 << c;
                }
            }
            BNode::Inner(grand) => {
                node.child[c] = emit(grand, nodes);
            }
        }
    }
    nodes[me] = node;
    me as u32
}
