//! One surface through the ring and polygon levels, into what the shell
//! checks need: its rings and triangles in merged vertex ids.

use std::collections::BTreeMap;

use super::codes::{INVALID_INPUT_FILE, TOO_FEW_POINTS};
use super::plane::{Plane, newell};
use super::{Surface, Tolerances, polygon, ring, triangulate};

/// A surface that passed its ring and polygon checks.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Face {
    /// Rings in merged vertex ids (outer first).
    pub rings: Vec<Vec<usize>>,
    /// Triangles in merged vertex ids, turning as the outer ring does.
    pub triangles: Vec<[usize; 3]>,
}

/// An undirected edge (smaller merged id first) → the faces using it, each
/// with whether it runs the edge from the smaller id to the larger.
pub(super) type Edges = BTreeMap<(usize, usize), Vec<(usize, bool)>>;

/// Every ring edge of every face, keyed undirected.
pub(super) fn edges(faces: &[Face]) -> Edges {
    let mut edges = Edges::new();
    for (f, face) in faces.iter().enumerate() {
        for ring in &face.rings {
            for (i, &a) in ring.iter().enumerate() {
                let b = ring[(i + 1) % ring.len()];
                edges
                    .entry((a.min(b), a.max(b)))
                    .or_default()
                    .push((f, a < b));
            }
        }
    }
    edges
}

/// The surface `rings` checked at the ring level (all rings), then at the
/// polygon level when the rings passed; `Err` holds the codes that failed.
/// `ids` maps each vertex to its merged id.
pub(super) fn check(
    vertices: &[[f64; 3]],
    ids: &[usize],
    rings: &Surface,
    tol: &Tolerances,
) -> Result<Face, Vec<u16>> {
    if rings.is_empty() {
        return Err(vec![TOO_FEW_POINTS]);
    }
    let mut merged = Vec::with_capacity(rings.len());
    for r in rings {
        let m: Option<Vec<usize>> = r.iter().map(|&i| ids.get(i).copied()).collect();
        merged.push(m.ok_or_else(|| vec![INVALID_INPUT_FILE])?);
    }
    let mut codes: Vec<u16> = merged
        .iter()
        .filter_map(|r| ring::counts(r, vertices, tol.snap_m))
        .collect();
    if !codes.is_empty() {
        return Err(codes);
    }
    let points: Vec<[f64; 3]> = merged.iter().flatten().map(|&i| vertices[i]).collect();
    let outer: Vec<[f64; 3]> = merged[0].iter().map(|&i| vertices[i]).collect();
    let mut distinct: Vec<usize> = merged.iter().flatten().copied().collect();
    distinct.sort_unstable();
    distinct.dedup();
    let fit: Vec<[f64; 3]> = distinct.iter().map(|&i| vertices[i]).collect();
    let plane = Plane::fit(&fit, newell(&outer)).ok_or_else(|| vec![TOO_FEW_POINTS])?;
    let flat: Vec<Vec<[f64; 2]>> = merged
        .iter()
        .map(|r| r.iter().map(|&i| plane.project(vertices[i])).collect())
        .collect();
    codes.extend(
        merged
            .iter()
            .zip(&flat)
            .filter_map(|(r, f)| ring::self_intersection(r, vertices, f, tol.snap_m)),
    );
    if !codes.is_empty() {
        return Err(codes);
    }
    codes.extend(polygon::distance_to_plane(&plane, &points, tol.planarity_m));
    codes.extend(polygon::rings(&flat));
    if !codes.is_empty() {
        return Err(codes);
    }
    let local = triangulate::triangles(&flat);
    if let Some(code) = polygon::normals_deviation(&plane, &points, &local, tol.normals_deg) {
        return Err(vec![code]);
    }
    let concatenated: Vec<usize> = merged.iter().flatten().copied().collect();
    let triangles = local.iter().map(|t| t.map(|k| concatenated[k])).collect();
    Ok(Face {
        rings: merged,
        triangles,
    })
}
