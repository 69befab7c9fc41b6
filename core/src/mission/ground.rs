//! The one ground graph of a mission: the planner and the explorer build it
//! with the same call and take out the same blocked spots, so the explorer
//! never routes back into a spot the planner was blocked at.

use crate::graph::{GraphError, GraphParams, GroundGraph};

use super::protocol::BlockedSpot;

/// Builds the ground graph from a classified cloud at `start` and takes out
/// every spot in `blocked`.
pub fn build(
    xyz: &[[f32; 3]],
    labels: &[u8],
    start: [f32; 3],
    params: &GraphParams,
    blocked: &[BlockedSpot],
) -> Result<GroundGraph, GraphError> {
    let mut g = GroundGraph::build(xyz, labels, start, params)?;
    apply(&mut g, blocked);
    Ok(g)
}

/// Takes the spots of `blocked` out of `graph`; returns the edges cut.
pub fn apply(graph: &mut GroundGraph, blocked: &[BlockedSpot]) -> usize {
    blocked
        .iter()
        .map(|s| graph.block_near(s.at, s.radius))
        .sum()
}
