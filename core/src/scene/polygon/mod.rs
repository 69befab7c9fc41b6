//! Triangulating polygons with holes: 2D ear clipping ([`triangulate_2d`]) and
//! 3D rings projected to their best-fit plane first ([`triangulate_3d`]).
//!
//! Robust by construction rather than exact: every input gives a result and
//! never panics. A simple polygon with `n` vertices (holes bridged in) gives
//! `n - 2` triangles; self-intersecting or degenerate input still gives
//! triangles covering roughly the polygon (a vertex with no valid ear is
//! clipped anyway), and rings with no area give none.
//!
//! Not geo's `TriangulateEarcut`: on a rectangle with two rectangular holes
//! (the reference scene's podium roof) geo 0.33 leaves a hole corner out of
//! every triangle, a T-junction that opens the solid
//! (`geo_earcut_leaves_a_hole_corner_out_and_ours_keeps_it`; swapped in, the
//! reference podium and slab on pillars got 4 boundary edges each). This
//! clipper keeps every vertex (`collinear_vertices_are_kept`). On the real
//! city models of `benches/earcut.rs` the two agree to within one surface
//! (docs/performance.md "Polygon triangulation").

mod earcut;
mod plane;

pub use earcut::triangulate_2d;
pub use plane::triangulate_3d;
