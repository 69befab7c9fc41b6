//! Triangulating polygons with holes: 2D ear clipping ([`triangulate_2d`]) and
//! 3D rings projected to their best-fit plane first ([`triangulate_3d`]).
//!
//! Robust by construction rather than exact: every input gives a result and
//! never panics. A simple polygon with `n` vertices (holes bridged in) gives
//! `n - 2` triangles; self-intersecting or degenerate input still gives
//! triangles covering roughly the polygon (a vertex with no valid ear is
//! clipped anyway), and rings with no area give none.
//!
//! Not geo's `TriangulateEarcut`: its earcut drops collinear vertices
//! (`filter_points`), which leaves T-junctions where a wall meets a roof
//! edge, so the reconstructed solids (`reconstruct::solid`) would no longer
//! be watertight. This clipper keeps every vertex (`collinear_vertices_are_kept`).
//! geo 0.33's earcut keeps the collinear vertex of that simple ring too
//! (`geo_earcut_keeps_the_collinear_vertex_too`), so that reason is not shown
//! there; on real city models the two agree and ours is 1.2–1.5× faster
//! (`benches/earcut.rs`, docs/performance.md "Polygon triangulation").

mod earcut;
mod plane;

pub use earcut::triangulate_2d;
pub use plane::triangulate_3d;
