//! Any city layout starts (issue 49, part 4): real LoD2 buildings of
//! Zurich (`../shared/data/real/zurich_subset_lod2.json`) moved into layouts
//! made at test time (not committed; tests/python/city_layouts.py makes the
//! same ones for the demo) — clusters 500 m apart without terrain, a single
//! building, a terrain in another datum, a local frame without a CRS — and
//! synthetic scenes for ground with a hole and the impossible cases.

mod common;

use common::real_file;
use serde_json::{Value, json};
use skyground_core::graph::{GraphParams, GroundGraph};
use skyground_core::io::cityjson::{CityJsonOptions, parse_cityjson, read_city_files_and_crs};
use skyground_core::lidar::Caster;
use skyground_core::scene::{MeshPart, ObjectKind, Scene, SceneBuilder, Window};
use skyground_core::vehicle::{
    START_CLEARANCE_M, StartError, Terrain, Vehicle, VehicleConfig, find_start, free_spot,
    goal_inside_building, start_on_classes,
};

/// Each root Building of a CityJSON document, sorted by id.
fn buildings(doc: &Value) -> Vec<Piece> {
    fn indices(v: &Value, out: &mut Vec<u64>) {
        match v {
            Value::Array(a) => a.iter().for_each(|x| indices(x, out)),
            Value::Number(n) => out.extend(n.as_u64()),
            _ => {}
        }
    }
    fn remap(v: &Value, map: &dyn Fn(u64) -> u64) -> Value {
        match v {
            Value::Array(a) => Value::Array(a.iter().map(|x| remap(x, map)).collect()),
            Value::Number(n) => json!(map(n.as_u64().unwrap())),
            other => other.clone(),
        }
    }
    let objects = doc["CityObjects"].as_object().unwrap();
    let verts = doc["vertices"].as_array().unwrap();
    let t = &doc["transform"];
    let (s, o) = (&t["scale"], &t["translate"]);
    let mut ids: Vec<&String> = objects
        .iter()
        .filter(|(_, o)| o["type"] == "Building")
        .map(|(k, _)| k)
        .collect();
    ids.sort();
    ids.into_iter()
        .map(|id| {
            let mut members = vec![id.clone()];
            for c in objects[id]["children"].as_array().into_iter().flatten() {
                members.push(c.as_str().unwrap().to_string());
            }
            let mut used = Vec::new();
            for m in &members {
                for g in objects[m]["geometry"].as_array().into_iter().flatten() {
                    indices(&g["boundaries"], &mut used);
                }
            }
            used.sort_unstable();
            used.dedup();
            let at = |i: u64| used.binary_search(&i).unwrap() as u64;
            let mut part = serde_json::Map::new();
            for m in &members {
                let mut obj = objects[m].clone();
                let geometry = obj.get_mut("geometry").and_then(Value::as_array_mut);
                for g in geometry.into_iter().flatten() {
                    g["boundaries"] = remap(&g["boundaries"], &at);
                }
                part.insert(m.clone(), obj);
            }
            let real = used
                .iter()
                .map(|&i| {
                    let v = &verts[i as usize];
                    [0, 1, 2].map(|k| {
                        v[k].as_f64().unwrap() * s[k].as_f64().unwrap() + o[k].as_f64().unwrap()
                    })
                })
                .collect();
            (part, real)
        })
        .collect()
}

type Piece = (serde_json::Map<String, Value>, Vec<[f64; 3]>);

/// `b` moved so its footprint box is centred on `(x, y)` and its lowest vertex is at `z`.
fn placed(b: &Piece, x: f64, y: f64, z: f64) -> Piece {
    let (lo, hi) = bounds(&b.1);
    let d = [
        x - (lo[0] + hi[0]) / 2.0,
        y - (lo[1] + hi[1]) / 2.0,
        z - lo[2],
    ];
    let moved = b.1.iter().map(|p| [0, 1, 2].map(|k| p[k] + d[k])).collect();
    (b.0.clone(), moved)
}

fn bounds(ps: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in ps {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// A CityJSON 2.0 document of `pieces` (each indexing its own vertices from
/// 0) in EPSG:2056, or without a CRS, stored in millimetres from `origin`.
fn model(pieces: &[Piece], crs: bool, origin: [f64; 3]) -> Value {
    fn shift(v: &Value, base: u64) -> Value {
        match v {
            Value::Array(a) => Value::Array(a.iter().map(|x| shift(x, base)).collect()),
            Value::Number(n) => json!(n.as_u64().unwrap() + base),
            other => other.clone(),
        }
    }
    let mut objects = serde_json::Map::new();
    let mut vertices: Vec<Value> = Vec::new();
    for (part, real) in pieces {
        let base = vertices.len() as u64;
        for (id, o) in part {
            let mut o = o.clone();
            let geometry = o.get_mut("geometry").and_then(Value::as_array_mut);
            for g in geometry.into_iter().flatten() {
                g["boundaries"] = shift(&g["boundaries"], base);
            }
            objects.insert(id.clone(), o);
        }
        for p in real {
            vertices.push(json!(
                [0, 1, 2].map(|k| ((p[k] - origin[k]) * 1000.0).round() as i64)
            ));
        }
    }
    let mut doc = json!({"type": "CityJSON", "version": "2.0",
        "transform": {"scale": [0.001, 0.001, 0.001], "translate": origin},
        "CityObjects": objects, "vertices": vertices});
    if crs {
        doc["metadata"] = json!({"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/2056"});
    }
    doc
}

/// Zurich's buildings, moved near the middle of the file's own area (LV95).
const AT: [f64; 3] = [2_682_000.0, 1_248_000.0, 410.0];

fn zurich() -> Option<Vec<Piece>> {
    let path = real_file("zurich_subset_lod2.json")?;
    let doc: Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    Some(buildings(&doc))
}

/// 16 buildings in 4 clusters of 4 (2 × 2, 45 m apart) at the corners of a
/// 500 m × 380 m rectangle, each cluster's ground a few metres off the others'.
fn spread(bs: &[Piece]) -> Vec<Piece> {
    let corners = [
        (0.0, 0.0, 0.0),
        (500.0, 0.0, 6.0),
        (0.0, 380.0, -4.0),
        (500.0, 380.0, 3.0),
    ];
    let mut out = Vec::new();
    for (c, (cx, cy, dz)) in corners.into_iter().enumerate() {
        for k in 0..4 {
            let x = AT[0] + cx + 45.0 * (k % 2) as f64;
            let y = AT[1] + cy + 45.0 * (k / 2) as f64;
            out.push(placed(&bs[4 * c + k], x, y, AT[2] + dz));
        }
    }
    out
}

fn scene_of(doc: &Value) -> Scene {
    parse_cityjson(doc.to_string().as_bytes(), &CityJsonOptions::default()).unwrap()
}

/// Points on the scene's ground on a 1 m grid, as a perfectly classified
/// cloud (class 2): what a ground graph needs to follow the ground.
fn ground_points(caster: &Caster) -> Vec<[f32; 3]> {
    let terrain = Terrain::new(caster);
    let (lo, hi) = caster.bounds().unwrap();
    let mut out = Vec::new();
    let mut y = lo[1];
    while y <= hi[1] {
        let mut x = lo[0];
        while x <= hi[0] {
            if let Some(z) = terrain.ground_height(x, y)
                && !goal_inside_building(caster, [x, y, z + 0.5])
            {
                out.push([x, y, z]);
            }
            x += 1.0;
        }
        y += 1.0;
    }
    out
}

/// The xy box of building `b` (1-based).
fn building_box(s: &Scene, b: u32) -> ([f32; 2], [f32; 2]) {
    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    for t in 0..s.triangles.len() {
        let o = s.triangle_kind(t).unwrap();
        if o.kind == ObjectKind::Building && o.building == b {
            for p in s.triangle_corners(t).unwrap() {
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
    }
    (lo, hi)
}

/// The start a vehicle with the default limits takes at `xy`.
fn stands(caster: &Caster, xy: [f32; 2]) -> bool {
    Vehicle::new(VehicleConfig::default(), caster, xy[0], xy[1], 0.0).is_some()
}

#[test]
fn clusters_500_m_apart_without_terrain_stand_on_one_ground_with_a_start() {
    let Some(bs) = zurich() else {
        return;
    };
    let scene = scene_of(&model(&spread(&bs), true, AT.map(f64::floor)));
    assert_eq!(scene.building_count(), 16);
    let caster = Caster::new(&scene).unwrap();
    let (lo, hi) = caster.bounds().unwrap();
    // About 550 m × 430 m of buildings, the built ground 30 m beyond.
    assert!((hi[0] - lo[0] - 614.0).abs() < 20.0 && (hi[1] - lo[1] - 490.0).abs() < 20.0);
    let middle = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    // The old search (rings up to 100 m about the middle) found nothing:
    // the middle of the layout is 150 m from any ground.
    assert_eq!(
        free_spot(&caster, middle[0], middle[1], START_CLEARANCE_M, 100.0),
        None
    );
    let start = find_start(&caster, None).unwrap();
    assert!(stands(&caster, start), "{start:?}");
    // The ground joins every cluster: a ground graph from the start on the
    // ground's own points reaches beside every building.
    let pts = ground_points(&caster);
    let labels = vec![2u8; pts.len()];
    let z = Terrain::new(&caster)
        .ground_height(start[0], start[1])
        .unwrap();
    let g = GroundGraph::build(
        &pts,
        &labels,
        [start[0], start[1], z],
        &GraphParams::default(),
    )
    .unwrap();
    for b in 1..=16 {
        let (blo, bhi) = building_box(&scene, b);
        let beside = [blo[0] - 3.0, (blo[1] + bhi[1]) / 2.0];
        let near = g.nodes_near(beside, 3.0, 1);
        assert!(
            !near.is_empty(),
            "building {b}: no ground node reached beside it at {beside:?}"
        );
    }
}

#[test]
fn a_single_building_starts_beside_it() {
    let Some(bs) = zurich() else {
        return;
    };
    let scene = scene_of(&model(&[placed(&bs[0], AT[0], AT[1], AT[2])], true, AT));
    assert_eq!(scene.building_count(), 1);
    let caster = Caster::new(&scene).unwrap();
    let start = find_start(&caster, None).unwrap();
    assert!(stands(&caster, start));
    // Outside the building (its footprint is no box: the start may be in the box), beside it.
    let z = Terrain::new(&caster)
        .ground_height(start[0], start[1])
        .unwrap();
    assert!(!goal_inside_building(
        &caster,
        [start[0], start[1], z + 0.5]
    ));
    let (lo, hi) = building_box(&scene, 1);
    let gap = [0, 1].map(|k| (lo[k] - start[k]).max(start[k] - hi[k]).max(0.0));
    assert!(
        gap[0].hypot(gap[1]) < 10.0,
        "start {start:?}, building {lo:?}..{hi:?}"
    );
}

/// A CityJSON TINRelief over `[x0, x1] × [y0, y1]` at height `z`, 10 m cells.
fn tin(x0: f64, y0: f64, x1: f64, y1: f64, z: f64) -> Piece {
    let n = [((x1 - x0) / 10.0) as usize, ((y1 - y0) / 10.0) as usize];
    let mut real = Vec::new();
    for j in 0..=n[1] {
        for i in 0..=n[0] {
            real.push([x0 + i as f64 * 10.0, y0 + j as f64 * 10.0, z]);
        }
    }
    let v = |i: usize, j: usize| (j * (n[0] + 1) + i) as u64;
    let mut tris = Vec::new();
    for j in 0..n[1] {
        for i in 0..n[0] {
            tris.push(json!([[v(i, j), v(i + 1, j), v(i + 1, j + 1)]]));
            tris.push(json!([[v(i, j), v(i + 1, j + 1), v(i, j + 1)]]));
        }
    }
    let mut part = serde_json::Map::new();
    part.insert(
        "tin".into(),
        json!({"type": "TINRelief", "geometry": [{"type": "CompositeSurface", "lod": "1", "boundaries": tris}]}),
    );
    (part, real)
}

#[test]
fn a_terrain_in_another_datum_is_moved_to_meet_the_buildings() {
    let Some(bs) = zurich() else {
        return;
    };
    let four: Vec<Piece> = (0..4)
        .map(|k| {
            placed(
                &bs[k],
                AT[0] + 40.0 * (k % 2) as f64,
                AT[1] + 40.0 * (k / 2) as f64,
                AT[2],
            )
        })
        .collect();
    for offset in [-50.0, 30.0] {
        let mut pieces = four.clone();
        pieces.push(tin(
            AT[0] - 60.0,
            AT[1] - 60.0,
            AT[0] + 100.0,
            AT[1] + 100.0,
            AT[2] + offset,
        ));
        let scene = scene_of(&model(
            &pieces,
            true,
            [AT[0] - 60.0, AT[1] - 60.0, AT[2] - 60.0],
        ));
        let caster = Caster::new(&scene).unwrap();
        let terrain = Terrain::new(&caster);
        let base = (AT[2] - scene.origin[2]) as f32;
        // Beside each building and far from them, the ground is at the bases' height.
        for b in 1..=4 {
            let (lo, _) = building_box(&scene, b);
            let z = terrain.ground_height(lo[0] - 2.0, lo[1] - 2.0).unwrap();
            assert!(
                (z - base).abs() < 0.3,
                "offset {offset}: ground {z} beside {b}, base {base}"
            );
        }
        let (lo, _) = caster.bounds().unwrap();
        let z = terrain.ground_height(lo[0] + 5.0, lo[1] + 5.0).unwrap();
        assert!(
            (z - base).abs() < 0.3,
            "offset {offset}: the file's ground at {z}, base {base}"
        );
        let start = find_start(&caster, None).unwrap();
        assert!(stands(&caster, start));
    }
}

#[test]
fn a_local_frame_without_a_crs_starts() {
    let Some(bs) = zurich() else {
        return;
    };
    // The spread layout with coordinates from about (20, 20, 0): an engineering frame.
    let local: Vec<Piece> = spread(&bs)
        .into_iter()
        .map(|(part, real)| {
            let moved = real
                .iter()
                .map(|p| [p[0] - AT[0] + 60.0, p[1] - AT[1] + 60.0, p[2] - AT[2]])
                .collect();
            (part, moved)
        })
        .collect();
    let doc = model(&local, false, [0.0; 3]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("local.city.json");
    std::fs::write(&path, doc.to_string()).unwrap();
    let (scene, crs) = read_city_files_and_crs(&[path], &CityJsonOptions::default()).unwrap();
    assert_eq!(crs, None);
    assert!(
        scene.origin.iter().all(|v| v.abs() < 100.0),
        "{:?}",
        scene.origin
    );
    let caster = Caster::new(&scene).unwrap();
    assert!(stands(&caster, find_start(&caster, None).unwrap()));
}

/// A closed box as a mesh part.
fn block(x0: f64, y0: f64, x1: f64, y1: f64, z0: f64, h: f64) -> MeshPart {
    let mut m = MeshPart::default();
    let xy = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
    let lo = m.ring(&xy, z0);
    let hi = m.ring(&xy, z0 + h);
    m.walls(&lo, &hi);
    m.cap(&[&hi], true);
    m.cap(&[&lo], false);
    m
}

/// Flat ground over `outer` with the square `hole` (both x0, y0, x1, y1) left out, at z = 0.
fn ground_with_hole(outer: [f64; 4], hole: Option<[f64; 4]>) -> MeshPart {
    let mut m = MeshPart::default();
    let step = 10.0;
    let mut y = outer[1];
    while y < outer[3] {
        let mut x = outer[0];
        while x < outer[2] {
            let (cx, cy) = (x + step / 2.0, y + step / 2.0);
            let in_hole = hole.is_some_and(|h| h[0] < cx && cx < h[2] && h[1] < cy && cy < h[3]);
            if !in_hole {
                let r = m.ring(
                    &[[x, y], [x + step, y], [x + step, y + step], [x, y + step]],
                    0.0,
                );
                m.quad(r[0], r[1], r[2], r[3]);
            }
            x += step;
        }
        y += step;
    }
    m
}

#[test]
fn ground_with_a_hole_in_its_middle_starts_at_its_nearest_edge() {
    // A square of ground 400 m across round a 260 m pond, a building at each corner.
    let mut b = SceneBuilder::new([0.0; 3]);
    b.add(
        "terrain",
        ObjectKind::Ground,
        0,
        &ground_with_hole([0.0, 0.0, 400.0, 400.0], Some([70.0, 70.0, 330.0, 330.0])),
    );
    for (k, (x, y)) in [(10.0, 10.0), (370.0, 10.0), (10.0, 370.0), (370.0, 370.0)]
        .into_iter()
        .enumerate()
    {
        b.add(
            format!("building_{k}"),
            ObjectKind::Building,
            k as u32 + 1,
            &block(x, y, x + 20.0, y + 20.0, 0.0, 10.0),
        );
    }
    let scene = b.finish();
    let caster = Caster::new(&scene).unwrap();
    assert_eq!(
        free_spot(&caster, 200.0, 200.0, START_CLEARANCE_M, 100.0),
        None
    );
    let start = find_start(&caster, None).unwrap();
    assert!(stands(&caster, start));
    // The nearest ground to the middle is the pond's edge, 130 m off.
    let d = (start[0] - 200.0).hypot(start[1] - 200.0);
    assert!(
        (130.0..140.0).contains(&d),
        "start {start:?}, {d} m from the middle"
    );
}

#[test]
fn no_ground_and_no_room_say_why() {
    // Buildings only: no ground object at all.
    let mut b = SceneBuilder::new([0.0; 3]);
    b.add(
        "building_1",
        ObjectKind::Building,
        1,
        &block(0.0, 0.0, 20.0, 20.0, 0.0, 10.0),
    );
    let caster = Caster::new(&b.finish()).unwrap();
    let e = find_start(&caster, None).unwrap_err();
    assert_eq!(e, StartError::NoGround);
    assert!(e.to_string().contains("no ground"), "{e}");
    // A city model read without its built ground: the same.
    if let Some(bs) = zurich() {
        let doc = model(&[placed(&bs[0], AT[0], AT[1], AT[2])], true, AT);
        let bare = parse_cityjson(
            doc.to_string().as_bytes(),
            &CityJsonOptions { terrain: None },
        )
        .unwrap();
        let caster = Caster::new(&bare).unwrap();
        assert_eq!(find_start(&caster, None), Err(StartError::NoGround));
    }
    // Ground only under and tight about a building: no spot has 2 m of room.
    let mut b = SceneBuilder::new([0.0; 3]);
    b.add(
        "terrain",
        ObjectKind::Ground,
        0,
        &ground_with_hole([0.0, 0.0, 30.0, 30.0], None),
    );
    b.add(
        "building_1",
        ObjectKind::Building,
        1,
        &block(1.3, 1.3, 28.7, 28.7, 0.0, 10.0),
    );
    let caster = Caster::new(&b.finish()).unwrap();
    let e = find_start(&caster, None).unwrap_err();
    let StartError::NoFreeSpot {
        on_ground,
        inside,
        crowded,
        ..
    } = e
    else {
        panic!("{e}");
    };
    assert_eq!(on_ground, inside + crowded);
    assert!(inside > 0 && crowded > 0, "{e}");
    assert!(e.to_string().contains("inside buildings"), "{e}");
    let empty = Caster::new(&Scene::default());
    if let Ok(c) = empty {
        assert_eq!(find_start(&c, None), Err(StartError::EmptyScene));
    }
}

#[test]
fn on_a_classified_prior_the_start_is_on_the_largest_ground() {
    // Two pieces of ground 60 m apart: 40 m × 40 m and 120 m × 120 m.
    let mut b = SceneBuilder::new([0.0; 3]);
    b.add(
        "small",
        ObjectKind::Ground,
        0,
        &ground_with_hole([0.0, 0.0, 40.0, 40.0], None),
    );
    b.add(
        "large",
        ObjectKind::Ground,
        0,
        &ground_with_hole([100.0, 0.0, 220.0, 120.0], None),
    );
    let scene = b.finish();
    let caster = Caster::new(&scene).unwrap();
    let pts = ground_points(&caster);
    let labels = vec![2u8; pts.len()];
    let extent = Window::new(0.0, 0.0, 220.0, 120.0).unwrap();
    let s = start_on_classes(&caster, &pts, &labels, &extent, &GraphParams::default()).unwrap();
    assert!(s.at[0] > 100.0, "{s:?}");
    // 1 point a m² gives 2.5 m nodes: 48 × 48 on the large piece, 16 × 16 on the small.
    assert_eq!(s.nodes, 48 * 48, "{s:?}");
    // A prior without ground points says so.
    let none = vec![1u8; pts.len()];
    let e = start_on_classes(&caster, &pts, &none, &extent, &GraphParams::default()).unwrap_err();
    assert!(e.to_string().contains("no ground points"), "{e}");
}
