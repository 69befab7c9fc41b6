//! Shell self-intersection (306): triangles of different surfaces that meet
//! other than along the edge or at the vertex they share.

use super::surface::Face;
use super::tritri::{Tri, segment_meets_triangle, triangles_meet};
use crate::scene::vec3::{cross, dot, sub};

/// One surface triangle, placed.
struct Placed {
    /// Index of its face in the shell.
    face: usize,
    /// Merged vertex ids of its corners.
    ids: [usize; 3],
    /// Corners relative to the shell's first vertex.
    corners: Tri,
    /// Bounding box, low and high corners.
    lo: [f64; 3],
    /// See `lo`.
    hi: [f64; 3],
}

/// The faces (each once, sorted) with a triangle meeting another face's
/// triangle where they should not, within `eps`.
pub(super) fn crossing_faces(vertices: &[[f64; 3]], faces: &[Face], eps: f64) -> Vec<usize> {
    let mut tris = placed(vertices, faces);
    // Sweep along x: only boxes overlapping in x are compared further.
    tris.sort_by(|a, b| a.lo[0].total_cmp(&b.lo[0]));
    let mut hit = Vec::new();
    for (i, a) in tris.iter().enumerate() {
        for b in &tris[i + 1..] {
            if b.lo[0] > a.hi[0] + eps {
                break;
            }
            let boxes = (1..3).all(|k| b.lo[k] <= a.hi[k] + eps && a.lo[k] <= b.hi[k] + eps);
            if a.face != b.face && boxes && wrongly_meet(a, b, eps) {
                hit.push(a.face);
                hit.push(b.face);
            }
        }
    }
    hit.sort_unstable();
    hit.dedup();
    hit
}

/// Every face's triangles with their boxes; slivers without area are left out.
fn placed(vertices: &[[f64; 3]], faces: &[Face]) -> Vec<Placed> {
    let origin = faces
        .iter()
        .flat_map(|f| &f.triangles)
        .next()
        .map_or([0.0; 3], |t| vertices[t[0]]);
    let mut out = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        for t in &face.triangles {
            let corners = t.map(|i| sub(vertices[i], origin));
            let n = cross(sub(corners[1], corners[0]), sub(corners[2], corners[0]));
            if dot(n, n) <= 1e-24 {
                continue;
            }
            let lo = [0, 1, 2].map(|k| corners.iter().map(|c| c[k]).fold(f64::INFINITY, f64::min));
            let hi = [0, 1, 2].map(|k| {
                corners
                    .iter()
                    .map(|c| c[k])
                    .fold(f64::NEG_INFINITY, f64::max)
            });
            out.push(Placed {
                face: f,
                ids: *t,
                corners,
                lo,
                hi,
            });
        }
    }
    out
}

/// Whether two triangles of different faces meet beyond what they share.
fn wrongly_meet(a: &Placed, b: &Placed, eps: f64) -> bool {
    let shared: Vec<(usize, usize)> = (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .filter(|&(i, j)| a.ids[i] == b.ids[j])
        .collect();
    match shared[..] {
        [] => triangles_meet(&a.corners, &b.corners, eps),
        // Two triangles through one vertex meet elsewhere only if an edge
        // facing that vertex meets the other triangle.
        [(i, j)] => {
            let (a1, a2) = (a.corners[(i + 1) % 3], a.corners[(i + 2) % 3]);
            let (b1, b2) = (b.corners[(j + 1) % 3], b.corners[(j + 2) % 3]);
            segment_meets_triangle(a1, a2, &b.corners, eps)
                || segment_meets_triangle(b1, b2, &a.corners, eps)
        }
        // Sharing an edge, they overlap only folded flat onto each other.
        [(i0, j0), (i1, j1)] => folded_onto(a, b, [i0, i1], [j0, j1], eps),
        _ => true,
    }
}

/// Whether `a` and `b`, sharing the edge at corners `ia` of `a` and `jb` of
/// `b`, lie folded flat onto each other: their third corners on the same side
/// of the edge, the one within `eps` of the other's plane.
fn folded_onto(a: &Placed, b: &Placed, ia: [usize; 2], jb: [usize; 2], eps: f64) -> bool {
    let (v, w) = (a.corners[ia[0]], a.corners[ia[1]]);
    let x = a.corners[3 - ia[0] - ia[1]];
    let y = b.corners[3 - jb[0] - jb[1]];
    let e = sub(w, v);
    let (nx, ny) = (cross(e, sub(x, v)), cross(e, sub(y, v)));
    let (lx, ly, el) = (dot(nx, nx).sqrt(), dot(ny, ny).sqrt(), dot(e, e).sqrt());
    if lx <= 0.0 || ly <= 0.0 || el <= 0.0 {
        return false;
    }
    let cos = dot(nx, ny) / (lx * ly);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    // `ly / el` is y's height off the edge: times the dihedral's sine, its distance from a's plane.
    cos > 0.0 && sin * (ly / el) <= eps
}
