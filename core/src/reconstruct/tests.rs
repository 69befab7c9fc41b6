//! Synthetic buildings with known truth: a gable house and an L-shaped
//! block with a courtyard-free tower, sampled as a cloud (complete, and
//! with the south walls missing).

use super::*;
use crate::io::cityjson::models as cityjson;
use crate::io::obj::models as obj;
use crate::metrics::sample_building_surfaces;
use crate::scene::reference::solids::{Rect, gable_house, podium_with_towers, prism};
use crate::scene::{MeshPart, ObjectKind, Scene, SceneBuilder};

fn scene() -> Scene {
    let mut g = MeshPart::default();
    let r = g.ring(
        &[[-30.0, -30.0], [70.0, -30.0], [70.0, 70.0], [-30.0, 70.0]],
        0.0,
    );
    g.quad(r[0], r[1], r[2], r[3]);
    let mut b = SceneBuilder::new([0.0; 3]);
    b.add("terrain", ObjectKind::Ground, 0, &g);
    b.add(
        "building_01_gable",
        ObjectKind::Building,
        1,
        &gable_house(Rect::at(0.0, 0.0, 16.0, 10.0), -0.5, 6.0, 9.0, true),
    );
    let l = [
        [25.0, 0.0],
        [45.0, 0.0],
        [45.0, 8.0],
        [33.0, 8.0],
        [33.0, 20.0],
        [25.0, 20.0],
    ];
    b.add(
        "building_02_l",
        ObjectKind::Building,
        2,
        &prism(&l, &[], -0.5, 10.0),
    );
    b.add(
        "building_03_podium",
        ObjectKind::Building,
        3,
        &podium_with_towers(
            Rect::at(0.0, 30.0, 30.0, 20.0),
            -0.5,
            5.0,
            &[(Rect::at(4.0, 34.0, 8.0, 8.0), 20.0)],
        ),
    );
    b.finish()
}

/// The scene's building surfaces as a cloud with ±3 cm noise, plus ground
/// points; `keep` decides which building samples (position, normal) stay.
fn cloud(scene: &Scene, keep: impl Fn([f32; 3], [f32; 3]) -> bool) -> Cloud {
    let gt = sample_building_surfaces(scene, 0.3);
    let mut xyz = Vec::new();
    let mut label = Vec::new();
    for (k, (p, n)) in gt.xyz.iter().zip(&gt.normal).enumerate() {
        if !keep(*p, *n) {
            continue;
        }
        let h = |s: usize| ((k * 7919 + s * 104_729) % 1000) as f32 / 1000.0 * 0.06 - 0.03;
        xyz.push([p[0] + h(1), p[1] + h(2), p[2] + h(3)]);
        label.push(class::BUILDING);
    }
    let fp = crate::footprint::footprints_of_scene(scene);
    for i in 0..200 {
        for j in 0..200 {
            let (x, y) = (-30.0 + i as f64 * 0.5, -30.0 + j as f64 * 0.5);
            let inside = fp
                .iter()
                .any(|f| geo::Contains::contains(&f.polygon, &geo::Coord { x, y }));
            if !inside {
                xyz.push([x as f32, y as f32, 0.0]);
                label.push(class::GROUND);
            }
        }
    }
    Cloud {
        xyz,
        label: Some(label),
        ..Cloud::default()
    }
}

#[test]
fn complete_cloud_gives_closed_accurate_models() {
    let s = scene();
    let rec =
        reconstruct_cloud(&cloud(&s, |_, _| true), None, &ReconstructParams::default()).unwrap();
    assert_eq!(rec.models.len(), 3, "skipped: {:?}", rec.skipped);
    for m in &rec.models {
        let c = m.shell.check();
        assert!(c.valid(), "building {}: {c:?}", m.id);
        // Samples every 0.3 m: 11 per m² in plan on flat roofs, more on slopes.
        let d = m.roof_density.unwrap();
        assert!((8.0..30.0).contains(&d), "building {}: {d}", m.id);
    }
    let gt = sample_building_surfaces(&s, 0.25);
    let e = evaluate_models(&s, &gt, &rec, 0.25);
    for b in &e.buildings {
        assert!(b.distance.mean.unwrap() < 0.08, "{b:?}");
        assert!(b.footprint_iou.unwrap() > 0.97, "{b:?}");
        assert!(b.roof_error.unwrap() < 0.06, "{b:?}");
        assert!(b.watertight);
    }
    assert!(e.all_valid && e.without_model.is_empty() && e.unmatched_models.is_empty());
    let pts: Vec<[f32; 3]> = gt.xyz.clone();
    let (d, n) = evaluate::points_to_models(&rec, &pts).unwrap();
    assert!(d < 0.06 && n == pts.len(), "{d} {n}");
}

#[test]
fn missing_walls_leave_the_model_less_accurate() {
    let s = scene();
    let params = ReconstructParams::default();
    // Before: no south- or east-facing wall points (occluded from the flight lines).
    let before = cloud(&s, |_, n| n[1] > -0.5 && n[0] < 0.5);
    let after = cloud(&s, |_, _| true);
    let gt = sample_building_surfaces(&s, 0.25);
    let eb = evaluate_models(
        &s,
        &gt,
        &reconstruct_cloud(&before, None, &params).unwrap(),
        0.25,
    );
    let ea = evaluate_models(
        &s,
        &gt,
        &reconstruct_cloud(&after, None, &params).unwrap(),
        0.25,
    );
    assert!(eb.all_watertight && ea.all_watertight);
    for (b, a) in eb.buildings.iter().zip(&ea.buildings) {
        assert!(
            a.distance.mean.unwrap() < b.distance.mean.unwrap(),
            "after {a:?}\nbefore {b:?}"
        );
    }
}

#[test]
fn a_cloud_labelled_only_unclassified_uses_all_its_points() {
    // A scanner's LAS: every point class 0 or 1. `--help` says all points
    // are used; before, it gave 0 models and no error.
    let s = scene();
    let mut c = cloud(&s, |_, _| true);
    let keep: Vec<bool> = c
        .label
        .iter()
        .flatten()
        .map(|&l| l == class::BUILDING)
        .collect();
    c.xyz = c
        .xyz
        .iter()
        .zip(&keep)
        .filter(|(_, k)| **k)
        .map(|(p, _)| *p)
        .collect();
    for code in [class::CREATED, class::UNCLASSIFIED] {
        c.label = Some(vec![code; c.xyz.len()]);
        let rec = reconstruct_cloud(&c, None, &ReconstructParams::default()).unwrap();
        assert_eq!(
            rec.models.len(),
            3,
            "class {code}: skipped {:?}",
            rec.skipped
        );
    }
}

#[test]
fn bad_input_is_typed() {
    let empty = Cloud::from_xyz(Vec::new());
    assert!(matches!(
        reconstruct_cloud(&empty, None, &ReconstructParams::default()),
        Err(ReconstructError::NoBuildingPoints)
    ));
    // A classified tile without buildings is no error: it has no models.
    let mut field = Cloud::from_xyz(vec![[0.0, 0.0, 0.0], [5.0, 5.0, 0.1]]);
    field.label = Some(vec![class::GROUND, class::GROUND]);
    let rec = reconstruct_cloud(&field, None, &ReconstructParams::default())
        .expect("no buildings, no models");
    assert!(rec.models.is_empty() && rec.skipped.is_empty());
    let doc = cityjson::to_cityjson(&rec);
    assert_eq!(doc["CityObjects"].as_object().map(|o| o.len()), Some(0));
    assert!(doc["metadata"].get("geographicalExtent").is_none());
    let bad = ReconstructParams {
        cell_m: 0.0,
        ..ReconstructParams::default()
    };
    let e = reconstruct_cloud(&Cloud::from_xyz(vec![[0.0; 3]; 10]), None, &bad).unwrap_err();
    assert!(e.to_string().contains("cell_m"), "{e}");
}

#[test]
fn models_are_written_in_the_clouds_unit_with_its_crs() {
    let s = scene();
    let metres =
        reconstruct_cloud(&cloud(&s, |_, _| true), None, &ReconstructParams::default()).unwrap();
    let mut feet = metres.clone();
    feet.crs = Some(crate::crs::Crs::from_epsg(6880).unwrap());
    let ft = crate::crs::US_SURVEY_FOOT_M;
    let (m, f) = (cityjson::to_cityjson(&metres), cityjson::to_cityjson(&feet));
    assert!(m["metadata"].get("referenceSystem").is_none());
    assert_eq!(
        f["metadata"]["referenceSystem"],
        "https://www.opengis.net/def/crs/EPSG/0/6880"
    );
    let extent = |v: &serde_json::Value| -> Vec<f64> {
        v["metadata"]["geographicalExtent"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    for (a, b) in extent(&m).iter().zip(extent(&f)) {
        assert!(
            (a / ft - b).abs() < 0.01,
            "{a} m is {} ft, written {b}",
            a / ft
        );
    }
    let first_v = |text: String| -> Vec<f64> {
        let line = text
            .lines()
            .find(|l| l.starts_with("v "))
            .unwrap()
            .to_owned();
        line[2..].split(' ').map(|x| x.parse().unwrap()).collect()
    };
    let (vm, vf) = (
        first_v(obj::obj_text(&metres)),
        first_v(obj::obj_text(&feet)),
    );
    for (a, b) in vm.iter().zip(&vf) {
        assert!((a / ft - b).abs() < 0.01, "OBJ: {a} m written as {b} ft");
    }
}

#[test]
fn cityjson_has_one_solid_per_building_with_semantics() {
    let s = scene();
    let mut c = cloud(&s, |_, _| true);
    c.set_crs(crate::crs::Crs::from_epsg(28992).unwrap());
    let rec = reconstruct_cloud(&c, None, &ReconstructParams::default()).unwrap();
    let v = cityjson::to_cityjson(&rec);
    assert_eq!(v["version"], "2.0");
    assert_eq!(
        v["metadata"]["referenceSystem"],
        "https://www.opengis.net/def/crs/EPSG/0/28992"
    );
    let objs = v["CityObjects"].as_object().unwrap();
    assert_eq!(objs.len(), 3);
    let nv = v["vertices"].as_array().unwrap().len();
    for o in objs.values() {
        let g = &o["geometry"][0];
        assert_eq!(g["type"], "Solid");
        assert_eq!(g["lod"], "2.2");
        let shell = g["boundaries"][0].as_array().unwrap();
        let values = g["semantics"]["values"][0].as_array().unwrap();
        assert_eq!(shell.len(), values.len());
        for kind in [0, 1, 2] {
            assert!(values.iter().any(|x| x == kind), "surface {kind} missing");
        }
        let max = shell
            .iter()
            .flat_map(|s| s.as_array().unwrap())
            .flat_map(|r| r.as_array().unwrap())
            .map(|i| i.as_u64().unwrap())
            .max()
            .unwrap();
        assert!((max as usize) < nv);
    }
    let text = obj::obj_text(&rec);
    assert_eq!(text.matches("\no building_").count(), 3);
}

#[test]
fn models_of_building_parts_are_written_as_parts_of_their_building() {
    let s = scene();
    let c = cloud(&s, |_, _| true);
    let mut rec = reconstruct_cloud(&c, None, &ReconstructParams::default()).unwrap();
    let ids: Vec<u32> = rec.models.iter().map(|m| m.id).collect();
    assert_eq!(ids.len(), 3);
    rec.part_of = [(ids[0], "B".to_string()), (ids[1], "B".to_string())].into();
    // Parts without names of their own are named after their Building.
    rec.models[0].name.clear();
    rec.models[1].name.clear();
    let v = cityjson::to_cityjson(&rec);
    let objs = v["CityObjects"].as_object().unwrap();
    let keys: Vec<&str> = objs.keys().map(String::as_str).collect();
    assert_eq!(keys.len(), 4, "{keys:?}");
    let b = &objs["B"];
    assert_eq!(b["type"], "Building");
    assert_eq!(
        b["children"],
        serde_json::json!(["B-0", "B-1"]),
        "no own ids"
    );
    assert!(b.get("geometry").is_none());
    assert_eq!(b["attributes"]["skyground_parts"], 2);
    for k in ["B-0", "B-1"] {
        assert_eq!(objs[k]["type"], "BuildingPart");
        assert_eq!(objs[k]["parents"], serde_json::json!(["B"]));
        assert_eq!(objs[k]["geometry"][0]["type"], "Solid");
    }
    let lone = format!("building_{}", ids[2]);
    assert_eq!(objs[&lone]["type"], "Building");
    assert!(objs[&lone].get("parents").is_none());
    // Parts read from a city model keep their own CityObject ids.
    rec.models[0].name = "B_roof".into();
    rec.models[1].name = "B_wing".into();
    let v = cityjson::to_cityjson(&rec);
    let objs = v["CityObjects"].as_object().unwrap();
    assert_eq!(
        objs["B"]["children"],
        serde_json::json!(["B_roof", "B_wing"])
    );
    assert_eq!(objs["B_wing"]["parents"], serde_json::json!(["B"]));
}

#[test]
fn roof_density_counts_plane_points_over_the_cells_they_cover() {
    use crate::geom::grid::GridFrame;
    use crate::geom::planes::NO_PLANE;
    let grid = GridFrame {
        origin: [0.0, 0.0],
        cell: 0.5,
        nx: 8,
        ny: 8,
    };
    // Points every 0.25 m (16 per m²) over the left half; the right half
    // is unseen and must not thin the density.
    let xyz: Vec<[f32; 3]> = (0..8)
        .flat_map(|i| (0..16).map(move |j| [0.125 + 0.25 * i as f32, 0.125 + 0.25 * j as f32, 5.0]))
        .collect();
    let mut label = vec![0u32; xyz.len()];
    let mask = vec![true; 64];
    let d = building::roof_density(&xyz, &label, &grid, &mask);
    assert!((d - 16.0).abs() < 1e-9, "{d}");
    // Points on no plane (walls, clutter) do not count.
    label.iter_mut().step_by(2).for_each(|l| *l = NO_PLANE);
    let d = building::roof_density(&xyz, &label, &grid, &mask);
    assert!((d - 8.0).abs() < 1e-9, "{d}");
    // Outside the footprint neither.
    let none = vec![false; 64];
    assert!(building::roof_density(&xyz, &label, &grid, &none).is_nan());
}

#[test]
fn the_smallest_roof_part_grows_from_sparse_to_dense_roofs() {
    let p = ReconstructParams::default();
    assert_eq!(p.region_m2(12.0), p.min_region_m2);
    assert_eq!(p.region_m2(p.sparse_roof_density), p.min_region_m2);
    assert_eq!(p.region_m2(f64::NAN), p.min_region_m2);
    assert_eq!(p.region_m2(400.0), p.dense_region_m2);
    let mid = p.region_m2(0.5 * (p.sparse_roof_density + p.dense_roof_density));
    assert!((mid - 0.5 * (p.min_region_m2 + p.dense_region_m2)).abs() < 1e-9);
    let step = ReconstructParams {
        sparse_roof_density: 50.0,
        dense_roof_density: 50.0,
        ..p.clone()
    };
    assert_eq!(step.region_m2(49.9), p.min_region_m2);
    assert_eq!(step.region_m2(50.0), p.dense_region_m2);
    let bad = ReconstructParams {
        dense_region_m2: -1.0,
        ..p
    };
    assert!(
        bad.validate()
            .unwrap_err()
            .to_string()
            .contains("dense_region_m2")
    );
}

/// A flat roof at 6 m over a 10 m square, a box model of it, and a
/// chimney's few points a metre over the roof: roofer's measure (the
/// points on roof planes) leaves the chimney out, every roof point
/// counts it.
#[test]
fn the_b3_rmse_counts_roof_plane_points_and_the_strict_one_every_roof_point() {
    use geo::{LineString, MultiPolygon, Polygon};
    let square = MultiPolygon(vec![Polygon::new(
        LineString::from(vec![(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]),
        vec![],
    )]);
    let mut pts: Vec<[f32; 3]> = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            let z = 6.0 + 0.02 * (((i * 7 + j * 13) % 5) as f32 - 2.0);
            pts.push([0.125 + 0.25 * i as f32, 0.125 + 0.25 * j as f32, z]);
        }
    }
    let roof = pts.len();
    for k in 0..4 {
        pts.push([5.03 + 0.11 * k as f32, 5.07, 7.0 + 0.1 * k as f32]);
    }
    let params = ReconstructParams::default();
    let on = on_roof_planes(&pts, &params);
    assert!(on[..roof].iter().filter(|o| **o).count() > roof * 9 / 10);
    assert!(on[roof..].iter().all(|o| !*o), "the chimney is no plane");
    let shell = super::prism::prism(&square, 0.0, 6.0);
    let q = quality::assess(&shell, &square, (&pts, &on), &square);
    let (b3, strict) = (q.rmse_m.unwrap(), q.rmse_roof_points_m.unwrap());
    assert!(b3 < 0.03, "{b3}");
    // 4 points over 1 m above among 1,600 (the roof under the chimney
    // is covered, so not counted): sqrt(≈4·1.3/1,600) ≈ 0.06 m.
    assert!(strict > 0.04 && strict > 2.0 * b3, "{strict} {b3}");
    assert_eq!(q.footprint_iou, Some(1.0));
    assert!(q.val3dity.is_empty(), "{:?}", q.val3dity);
}

#[test]
fn no_points_on_planes_gives_no_b3_rmse() {
    let pts = [[1.0f32, 1.0, 6.0]; 3];
    assert_eq!(
        on_roof_planes(&pts, &ReconstructParams::default()),
        vec![false; 3]
    );
}
