//! val3dity's own CityJSON test files through `validity::check_solid`: each
//! Solid (and each member of a MultiSolid or CompositeSolid) gives the codes
//! the file is documented or, where the README says nothing, reasoned to have.

use serde_json::Value;
use skyground_core::validity::{Tolerances, check_solid, solids_from_cityjson_geometry};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The conformance folder; `None`, said plainly, when it is absent.
fn folder() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/conformance");
    if dir.is_dir() {
        Some(dir)
    } else {
        println!("SKIPPED: {} not found", dir.display());
        None
    }
}

/// The codes of every solid of every city object in `name`, in file order,
/// one set per solid; `None` when the data is absent.
fn codes_of(name: &str) -> Option<Vec<BTreeSet<u16>>> {
    let path = folder()?.join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let doc: Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
    let vertices = real_vertices(&doc);
    let mut out = Vec::new();
    let objects = doc["CityObjects"].as_object().into_iter().flatten();
    for (_, object) in objects {
        for g in object["geometry"].as_array().into_iter().flatten() {
            // MultiSurfaces are not solids: val3dity checks them differently.
            for solid in solids_from_cityjson_geometry(g, &vertices) {
                let found = check_solid(&solid, &Tolerances::default());
                out.push(found.iter().map(|f| f.code).collect());
            }
        }
    }
    Some(out)
}

/// The file's vertices with its `transform` (scale, translate) applied.
fn real_vertices(doc: &Value) -> Vec<[f64; 3]> {
    let part = |key: &str, k: usize, none: f64| doc["transform"][key][k].as_f64().unwrap_or(none);
    let scale = [0, 1, 2].map(|k| part("scale", k, 1.0));
    let translate = [0, 1, 2].map(|k| part("translate", k, 0.0));
    doc["vertices"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|v| [0, 1, 2].map(|k| v[k].as_f64().unwrap_or(f64::NAN) * scale[k] + translate[k]))
        .collect()
}

/// A set of codes, for comparing.
fn set(c: &[u16]) -> BTreeSet<u16> {
    c.iter().copied().collect()
}

#[test]
fn cube10_lacks_its_floor() {
    let Some(codes) = codes_of("val3dity_cube10.json") else {
        return;
    };
    // The README says only "a cube"; its Solid lists five surfaces, the floor
    // (0 3 2 1) missing, so every floor edge is used once: not closed (302).
    // The five surfaces left are planar and turned outward.
    assert_eq!(codes, vec![set(&[302])]);
}

#[test]
fn nonmanifold_is_non_manifold() {
    let Some(codes) = codes_of("val3dity_nonmanifold.json") else {
        return;
    };
    // Documented non-manifold (303): the roof's two triangles 4 7 8 and 5 8 6
    // meet only at vertex 8 (two fans there). Reasoned, not documented: the
    // other two roof triangles are absent, so the shell is open too (302).
    assert_eq!(codes, vec![set(&[302, 303])]);
}

#[test]
fn csol_second_member_repeats_a_vertex() {
    let Some(codes) = codes_of("val3dity_csol.json") else {
        return;
    };
    // The README says only "CompositeSolid". Reasoned: the first cube is
    // valid; the second's surface 9 10 14 14 repeats vertex 14 (102). That the
    // two cubes do not touch is a composite-solid (5xx) matter, not checked.
    assert_eq!(codes, vec![set(&[]), set(&[102])]);
}

#[test]
fn msol_members_are_valid() {
    let Some(codes) = codes_of("val3dity_msol.json") else {
        return;
    };
    // The README says only "MultiSolid". Reasoned: two closed, outward unit cubes.
    assert_eq!(codes, vec![set(&[]), set(&[])]);
}

#[test]
fn twobuildings_m_has_no_solid() {
    let Some(codes) = codes_of("val3dity_twobuildings_m.json") else {
        return;
    };
    // Documented as two LoD2 MultiSurface buildings: nothing to check as a solid.
    assert!(codes.is_empty(), "{codes:?}");
}

#[test]
fn several_lods_valid_is_valid() {
    let Some(codes) = codes_of("val3dity_several_lods_valid.json") else {
        return;
    };
    // val3dity named it valid: its three Solids (LoD 1.2, 1.3, 2.2) give nothing.
    assert_eq!(codes.len(), 3);
    assert!(codes.iter().all(BTreeSet::is_empty), "{codes:?}");
}
