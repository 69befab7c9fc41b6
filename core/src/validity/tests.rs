use super::*;
use std::collections::BTreeSet;

/// The six outward faces of the cube whose corners start at vertex `o`.
fn cube_faces(o: usize) -> Vec<Surface> {
    crate::geom::fixtures::BOX_FACES
        .iter()
        .map(|f| vec![f.iter().map(|&i| i + o).collect()])
        .collect()
}

/// The corners of the axis-aligned cube of side `s` at `min`.
fn cube_vertices(min: [f64; 3], s: f64) -> Vec<[f64; 3]> {
    let [x, y, z] = min;
    vec![
        [x, y, z],
        [x + s, y, z],
        [x + s, y + s, z],
        [x, y + s, z],
        [x, y, z + s],
        [x + s, y, z + s],
        [x + s, y + s, z + s],
        [x, y + s, z + s],
    ]
}

/// A unit cube as one exterior shell.
fn unit_cube() -> Solid {
    Solid {
        vertices: cube_vertices([0.0; 3], 1.0),
        shells: vec![cube_faces(0)],
    }
}

/// Cubes (min corner, side) in one shell, each with its own vertices.
fn cubes_in_one_shell(cubes: &[([f64; 3], f64)]) -> Solid {
    let mut s = Solid {
        vertices: Vec::new(),
        shells: vec![Vec::new()],
    };
    for &(min, side) in cubes {
        let o = s.vertices.len();
        s.vertices.extend(cube_vertices(min, side));
        s.shells[0].extend(cube_faces(o));
    }
    s
}

/// The codes `s` is found with, each once.
fn codes(s: &Solid) -> BTreeSet<u16> {
    check_solid(s, &Tolerances::default())
        .iter()
        .map(|f| f.code)
        .collect()
}

/// A set of codes, for comparing.
fn set(c: &[u16]) -> BTreeSet<u16> {
    c.iter().copied().collect()
}

/// The prism over `footprint` (counter-clockwise) from z = 0 to `h`, its
/// roof cut into the given pieces (each a list of footprint indices).
fn prism(footprint: &[[f64; 2]], h: f64, roof: &[Vec<usize>]) -> Solid {
    let n = footprint.len();
    let mut vertices: Vec<[f64; 3]> = footprint.iter().map(|p| [p[0], p[1], 0.0]).collect();
    vertices.extend(footprint.iter().map(|p| [p[0], p[1], h]));
    let mut faces: Vec<Surface> = vec![vec![(0..n).rev().collect()]];
    faces.extend(
        roof.iter()
            .map(|r| vec![r.iter().map(|&i| i + n).collect()]),
    );
    faces.extend((0..n).map(|i| {
        let j = (i + 1) % n;
        vec![vec![i, j, j + n, i + n]]
    }));
    Solid {
        vertices,
        shells: vec![faces],
    }
}

#[test]
fn unit_cube_is_valid() {
    assert_eq!(check_solid(&unit_cube(), &Tolerances::default()), vec![]);
}

#[test]
fn cube_without_a_face_is_not_closed() {
    let mut s = unit_cube();
    s.shells[0].remove(1);
    assert_eq!(codes(&s), set(&[302]));
}

#[test]
fn one_flipped_face_is_wrongly_turned() {
    let mut s = unit_cube();
    s.shells[0][3][0].reverse();
    let found = check_solid(&s, &Tolerances::default());
    assert_eq!(
        found,
        vec![Finding {
            code: 307,
            shell: 0,
            surface: Some(3)
        }]
    );
    // The blame falls on the odd face even when it is the first one met.
    let mut s = unit_cube();
    s.shells[0][0][0].reverse();
    let found = check_solid(&s, &Tolerances::default());
    assert_eq!(found.len(), 1);
    assert_eq!((found[0].code, found[0].surface), (307, Some(0)));
}

#[test]
fn all_faces_flipped_is_wrongly_turned_once() {
    let mut s = unit_cube();
    for f in &mut s.shells[0] {
        f[0].reverse();
    }
    assert_eq!(
        check_solid(&s, &Tolerances::default()),
        vec![Finding {
            code: 307,
            shell: 0,
            surface: None
        }]
    );
}

#[test]
fn vertex_five_cm_up_is_non_planar() {
    let mut s = unit_cube();
    s.vertices[6][2] += 0.05;
    assert_eq!(codes(&s), set(&[203]));
    // Within the 1 cm tolerance the cube passes.
    let mut s = unit_cube();
    s.vertices[6][2] += 0.005;
    assert_eq!(codes(&s), set(&[]));
}

#[test]
fn folded_small_face_deviates_in_normals() {
    // A 2 cm cube with a roof corner 2 cm up: a quarter of that off the
    // least-squares plane (within 1 cm), but its triangles tilt ~45°.
    let mut s = Solid {
        vertices: cube_vertices([0.0; 3], 0.02),
        shells: vec![cube_faces(0)],
    };
    s.vertices[6][2] += 0.02;
    assert_eq!(codes(&s), set(&[204]));
}

#[test]
fn repeated_consecutive_vertex() {
    let mut s = unit_cube();
    s.shells[0][1][0] = vec![4, 5, 5, 6, 7];
    assert_eq!(codes(&s), set(&[102]));
    // A distinct index at (nearly) the same spot is the same vertex.
    let mut s = unit_cube();
    s.vertices.push([1.0, 0.0, 1.0004]);
    s.shells[0][1][0] = vec![4, 5, 8, 6, 7];
    assert_eq!(codes(&s), set(&[102]));
}

#[test]
fn bow_tie_ring_intersects_itself() {
    let mut s = unit_cube();
    s.shells[0][1][0] = vec![4, 5, 7, 6];
    assert_eq!(codes(&s), set(&[104]));
    // Visiting a vertex twice is a self-intersection too.
    let mut s = unit_cube();
    s.vertices.push([0.5, 0.5, 1.0]);
    s.shells[0][1][0] = vec![4, 5, 8, 6, 7, 8];
    assert_eq!(codes(&s), set(&[104]));
}

#[test]
fn face_with_two_vertices_has_too_few_points() {
    let mut s = unit_cube();
    s.shells[0][1][0] = vec![4, 5];
    assert_eq!(codes(&s), set(&[101]));
}

#[test]
fn three_faces_are_too_few_polygons() {
    let mut s = unit_cube();
    s.shells[0].truncate(3);
    assert_eq!(codes(&s), set(&[301]));
}

#[test]
fn cubes_sharing_an_edge_are_non_manifold() {
    let s = cubes_in_one_shell(&[([0.0; 3], 1.0), ([1.0, 1.0, 0.0], 1.0)]);
    assert_eq!(codes(&s), set(&[303]));
}

#[test]
fn disjoint_cubes_are_two_components() {
    let s = cubes_in_one_shell(&[([0.0; 3], 1.0), ([3.0, 0.0, 0.0], 1.0)]);
    assert_eq!(codes(&s), set(&[305]));
}

#[test]
fn interpenetrating_cubes_intersect() {
    // Two closed cubes without a shared edge are two components as well;
    // val3dity would stop at 305, this check also names the crossing.
    let s = cubes_in_one_shell(&[([0.0; 3], 1.0), ([0.5, 0.5, 0.5], 1.0)]);
    assert_eq!(codes(&s), set(&[305, 306]));
    let crossing: Vec<_> = check_solid(&s, &Tolerances::default())
        .into_iter()
        .filter(|f| f.code == 306)
        .collect();
    assert!(crossing.iter().any(|f| f.surface < Some(6)), "{crossing:?}");
    assert!(
        crossing.iter().any(|f| f.surface >= Some(6)),
        "{crossing:?}"
    );
}

#[test]
fn roof_spiked_through_the_floor_intersects_itself() {
    // One connected, closed, outward shell: a 2 m cube whose roof is four
    // triangles down to an apex 1 m below the floor.
    let mut s = Solid {
        vertices: cube_vertices([0.0; 3], 2.0),
        shells: vec![cube_faces(0)],
    };
    s.vertices.push([1.0, 1.0, -1.0]);
    s.shells[0].remove(1);
    for [a, b] in [[4, 5], [5, 6], [6, 7], [7, 4]] {
        s.shells[0].push(vec![vec![a, b, 8]]);
    }
    assert_eq!(codes(&s), set(&[306]));
}

#[test]
fn l_shaped_prism_with_coplanar_pieces_is_valid() {
    // Collinear footprint vertices split the long walls into coplanar
    // pieces; the roof is two coplanar pieces sharing an edge.
    let footprint = [
        [0.0, 0.0],
        [2.0, 0.0],
        [4.0, 0.0],
        [6.0, 0.0],
        [6.0, 2.0],
        [4.0, 2.0],
        [2.0, 2.0],
        [2.0, 4.0],
        [2.0, 6.0],
        [0.0, 6.0],
        [0.0, 4.0],
        [0.0, 2.0],
    ];
    let roof = vec![vec![0, 1, 2, 3, 4, 5, 6, 11], vec![11, 6, 7, 8, 9, 10]];
    assert_eq!(
        check_solid(&prism(&footprint, 3.0, &roof), &Tolerances::default()),
        vec![]
    );
    // Far from the origin (map coordinates) nothing changes.
    let far: Vec<[f64; 2]> = footprint
        .iter()
        .map(|p| [p[0] + 85_000.0, p[1] + 446_000.0])
        .collect();
    assert_eq!(
        check_solid(&prism(&far, 3.0, &roof), &Tolerances::default()),
        vec![]
    );
}

#[test]
fn terraced_blocks_sharing_a_wall_are_each_valid() {
    let whole = |n: usize| vec![(0..n).collect::<Vec<_>>()];
    let west = [[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]];
    let east = [[4.0, 0.0], [8.0, 0.0], [8.0, 5.0], [4.0, 5.0]];
    for block in [west, east] {
        assert_eq!(
            check_solid(&prism(&block, 3.0, &whole(4)), &Tolerances::default()),
            vec![]
        );
    }
}

#[test]
fn inner_rings() {
    let hole = |ring: Vec<[f64; 3]>| {
        let mut s = unit_cube();
        let o = s.vertices.len();
        s.vertices.extend(ring.iter().copied());
        s.shells[0][1].push((o..o + ring.len()).collect());
        codes(&s)
    };
    let at = |pts: &[[f64; 2]]| pts.iter().map(|p| [p[0], p[1], 1.0]).collect::<Vec<_>>();
    // Clockwise seen from above, against the counter-clockwise roof: only the
    // open hole is left, which the ring and polygon levels do not see.
    let cw = at(&[[0.25, 0.25], [0.25, 0.75], [0.75, 0.75], [0.75, 0.25]]);
    assert_eq!(hole(cw), set(&[302]));
    let ccw = at(&[[0.25, 0.25], [0.75, 0.25], [0.75, 0.75], [0.25, 0.75]]);
    assert_eq!(hole(ccw), set(&[208]));
    let outside = at(&[[2.25, 0.25], [2.25, 0.75], [2.75, 0.75], [2.75, 0.25]]);
    assert_eq!(hole(outside), set(&[206]));
    let crossing = at(&[[0.5, 0.25], [0.5, 0.75], [1.5, 0.75], [1.5, 0.25]]);
    assert_eq!(hole(crossing), set(&[201]));
}

#[test]
fn vertex_index_out_of_range_is_invalid_input() {
    let mut s = unit_cube();
    s.shells[0][1][0][2] = 99;
    assert_eq!(codes(&s), set(&[901]));
    let empty = Solid {
        vertices: Vec::new(),
        shells: Vec::new(),
    };
    assert_eq!(codes(&empty), set(&[902]));
}

#[test]
fn names_and_defaults() {
    assert_eq!(code_name(302), "SHELL_NOT_CLOSED");
    assert_eq!(code_name(104), "RING_SELF_INTERSECTION");
    assert_eq!(code_name(1), "UNKNOWN");
    let t = Tolerances::default();
    assert_eq!(
        (t.planarity_m, t.normals_deg, t.snap_m),
        (0.01, 20.0, 0.001)
    );
}

#[test]
fn reads_cityjson_solid_boundaries() {
    let g = serde_json::json!({
        "type": "Solid",
        "boundaries": [[[[0, 3, 2, 1]], [[4, 5, 6, 7]], [[0, 1, 5, 4]], [[1, 2, 6, 5]],
                        [[2, 3, 7, 6]], [[3, 0, 4, 7]]]]
    });
    let mut vertices = vec![[9.0, 9.0, 9.0]];
    vertices.extend(cube_vertices([0.0; 3], 1.0));
    // The file's vertex 0 is unused: shift every index by one.
    let g = shift(&g);
    let s = from_cityjson_geometry(&g, &vertices);
    assert_eq!(s.as_ref().map(|s| s.vertices.len()), Some(8));
    assert_eq!(s.map(|s| codes(&s)), Some(set(&[])));
    let multi =
        serde_json::json!({"type": "MultiSolid", "boundaries": [g["boundaries"], g["boundaries"]]});
    assert_eq!(solids_from_cityjson_geometry(&multi, &vertices).len(), 2);
    assert!(from_cityjson_geometry(&multi, &vertices).is_none());
    let bad = serde_json::json!({"type": "Solid", "boundaries": [[[[0, 1, 99]]]]});
    assert!(from_cityjson_geometry(&bad, &vertices).is_none());
}

/// `g` with every vertex index one higher.
fn shift(g: &serde_json::Value) -> serde_json::Value {
    match g {
        serde_json::Value::Number(n) => serde_json::json!(n.as_u64().unwrap_or(0) + 1),
        serde_json::Value::Array(a) => a.iter().map(shift).collect(),
        serde_json::Value::Object(o) => o
            .iter()
            .map(|(k, v)| {
                (
                    k.clone(),
                    if k == "boundaries" {
                        shift(v)
                    } else {
                        v.clone()
                    },
                )
            })
            .collect(),
        other => other.clone(),
    }
}
