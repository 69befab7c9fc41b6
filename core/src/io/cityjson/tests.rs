//! CityJSON reader on small hand-written documents.

use super::*;

/// A 2.0 document: a Building with a LoD1 Solid cube and a LoD2 MultiSurface
/// (a box whose south wall has a window hole), one BuildingPart, and a road.
fn doc(version: &str) -> String {
    format!(
        r#"{{"type": "CityJSON", "version": "{version}",
  "transform": {{"scale": [0.001, 0.001, 0.001], "translate": [84000.5, 447000.25, 1.0]}},
  "CityObjects": {{
    "b1": {{"type": "Building", "children": ["b1-p"], "geometry": [
      {{"type": "Solid", "lod": "1", "boundaries": [[[[0,3,2,1]],[[4,5,6,7]],[[0,1,5,4]],[[1,2,6,5]],[[2,3,7,6]],[[3,0,4,7]]]]}},
      {{"type": "MultiSurface", "lod": "2.2", "boundaries": [[[0,3,2,1]],[[4,5,6,7]],[[0,1,5,4],[8,9,10,11]],[[1,2,6,5]],[[2,3,7,6]],[[3,0,4,7]]]}}
    ]}},
    "b1-p": {{"type": "BuildingPart", "parents": ["b1"], "geometry": [
      {{"type": "MultiSurface", "lod": 2, "boundaries": [[[12,13,14]]]}}
    ]}},
    "road": {{"type": "Road", "geometry": [{{"type": "MultiSurface", "lod": "1", "boundaries": [[[0,1,2]]]}}]}}
  }},
  "vertices": [
    [0,0,0],[10000,0,0],[10000,10000,0],[0,10000,0],
    [0,0,5000],[10000,0,5000],[10000,10000,5000],[0,10000,5000],
    [2000,0,1000],[2000,0,3000],[4000,0,3000],[4000,0,1000],
    [20000,0,0],[21000,0,0],[20000,1000,0]
  ]
}}"#
    )
}

#[test]
fn highest_lod_parts_merged_holes_triangulated() {
    let s = parse_cityjson(doc("2.0").as_bytes(), &CityJsonOptions::default()).unwrap_or_default();
    assert_eq!(s.building_count(), 1);
    let names: Vec<(&str, u32)> = s
        .objects
        .iter()
        .map(|o| (o.name.as_str(), o.building))
        .collect();
    // The road is ground; the built terrain sits 5 cm under it.
    assert_eq!(names, [("b1", 1), ("b1-p", 1), ("road", 0), ("terrain", 0)]);
    assert_eq!(s.origin, [84000.0, 447000.0, 1.0]);
    // LoD2 box: 5 quads (10 triangles) + a wall with a window (8 triangles).
    assert_eq!(s.object_triangles(0).count(), 18);
    let area: f64 = s.object_triangles(0).map(|t| s.triangle_area(t)).sum();
    assert!(
        (area - (2.0 * 100.0 + 4.0 * 50.0 - 4.0)).abs() < 1e-3,
        "area {area}"
    );
    // Outward normals: the south wall (with the window) faces -y.
    let mut south = 0;
    for t in s.object_triangles(0) {
        let [a, b, c] = s.triangle_corners(t).unwrap_or_default();
        if a[1] == 0.25 && b[1] == 0.25 && c[1] == 0.25 {
            let n_y = (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]);
            assert!(n_y < 0.0, "south wall triangle faces +y");
            south += 1;
        }
    }
    assert_eq!(south, 8);
    let (lo, _) = s
        .bounds_of(|k| k == ObjectKind::Building)
        .unwrap_or_default();
    assert_eq!(lo, [0.5, 0.25, 0.0]);
    let (glo, ghi) = s.bounds_of(|k| k == ObjectKind::Ground).unwrap_or_default();
    assert!(glo[0] <= -29.0 && ghi[0] >= 51.0, "{glo:?} {ghi:?}");
    assert!(
        (glo[2] + 0.05).abs() < 1e-6 && ghi[2] == 0.0,
        "{glo:?} {ghi:?}"
    );
    let no_ground = CityJsonOptions { terrain: None };
    let s = parse_cityjson(doc("1.1").as_bytes(), &no_ground).unwrap_or_default();
    // Only the file's own ground (the road), nothing built.
    assert_eq!(s.object_count(ObjectKind::Ground), 1);
    assert!(!s.objects.iter().any(|o| o.name == "terrain"));
}

#[test]
fn parts_found_through_children_alone() {
    let text = doc("1.1").replace("\"parents\": [\"b1\"], ", "");
    let s = parse_cityjson(text.as_bytes(), &CityJsonOptions { terrain: None }).unwrap_or_default();
    assert_eq!(s.building_count(), 1);
    assert_eq!(s.object_count(ObjectKind::Building), 2);
}

#[test]
fn version_1_0_plain_vertices() {
    let text = r#"{"type": "CityJSON", "version": "1.0", "CityObjects": {
        "a": {"type": "Building", "geometry": [{"type": "CompositeSurface", "lod": 2, "boundaries": [[[0,1,2,3]]]}]}},
        "vertices": [[1.5, 2.5, 3.0], [11.5, 2.5, 3.0], [11.5, 12.5, 3.0], [1.5, 12.5, 3.0]]}"#;
    let s = parse_cityjson(text.as_bytes(), &CityJsonOptions { terrain: None }).unwrap_or_default();
    assert_eq!(s.triangles.len(), 2);
    assert_eq!(s.origin, [1.0, 2.0, 3.0]);
}

fn err(text: &str) -> Option<CityJsonError> {
    parse_cityjson(text.as_bytes(), &CityJsonOptions::default()).err()
}

#[test]
fn errors_are_typed() {
    assert!(matches!(
        err("{\"type\": \"CityJSON\",\n \"vertices\": [1,2]}"),
        Some(CityJsonError::Json { line: 2, .. })
    ));
    assert!(matches!(
        err("{\"type\": \"FeatureCollection\"}"),
        Some(CityJsonError::NotCityJson { .. })
    ));
    assert!(matches!(
        err(&doc("3.0")),
        Some(CityJsonError::Version { .. })
    ));
    let bad_index = doc("2.0").replace("[[[12,13,14]]]", "[[[12,13,99]]]");
    assert_eq!(
        err(&bad_index),
        Some(CityJsonError::VertexIndex {
            object: "b1-p".into(),
            index: 99,
            vertices: 15
        })
    );
    let bad_nesting = doc("2.0").replace("[[[12,13,14]]]", "[[12,13,14]]");
    assert!(matches!(
        err(&bad_nesting),
        Some(CityJsonError::Boundaries { .. })
    ));
    let negative = doc("2.0").replace("[[[12,13,14]]]", "[[[12,-13,14]]]");
    assert!(matches!(
        err(&negative),
        Some(CityJsonError::Boundaries { .. })
    ));
    let nothing = r#"{"type": "CityJSON", "version": "2.0", "CityObjects": {}, "vertices": []}"#;
    assert_eq!(
        err(nothing),
        Some(CityJsonError::NoBuildings { ground_objects: 0 })
    );
    let huge = doc("2.0").replace(
        "\"scale\": [0.001, 0.001, 0.001]",
        "\"scale\": [1e308, 1e308, 1e308]",
    );
    assert!(matches!(err(&huge), Some(CityJsonError::NonFinite { .. })));
    let flat = doc("2.0").replace(
        "\"scale\": [0.001, 0.001, 0.001]",
        "\"scale\": [0.001, 0.0, 0.001]",
    );
    assert_eq!(err(&flat), Some(CityJsonError::Transform));
}

/// A CityJSONSeq stream of `doc`: the header, then one feature per building
/// with its own vertices.
fn seq(version: &str) -> String {
    let d: serde_json::Value = serde_json::from_str(&doc(version)).unwrap_or_default();
    let header = serde_json::json!({"type": "CityJSON", "version": version,
        "transform": d["transform"], "CityObjects": {}, "vertices": []});
    let v = d["vertices"].as_array().cloned().unwrap_or_default();
    let feature = serde_json::json!({"type": "CityJSONFeature", "id": "b1",
        "CityObjects": {"b1": d["CityObjects"]["b1"], "b1-p": d["CityObjects"]["b1-p"]},
        "vertices": v});
    // A second feature whose object indexes its own vertices from 0.
    let second = serde_json::json!({"type": "CityJSONFeature", "id": "b2",
        "CityObjects": {"b2": {"type": "Building", "geometry": [
            {"type": "MultiSurface", "lod": "1.2", "boundaries": [[[0, 1, 2]]]}]}},
        "vertices": [[50000, 0, 0], [51000, 0, 0], [50000, 1000, 0]]});
    format!("{header}\n{feature}\n\n{second}\n")
}

#[test]
fn city_json_seq_features_keep_their_own_vertices() {
    let no_ground = CityJsonOptions { terrain: None };
    let s = parse_cityjson(seq("2.0").as_bytes(), &no_ground).unwrap_or_default();
    assert_eq!(s.building_count(), 2);
    let whole = parse_cityjson(doc("2.0").as_bytes(), &no_ground).unwrap_or_default();
    // b1 and its part as in the whole file; b2 (its own vertex 0) 50 m east.
    assert_eq!(
        s.object_triangles(0).count(),
        whole.object_triangles(0).count()
    );
    let b2 = s.objects.iter().position(|o| o.name == "b2").unwrap_or(0) as u32;
    let t = s.object_triangles(b2).next().unwrap_or(0);
    let [a, _, _] = s.triangle_corners(t).unwrap_or_default();
    assert_eq!(a[0], 50.0 + 84000.5 - 84000.0);
    let mut bad = seq("2.0");
    let at = bad.rfind("CityJSONFeature").unwrap_or(0);
    bad.replace_range(at..at + "CityJSONFeature".len(), "Feature");
    assert_eq!(
        parse_cityjson(bad.as_bytes(), &no_ground).err(),
        Some(CityJsonError::NotFeature {
            line: 4,
            found: "Feature".into()
        })
    );
    // Without the header's transform the integers would be read as metres
    // (one "building" kilometres across): refused.
    let text = seq("2.0");
    let mut lines: Vec<serde_json::Value> = text
        .lines()
        .filter(|l| !l.is_empty())
        .map(|l| serde_json::from_str(l).unwrap_or_default())
        .collect();
    if let Some(h) = lines[0].as_object_mut() {
        h.remove("transform");
    }
    let untransformed: Vec<String> = lines.iter().map(ToString::to_string).collect();
    assert_eq!(
        parse_cityjson(untransformed.join("\n").as_bytes(), &no_ground).err(),
        Some(CityJsonError::SeqWithoutTransform)
    );
    let past_range = seq("2.0")
        .replace("[[[0, 1, 2]]]", "[[[0, 1, 3]]]")
        .replace("[[[0,1,2]]]", "[[[0,1,3]]]");
    assert!(matches!(
        parse_cityjson(past_range.as_bytes(), &no_ground).err(),
        Some(CityJsonError::VertexIndex {
            index: 3,
            vertices: 3,
            ..
        })
    ));
}

#[test]
fn ground_stands_on_the_base_vertices() {
    // b1's lowest vertices are at z = 1 (stored 0): the ground under and
    // around it is there too.
    let s = parse_cityjson(
        doc("2.0")
            .replace(
                "\"road\": {\"type\": \"Road\"",
                "\"road\": {\"type\": \"Bridge\"",
            )
            .as_bytes(),
        &CityJsonOptions::default(),
    )
    .unwrap_or_default();
    assert_eq!(s.object_count(ObjectKind::Ground), 1);
    let (glo, ghi) = s.bounds_of(|k| k == ObjectKind::Ground).unwrap_or_default();
    assert!(
        glo[2].abs() < 1e-6 && ghi[2].abs() < 1e-6,
        "{glo:?} {ghi:?}"
    );
}

#[test]
fn base_vertices_are_under_walls() {
    // A box (0..10, z 0..5) with a tower (4..6, z 5..9) standing on its roof,
    // and a roof ridge vertex with nothing under it.
    let v = [
        [0.0, 0.0, 0.0],
        [10.0, 0.0, 0.0],
        [0.0, 0.0, 5.0],
        [10.0, 0.0, 5.0],
        [4.0, 4.0, 5.0],
        [4.0, 4.0, 9.0],
        [5.0, 5.0, 7.0],
    ];
    let used: Vec<usize> = (0..v.len()).collect();
    assert_eq!(base_vertices(&used, &v), [0, 1]);
}

#[test]
fn written_model_keeps_buildings_and_adds_attributes() {
    let text = doc("1.1").replace("\"type\": \"Road\"", "\"type\": \"Bridge\"");
    let model = parse_city_model(text.as_bytes()).unwrap_or_default();
    let mut attrs = std::collections::BTreeMap::new();
    let mut a = Attributes::new();
    a.insert(
        "skyground_completeness_after".into(),
        serde_json::json!(0.97),
    );
    attrs.insert("b1".to_string(), a);
    let out = annotated_model(&model, &attrs, false);
    assert_eq!(out["version"], "2.0");
    assert_eq!(
        out["CityObjects"]["b1"]["attributes"]["skyground_completeness_after"],
        0.97
    );
    assert_eq!(
        out["CityObjects"]["b1-p"]["parents"],
        serde_json::json!(["b1"])
    );
    assert_eq!(
        out["CityObjects"]["b1"]["children"],
        serde_json::json!(["b1-p"])
    );
    assert!(out["CityObjects"].get("road").is_none());
    // Both of b1's geometries, same transform: the same integers come back.
    assert_eq!(
        out["CityObjects"]["b1"]["geometry"]
            .as_array()
            .map(Vec::len),
        Some(2)
    );
    assert_eq!(
        out["transform"]["translate"],
        serde_json::json!([84000.5, 447000.25, 1.0])
    );
    let again = parse_cityjson(
        out.to_string().as_bytes(),
        &CityJsonOptions { terrain: None },
    )
    .unwrap_or_default();
    let first =
        parse_cityjson(text.as_bytes(), &CityJsonOptions { terrain: None }).unwrap_or_default();
    assert_eq!(again.vertices.len(), first.vertices.len());
    assert_eq!(again.triangles, first.triangles);
    assert_eq!(again.origin, first.origin);
}

#[test]
fn crs_names_compare_by_code() {
    assert_eq!(
        crs_key("https://www.opengis.net/def/crs/EPSG/0/7415"),
        "EPSG:7415"
    );
    assert_eq!(crs_key("urn:ogc:def:crs:EPSG::7415"), "EPSG:7415");
    assert_eq!(
        crs_url("EPSG:2056"),
        "https://www.opengis.net/def/crs/EPSG/0/2056"
    );
    assert_ne!(crs_key("EPSG:2056"), crs_key("EPSG:7415"));
}

/// `doc` with its transform in US survey feet and a CRS in them (NAD83 /
/// New York Long Island ftUS), `unit` metres per foot.
fn in_feet(unit: f64) -> String {
    let mut d: serde_json::Value = serde_json::from_str(&doc("2.0")).unwrap_or_default();
    d["transform"] = serde_json::json!({
        "scale": [0.001 / unit, 0.001 / unit, 0.001 / unit],
        "translate": [84000.5 / unit, 447000.25 / unit, 1.0 / unit],
    });
    d["metadata"] =
        serde_json::json!({"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/2263"});
    d.to_string()
}

#[test]
fn a_model_in_feet_is_read_in_metres() {
    let us_foot = 1200.0 / 3937.0;
    let model = parse_city_model(in_feet(us_foot).as_bytes()).unwrap_or_default();
    assert_eq!(model.crs().and_then(|c| c.epsg), Some(2263));
    assert!((model.to_metre()[0] - us_foot).abs() < 1e-12);
    let feet = parse_cityjson(in_feet(us_foot).as_bytes(), &CityJsonOptions::default())
        .unwrap_or_default();
    let metres =
        parse_cityjson(doc("2.0").as_bytes(), &CityJsonOptions::default()).unwrap_or_default();
    // Same frame and the same building, 10 m × 10 m × 5 m, not 3.3 times it.
    assert_eq!(feet.origin, metres.origin);
    assert_eq!(feet.vertices.len(), metres.vertices.len());
    for (a, b) in feet.vertices.iter().zip(&metres.vertices) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 1e-3, "{a:?} vs {b:?}");
        }
    }
    // Read as if in metres, the same file would be 3.28 times larger.
    let mut unnamed: serde_json::Value =
        serde_json::from_str(&in_feet(us_foot)).unwrap_or_default();
    unnamed["metadata"] = serde_json::json!({});
    let raw = parse_cityjson(unnamed.to_string().as_bytes(), &CityJsonOptions::default())
        .unwrap_or_default();
    let area = |s: &Scene| -> f64 { s.object_triangles(0).map(|t| s.triangle_area(t)).sum() };
    assert!((area(&feet) - (2.0 * 100.0 + 4.0 * 50.0 - 4.0)).abs() < 1e-2);
    assert!((area(&raw) / area(&feet) * us_foot * us_foot - 1.0).abs() < 1e-3);
}

#[test]
fn a_scene_loads_with_its_models_crs_from_one_read() {
    let dir = std::env::temp_dir().join(format!("skyground-scene-crs-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let feet = dir.join("feet.city.json");
    let plain = dir.join("plain.city.json");
    let wrote = std::fs::write(&feet, in_feet(1200.0 / 3937.0))
        .and_then(|()| std::fs::write(&plain, doc("2.0")));
    let load = |p: &std::path::Path| crate::io::load_scene_and_crs(&p.display().to_string());
    let (named, unnamed) = (load(&feet), load(&plain));
    let scene_alone = read_city_files(std::slice::from_ref(&feet), &CityJsonOptions::default());
    let reference = crate::io::load_scene_and_crs("reference");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(wrote.is_ok());
    let (scene, crs) = named.expect("a model in feet loads");
    assert_eq!(crs.and_then(|c| c.epsg), Some(2263));
    // The same scene read_city_files gives (in metres).
    assert!(scene_alone.is_ok_and(|s| s == scene));
    assert!(!scene.vertices.is_empty());
    assert!(matches!(unnamed, Ok((_, None))), "a model naming no CRS");
    assert!(matches!(reference, Ok((_, None))));
}
