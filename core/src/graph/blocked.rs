//! Obstacles the vehicle met that the aerial prior did not show (pillars
//! under a slab, trunks under a crown): the graph forgets the ground there so
//! the next route goes around instead of into them again.

use super::GroundGraph;
use crate::geom::segment;

impl GroundGraph {
    /// Takes out every node within `radius` (xy) of `at` and makes every edge
    /// passing within `radius` of it impassable (infinite length). Returns
    /// how many edges were cut. Node indices stay valid: a removed node is
    /// only no longer found by [`GroundGraph::nearest_node`] and the other
    /// look-ups, and no search reaches it.
    pub fn block_near(&mut self, at: [f32; 2], radius: f32) -> usize {
        if !(at.iter().all(|v| v.is_finite()) && radius.is_finite() && radius > 0.0) {
            return 0;
        }
        self.blocked_spots.push((at, radius));
        let reach = radius + self.params.d_threshold();
        let near = self.nodes_near(at, reach, usize::MAX);
        let mut cut = 0;
        for &(u, du) in &near {
            let remove = du <= radius;
            for e in self.adj_start[u]..self.adj_start[u + 1] {
                if !self.adj_w[e].is_finite() {
                    continue;
                }
                let v = self.adj[e] as usize;
                let (p, q) = (self.positions[u], self.positions[v]);
                if !remove && segment_distance(at, [p[0], p[1]], [q[0], q[1]]) > radius {
                    continue;
                }
                self.adj_w[e] = f32::INFINITY;
                if let Some(back) =
                    (self.adj_start[v]..self.adj_start[v + 1]).find(|&b| self.adj[b] as usize == u)
                {
                    self.adj_w[back] = f32::INFINITY;
                }
                cut += 1;
            }
            if remove {
                self.unindex_node(u);
            }
        }
        cut
    }

    /// The node to start a route from at `xy`: the nearest one within
    /// `max_dist` whose straight way from `xy` passes no spot found blocked
    /// (the nearest node can lie just beyond the obstacle the vehicle met).
    pub fn start_node_from(&self, xy: [f32; 2], max_dist: f32) -> Option<(usize, f32)> {
        if self.blocked_spots.is_empty() {
            return self.nearest_node(xy).filter(|&(_, d)| d <= max_dist);
        }
        self.nodes_near(xy, max_dist, usize::MAX)
            .into_iter()
            .find(|&(n, _)| {
                let p = self.positions[n];
                self.blocked_spots
                    .iter()
                    .all(|&(at, r)| segment_distance(at, xy, [p[0], p[1]]) > r)
            })
            .or_else(|| self.nearest_node(xy).filter(|&(_, d)| d <= max_dist))
    }
}

/// Distance (xy) from `p` to the segment `a → b`.
fn segment_distance(p: [f32; 2], a: [f32; 2], b: [f32; 2]) -> f32 {
    let wide = |q: [f32; 2]| q.map(f64::from);
    segment::distance(wide(p), wide(a), wide(b)) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::GraphParams;

    /// Flat open ground, 20 m × 6 m, one ground point every 0.25 m.
    fn strip() -> GroundGraph {
        let (xyz, labels) = crate::geom::fixtures::flat_ground(80, 24, 0.25);
        GroundGraph::build(&xyz, &labels, [1.0, 3.0, 0.0], &GraphParams::default())
            .expect("open ground builds")
    }

    #[test]
    fn a_blocked_spot_is_routed_around_and_no_longer_snapped_to() {
        let mut g = strip();
        let (a, _) = g.nearest_node([1.0, 3.0]).expect("node");
        let (b, _) = g.nearest_node([19.0, 3.0]).expect("node");
        let straight = g.shortest_paths(&[a]).dist[b];
        assert!(straight.is_finite());
        let cut = g.block_near([10.0, 3.0], 1.0);
        assert!(cut > 0, "no edge cut");
        let around = g.shortest_paths(&[a]);
        assert!(
            around.dist[b].is_finite(),
            "the strip is wide enough to pass"
        );
        assert!(
            around.dist[b] > straight,
            "{} vs {straight}",
            around.dist[b]
        );
        for n in around.path_to_source(b) {
            let p = g.positions()[n];
            assert!(
                (p[0] - 10.0).hypot(p[1] - 3.0) > 1.0,
                "path still through {p:?}"
            );
        }
        let (n, d) = g.nearest_node([10.0, 3.0]).expect("node");
        assert!(d > 1.0, "snapped to removed node {n} at {d} m");
        // Standing just before the spot, a route starts behind it, not beyond.
        let (s, _) = g.start_node_from([8.5, 3.0], 5.0).expect("start");
        let p = g.positions()[s];
        assert!(p[0] < 9.0, "start node {p:?} lies beyond the blocked spot");
    }

    #[test]
    fn bad_input_cuts_nothing() {
        let mut g = strip();
        assert_eq!(g.block_near([f32::NAN, 0.0], 1.0), 0);
        assert_eq!(g.block_near([10.0, 3.0], 0.0), 0);
        assert_eq!(g.block_near([10.0, 3.0], f32::INFINITY), 0);
    }
}
