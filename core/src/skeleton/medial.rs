//! The medial axis from a constrained Delaunay triangulation of the outline.

use geo::{Contains, Coord, LineString, MultiPolygon, Point};

use serde::{Deserialize, Serialize};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::params::{Checks, ParamError};

use super::graph::Skeleton;
use super::prune::prune_spurs;

/// How the skeleton is built.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SkeletonParams {
    /// Spacing at which the contour is sampled for the triangulation, metres.
    pub sample: f64,
    /// Leaf branches shorter than this are pruned, metres.
    pub min_branch: f64,
}

impl Default for SkeletonParams {
    fn default() -> Self {
        SkeletonParams {
            sample: 1.0,
            min_branch: 3.0,
        }
    }
}

impl SkeletonParams {
    /// Checks every field is usable.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("skeleton");
        c.positive("sample", self.sample)?;
        c.positive("min_branch", self.min_branch)
    }
}

/// Resamples a closed ring so no edge is longer than `spacing`.
fn densify(ring: &LineString<f64>, spacing: f64) -> Vec<Coord<f64>> {
    let mut out = Vec::new();
    for w in ring.0.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = ((b.x - a.x).powi(2) + (b.y - a.y).powi(2)).sqrt();
        let n = (len / spacing).ceil().max(1.0) as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.push(Coord {
                x: a.x + t * (b.x - a.x),
                y: a.y + t * (b.y - a.y),
            });
        }
    }
    out
}

/// Medial axis of `outline` (outer rings and holes); empty for an empty or
/// degenerate outline.
pub fn medial_axis(outline: &MultiPolygon<f64>, params: &SkeletonParams) -> Skeleton {
    let spacing = if params.sample.is_finite() && params.sample > 0.0 {
        params.sample
    } else {
        1.0
    };
    let mut vertices = Vec::new();
    let mut edges = Vec::new();
    for poly in &outline.0 {
        for ring in std::iter::once(poly.exterior()).chain(poly.interiors()) {
            let pts = densify(ring, spacing);
            if pts.len() < 3 || pts.iter().any(|c| !(c.x.is_finite() && c.y.is_finite())) {
                continue;
            }
            let first = vertices.len();
            for (k, c) in pts.iter().enumerate() {
                vertices.push(Point2::new(c.x, c.y));
                let next = if k + 1 == pts.len() {
                    first
                } else {
                    first + k + 1
                };
                edges.push([first + k, next]);
            }
        }
    }
    if vertices.len() < 3 {
        return Skeleton::default();
    }
    // Self-touching outlines can give crossing constraints: skip those
    // edges rather than fail the building.
    let Ok(cdt) =
        ConstrainedDelaunayTriangulation::<Point2<f64>>::try_bulk_load_cdt(vertices, edges, |_| {})
    else {
        return Skeleton::default();
    };
    let faces = cdt.num_all_faces();
    let mut node_of = vec![usize::MAX; faces];
    let mut nodes = Vec::new();
    for face in cdt.inner_faces() {
        let [a, b, c] = face.positions();
        let centroid = Point::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0);
        if !outline.contains(&centroid) {
            continue;
        }
        let cc = face.circumcenter();
        // Obtuse triangles put their circumcentre outside the triangle,
        // sometimes outside the outline: fall back to the centroid there.
        let p = if cc.x.is_finite() && cc.y.is_finite() && outline.contains(&Point::new(cc.x, cc.y))
        {
            [cc.x, cc.y]
        } else {
            [centroid.x(), centroid.y()]
        };
        node_of[face.fix().index()] = nodes.len();
        nodes.push(p);
    }
    let mut sk_edges = Vec::new();
    for face in cdt.inner_faces() {
        let me = node_of[face.fix().index()];
        if me == usize::MAX {
            continue;
        }
        for e in face.adjacent_edges() {
            if e.as_undirected().is_constraint_edge() {
                continue;
            }
            let other = node_of[e.rev().face().fix().index()];
            if other != usize::MAX && me < other {
                sk_edges.push([me, other]);
            }
        }
    }
    prune_spurs(
        Skeleton {
            nodes,
            edges: sk_edges,
        },
        params.min_branch,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{Polygon, polygon};

    #[test]
    fn rectangle_axis_runs_along_its_middle() {
        let rect: Polygon<f64> =
            polygon![(x: 0.0, y: 0.0), (x: 40.0, y: 0.0), (x: 40.0, y: 10.0), (x: 0.0, y: 10.0)];
        let sk = medial_axis(&MultiPolygon(vec![rect]), &SkeletonParams::default());
        assert!(!sk.edges.is_empty());
        // interior nodes of the medial axis lie on y = 5 (ends fan to corners)
        let central: Vec<_> = sk
            .nodes
            .iter()
            .filter(|p| (8.0..32.0).contains(&p[0]))
            .collect();
        assert!(!central.is_empty());
        for p in central {
            assert!((p[1] - 5.0).abs() < 0.6, "{p:?}");
        }
        assert!(sk.length() > 25.0);
    }

    #[test]
    fn l_shape_axis_follows_both_arms() {
        let l: Polygon<f64> = polygon![(x: 0.0, y: 0.0), (x: 30.0, y: 0.0), (x: 30.0, y: 10.0), (x: 10.0, y: 10.0), (x: 10.0, y: 30.0), (x: 0.0, y: 30.0)];
        let sk = medial_axis(&MultiPolygon(vec![l]), &SkeletonParams::default());
        let arm_x = sk.nearest([20.0, 5.0]).unwrap();
        let arm_y = sk.nearest([5.0, 20.0]).unwrap();
        assert!(
            crate::geom::segment::distance(arm_x, [5.0, 5.0], [25.0, 5.0]) < 0.8,
            "{arm_x:?}"
        );
        assert!(
            crate::geom::segment::distance(arm_y, [5.0, 5.0], [5.0, 25.0]) < 0.8,
            "{arm_y:?}"
        );
    }

    #[test]
    fn empty_outline_gives_empty_skeleton() {
        let sk = medial_axis(&MultiPolygon(vec![]), &SkeletonParams::default());
        assert!(sk.nodes.is_empty() && sk.nearest([0.0, 0.0]).is_none());
    }
}
