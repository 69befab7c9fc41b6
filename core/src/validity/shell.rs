//! The shell checks of one shell whose surfaces all passed: 301, 302, 303,
//! 305, then (on a closed, manifold, consistently turned shell) 307 by volume
//! and 306.

use super::codes::{
    MULTIPLE_CONNECTED_COMPONENTS, NON_MANIFOLD_CASE, POLYGON_WRONG_ORIENTATION, SHELL_NOT_CLOSED,
    SHELL_SELF_INTERSECTION, TOO_FEW_POLYGONS,
};
use super::surface::{Edges, Face, edges};
use super::{Tolerances, intersect, orientation};
use petgraph::unionfind::UnionFind;
use std::collections::HashMap;

/// The shell's findings as (code, surface); `exterior` for the first shell,
/// whose normals point out (a void's point into it).
pub(super) fn check(
    vertices: &[[f64; 3]],
    faces: &[Face],
    exterior: bool,
    tol: &Tolerances,
) -> Vec<(u16, Option<usize>)> {
    if faces.len() < 4 {
        return vec![(TOO_FEW_POLYGONS, None)];
    }
    let edges = edges(faces);
    let mut found = Vec::new();
    for uses in edges.values() {
        match uses.len() {
            1 => found.push((SHELL_NOT_CLOSED, Some(uses[0].0))),
            2 => {}
            _ => found.push((NON_MANIFOLD_CASE, Some(uses[0].0))),
        }
    }
    found.extend(
        pinched_vertices(faces, &edges)
            .into_iter()
            .map(|f| (NON_MANIFOLD_CASE, Some(f))),
    );
    if components(faces.len(), &edges) > 1 {
        found.push((MULTIPLE_CONNECTED_COMPONENTS, None));
    }
    found.extend(
        orientation::misturned(faces.len(), &edges)
            .into_iter()
            .map(|f| (POLYGON_WRONG_ORIENTATION, Some(f))),
    );
    // Volume and intersections mean something only on a closed, manifold, consistently turned shell.
    let combinatorial = found
        .iter()
        .any(|&(c, _)| c != MULTIPLE_CONNECTED_COMPONENTS);
    if combinatorial {
        return found;
    }
    let volume = orientation::signed_volume(vertices, faces);
    if (exterior && volume <= 0.0) || (!exterior && volume >= 0.0) {
        found.push((POLYGON_WRONG_ORIENTATION, None));
        return found;
    }
    // A micrometre per millimetre of snapping: far below any real gap, far above rounding.
    let eps = tol.snap_m.max(1e-6) * 1e-3;
    found.extend(
        intersect::crossing_faces(vertices, faces, eps)
            .into_iter()
            .map(|f| (SHELL_SELF_INTERSECTION, Some(f))),
    );
    found
}

/// The number of groups of faces joined by shared edges.
fn components(n: usize, edges: &Edges) -> usize {
    let mut uf = UnionFind::<usize>::new(n);
    for uses in edges.values() {
        for w in uses.windows(2) {
            uf.union(w[0].0, w[1].0);
        }
    }
    let mut labels = uf.into_labeling();
    labels.sort_unstable();
    labels.dedup();
    labels.len()
}

/// A face at each vertex whose faces meet in more than one fan (groups
/// joined by edges through the vertex): the shell is pinched there.
fn pinched_vertices(faces: &[Face], edges: &Edges) -> Vec<usize> {
    let mut incident: HashMap<usize, Vec<usize>> = HashMap::new();
    for (f, face) in faces.iter().enumerate() {
        for &v in face.rings.iter().flatten() {
            incident.entry(v).or_default().push(f);
        }
    }
    let mut through: HashMap<usize, Vec<&[(usize, bool)]>> = HashMap::new();
    for (&(a, b), uses) in edges {
        through.entry(a).or_default().push(uses);
        through.entry(b).or_default().push(uses);
    }
    let mut pinched = Vec::new();
    for (v, mut around) in incident {
        around.sort_unstable();
        around.dedup();
        let local = |f: usize| around.binary_search(&f).ok();
        let mut uf = UnionFind::<usize>::new(around.len());
        for uses in through.get(&v).into_iter().flatten() {
            for w in uses.windows(2) {
                if let (Some(a), Some(b)) = (local(w[0].0), local(w[1].0)) {
                    uf.union(a, b);
                }
            }
        }
        let root = uf.find(0);
        if let Some(k) = (1..around.len()).find(|&k| uf.find(k) != root) {
            pinched.push(around[k]);
        }
    }
    pinched
}
