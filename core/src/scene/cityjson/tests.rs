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
    assert_eq!(names, [("b1", 1), ("b1-p", 1), ("terrain", 0)]);
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
    assert!(glo[0] <= -29.0 && ghi[0] >= 51.0 && glo[2] == 0.0 && ghi[2] == 0.0);
    let no_ground = CityJsonOptions { terrain: None };
    let s = parse_cityjson(doc("1.1").as_bytes(), &no_ground).unwrap_or_default();
    assert_eq!(s.object_count(ObjectKind::Ground), 0);
}

#[test]
fn parts_found_through_children_alone() {
    let text = doc("1.1").replace("\"parents\": [\"b1\"], ", "");
    let s = parse_cityjson(text.as_bytes(), &CityJsonOptions { terrain: None }).unwrap_or_default();
    assert_eq!(s.building_count(), 1);
    assert_eq!(s.objects.len(), 2);
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
    assert_eq!(err(nothing), Some(CityJsonError::NoBuildings));
    let huge = doc("2.0").replace(
        "\"scale\": [0.001, 0.001, 0.001]",
        "\"scale\": [1e308, 1e308, 1e308]",
    );
    assert!(matches!(err(&huge), Some(CityJsonError::NonFinite { .. })));
}
