//! Real city models as they come (`../shared/data/real`): CityJSON 2.0
//! without terrain (3DBAG), as CityJSONSeq and as tiles made from it at test
//! time, CityJSON 1.1 (Zurich); the ground built under them; and the
//! completeness model written back, checked with `cjval` when it is installed.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::real_file;
use serde_json::{Value, json};
use skyground_core::io::cityjson::{Attributes, annotated_model, read_city_model, scene_model};
use skyground_core::io::{SceneError, load_scene};
use skyground_core::lidar::Caster;
use skyground_core::scene::{ObjectKind, Scene, reference_scene};
use skyground_core::vehicle::{Terrain, free_spot, start_spot};

/// A scratch folder removed when the test ends.
fn temp_dir() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

fn read_json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// Every index in `boundaries`, in order.
fn indices(v: &Value, out: &mut Vec<u64>) {
    match v {
        Value::Array(a) => a.iter().for_each(|x| indices(x, out)),
        Value::Number(n) => out.extend(n.as_u64()),
        _ => {}
    }
}

/// `boundaries` with each index replaced by `map[index]`.
fn remap(v: &Value, map: &BTreeMap<u64, u64>) -> Value {
    match v {
        Value::Array(a) => Value::Array(a.iter().map(|x| remap(x, map)).collect()),
        Value::Number(n) => json!(map[&n.as_u64().unwrap()]),
        other => other.clone(),
    }
}

/// One self-contained piece of `doc` per root Building: its objects and only
/// the vertices they use (indexed from 0), as 3DBAG's features and tiles are.
fn split_per_building(doc: &Value) -> Vec<(Value, Vec<Value>)> {
    let objects = doc["CityObjects"].as_object().unwrap();
    let vertices = doc["vertices"].as_array().unwrap();
    let mut out = Vec::new();
    for (id, o) in objects.iter().filter(|(_, o)| o["type"] == "Building") {
        let mut ids = vec![id.clone()];
        for c in o["children"].as_array().into_iter().flatten() {
            ids.push(c.as_str().unwrap().to_string());
        }
        let mut used = Vec::new();
        for i in &ids {
            for g in objects[i]["geometry"].as_array().into_iter().flatten() {
                indices(&g["boundaries"], &mut used);
            }
        }
        used.sort_unstable();
        used.dedup();
        let map: BTreeMap<u64, u64> = used
            .iter()
            .enumerate()
            .map(|(k, &i)| (i, k as u64))
            .collect();
        let mut part = serde_json::Map::new();
        for i in &ids {
            let mut obj = objects[i].clone();
            for g in obj["geometry"].as_array_mut().into_iter().flatten() {
                g["boundaries"] = remap(&g["boundaries"], &map);
            }
            part.insert(i.clone(), obj);
        }
        let verts = used.iter().map(|&i| vertices[i as usize].clone()).collect();
        out.push((Value::Object(part), verts));
    }
    out
}

/// `doc` as a CityJSONSeq stream: header line, then a feature per building.
fn as_seq(doc: &Value) -> String {
    let header = json!({"type": "CityJSON", "version": doc["version"],
        "transform": doc["transform"], "metadata": doc["metadata"],
        "CityObjects": {}, "vertices": []});
    let mut s = format!("{header}\n");
    for (objects, vertices) in split_per_building(doc) {
        let id = objects.as_object().unwrap().keys().next().unwrap().clone();
        let f = json!({"type": "CityJSONFeature", "id": id, "CityObjects": objects, "vertices": vertices});
        s.push_str(&format!("{f}\n"));
    }
    s
}

/// `doc` as one tile per building (whole CityJSON files).
fn as_tiles(doc: &Value, dir: &Path) -> Vec<PathBuf> {
    split_per_building(doc)
        .into_iter()
        .enumerate()
        .map(|(k, (objects, vertices))| {
            let mut tile = doc.clone();
            tile["CityObjects"] = objects;
            tile["vertices"] = Value::Array(vertices);
            let path = dir.join(format!("tile_{k}.city.json"));
            std::fs::write(&path, tile.to_string()).unwrap();
            path
        })
        .collect()
}

/// Building triangles as sorted corner lists (frame-independent of order).
fn building_triangles(s: &Scene) -> Vec<[[i64; 3]; 3]> {
    let mut out: Vec<[[i64; 3]; 3]> = (0..s.triangles.len())
        .filter(|&t| s.triangle_kind(t).unwrap().kind == ObjectKind::Building)
        .map(|t| {
            s.triangle_corners(t).unwrap().map(|p| {
                [0, 1, 2].map(|k| ((f64::from(p[k]) + s.origin[k]) * 1000.0).round() as i64)
            })
        })
        .collect();
    out.sort_unstable();
    out
}

#[test]
fn lod22_without_terrain_stands_on_built_ground_with_a_start() {
    let Some(path) = real_file("3dbag_2buildings.city.json") else {
        return;
    };
    let scene = load_scene(path.to_str().unwrap()).unwrap();
    scene.validate().unwrap();
    assert_eq!(scene.building_count(), 2);
    assert_eq!(scene.object_count(ObjectKind::Ground), 1);
    let caster = Caster::new(&scene).unwrap();
    let terrain = Terrain::new(&caster);
    // The built ground meets each building where 3DBAG measured the ground
    // (b3_h_maaiveld, from AHN): the file has no terrain of its own.
    let doc = read_json(&path);
    for id in [
        "NL.IMBAG.Pand.0503100000028341",
        "NL.IMBAG.Pand.0503100000031927",
    ] {
        let base = doc["CityObjects"][id]["attributes"]["b3_h_maaiveld"]
            .as_f64()
            .unwrap();
        let b = scene
            .objects
            .iter()
            .find(|o| o.name.starts_with(id))
            .unwrap()
            .building;
        let (lo, hi) = bounds_of_building(&scene, b);
        // Just outside each corner of its box, the ground is within 0.25 m of its base.
        for (x, y) in [(lo[0] - 0.5, lo[1] - 0.5), (hi[0] + 0.5, hi[1] + 0.5)] {
            let z = terrain.ground_height(x, y).unwrap();
            let want = base - scene.origin[2];
            assert!(
                (f64::from(z) - want).abs() < 0.25,
                "{id}: ground {z} at ({x}, {y}), base {want}"
            );
        }
    }
    let (lo, hi) = caster.bounds().unwrap();
    let centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    let start = free_spot(&caster, centre[0], centre[1], 2.0, 100.0);
    assert!(start.is_some(), "no start on the built ground");
    // vehicle_sim's `start` param: empty is that free spot; [x, y] is taken
    // as given; anything else is a clear error.
    assert_eq!(start_spot(&caster, &[]).ok(), start);
    assert_eq!(start_spot(&caster, &[3.0, 4.0]), Ok([3.0, 4.0]));
    let bad = start_spot(&caster, &[1.0, 2.0, 3.0])
        .unwrap_err()
        .to_string();
    assert!(bad.contains("[x, y] or []"), "{bad}");
}

fn bounds_of_building(s: &Scene, b: u32) -> ([f32; 3], [f32; 3]) {
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for t in 0..s.triangles.len() {
        let o = s.triangle_kind(t).unwrap();
        if o.kind != ObjectKind::Building || o.building != b {
            continue;
        }
        for p in s.triangle_corners(t).unwrap() {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    (lo, hi)
}

#[test]
fn city_json_seq_and_tiles_load_as_the_whole_file() {
    let Some(path) = real_file("3dbag_2buildings.city.json") else {
        return;
    };
    let whole = load_scene(path.to_str().unwrap()).unwrap();
    let doc = read_json(&path);
    let dir = temp_dir();
    let seq = dir.path().join("3dbag.city.jsonl");
    std::fs::write(&seq, as_seq(&doc)).unwrap();
    let from_seq = load_scene(seq.to_str().unwrap()).unwrap();
    assert_eq!(from_seq.building_count(), 2);
    assert_eq!(building_triangles(&from_seq), building_triangles(&whole));
    assert_eq!(from_seq.origin, whole.origin);

    let tiles_tmp = temp_dir();
    let tiles_dir = tiles_tmp.path();
    let tiles = as_tiles(&doc, tiles_dir);
    assert_eq!(tiles.len(), 2);
    let list = tiles
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(",");
    for spec in [list, tiles_dir.display().to_string()] {
        let s = load_scene(&spec).unwrap();
        assert_eq!(s.building_count(), 2, "{spec}");
        assert_eq!(building_triangles(&s), building_triangles(&whole));
        assert_eq!(s.origin, whole.origin);
    }
    // A tile in another CRS is refused, naming both.
    let mut other = read_json(&tiles[1]);
    other["metadata"]["referenceSystem"] = json!("https://www.opengis.net/def/crs/EPSG/0/28992");
    std::fs::write(&tiles[1], other.to_string()).unwrap();
    let e = load_scene(&tiles_dir.display().to_string()).unwrap_err();
    assert!(matches!(e, SceneError::TileCrs { .. }), "{e}");
    assert!(
        e.to_string().contains("28992") && e.to_string().contains("7415"),
        "{e}"
    );
}

#[test]
fn files_without_buildings_say_so() {
    let Some(path) = real_file("3dbag_2buildings.city.json") else {
        return;
    };
    let mut doc = read_json(&path);
    doc["CityObjects"] = json!({});
    let dir = temp_dir();
    let empty = dir.path().join("empty.city.json");
    std::fs::write(&empty, doc.to_string()).unwrap();
    let e = load_scene(empty.to_str().unwrap()).unwrap_err().to_string();
    assert!(
        e.contains("empty.city.json") && e.contains("no Building"),
        "{e}"
    );
    doc["version"] = json!("3.0");
    std::fs::write(&empty, doc.to_string()).unwrap();
    let e = load_scene(empty.to_str().unwrap()).unwrap_err().to_string();
    assert!(e.contains("unsupported CityJSON version `3.0`"), "{e}");
}

/// `cjval` from PATH or the test command's `.tools/bin`, if installed.
fn cjval() -> Option<PathBuf> {
    let local = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../.tools/bin/cjval");
    if local.is_file() {
        return Some(local);
    }
    let ok = std::process::Command::new("cjval")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    ok.then(|| PathBuf::from("cjval"))
}

/// Validates `path` with cjval's JSON report (schema, parents and children,
/// vertex indices, semantics; no warnings); prints SKIPPED without cjval.
fn assert_valid(path: &Path) {
    let Some(cjval) = cjval() else {
        eprintln!("SKIPPED: cjval not installed (tests/run_all.sh installs it into .tools)");
        return;
    };
    let out = std::process::Command::new(&cjval)
        .arg("-r")
        .arg(path)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    // cjval exits 0 either way: its verdict is in the report.
    let report: Value = serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("{}: no cjval report ({e}): {text}", path.display()));
    assert_eq!(report["valid"], json!(true), "{}: {text}", path.display());
    assert_eq!(
        report["has_warnings"],
        json!(false),
        "{}: {text}",
        path.display()
    );
}

fn attrs(k: f64) -> Attributes {
    let mut a = Attributes::new();
    a.insert("skyground_completeness_before".into(), json!(0.8 * k));
    a.insert("skyground_completeness_after".into(), json!(0.97 * k));
    a.insert("skyground_strategy".into(), json!("point"));
    a
}

#[test]
fn completeness_models_are_valid_city_json_2() {
    let dir = temp_dir();
    if let Some(path) = real_file("3dbag_2buildings.city.json") {
        let model = read_city_model(std::slice::from_ref(&path)).unwrap();
        let roots = model.roots();
        let root = roots["NL.IMBAG.Pand.0503100000028341-0"];
        assert_eq!(root, "NL.IMBAG.Pand.0503100000028341");
        let by_root = BTreeMap::from([(root.to_string(), attrs(1.0))]);
        let out = annotated_model(&model, &by_root, false);
        let src = read_json(&path);
        // Same transform, CRS and vertex integers as 3DBAG wrote them.
        assert_eq!(out["transform"], src["transform"]);
        assert_eq!(
            out["metadata"]["referenceSystem"],
            src["metadata"]["referenceSystem"]
        );
        let sorted = |v: &Value| {
            let mut v = v.as_array().unwrap().clone();
            v.sort_by_key(|p| p.to_string());
            v
        };
        assert_eq!(sorted(&out["vertices"]), sorted(&src["vertices"]));
        let b = &out["CityObjects"][root]["attributes"];
        assert_eq!(b["skyground_completeness_after"], json!(0.97));
        // 3DBAG's own attributes stay next to ours.
        assert_eq!(
            b["b3_h_maaiveld"],
            src["CityObjects"][root]["attributes"]["b3_h_maaiveld"]
        );
        let file = dir.path().join("3dbag.completeness.city.json");
        std::fs::write(&file, out.to_string()).unwrap();
        assert_valid(&file);
        // Read back, it is the same scene.
        let again = load_scene(file.to_str().unwrap()).unwrap();
        let first = load_scene(path.to_str().unwrap()).unwrap();
        assert_eq!(building_triangles(&again), building_triangles(&first));
    }
    if let Some(path) = real_file("zurich_subset_lod2.json") {
        // CityJSON 1.1 in, 2.0 out.
        let model = read_city_model(&[path]).unwrap();
        let by_root: BTreeMap<String, Attributes> = model
            .roots()
            .values()
            .map(|r| (r.to_string(), attrs(0.5)))
            .collect();
        let out = annotated_model(&model, &by_root, false);
        assert_eq!(out["CityObjects"].as_object().unwrap().len(), 49 + 161);
        let file = dir.path().join("zurich.completeness.city.json");
        std::fs::write(&file, out.to_string()).unwrap();
        assert_valid(&file);
    }
    // A scene that is no city model: its buildings as LoD 2 surfaces.
    let scene = reference_scene(7);
    let by_id = scene
        .building_ids()
        .into_iter()
        .map(|b| (b, attrs(1.0)))
        .collect();
    let out = scene_model(&scene, &by_id, None);
    assert_eq!(
        out["CityObjects"].as_object().unwrap().len(),
        scene.building_count()
    );
    let file = dir.path().join("reference.completeness.city.json");
    std::fs::write(&file, out.to_string()).unwrap();
    assert_valid(&file);
}
