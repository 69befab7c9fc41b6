//! Footprints (step 2): readers, true footprints of scenes, splitting clouds
//! into buildings, and footprints derived from building points, checked
//! against the ground truth of simulated scenes and real files.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use geo::{Area, BooleanOps, Distance, Euclidean};
use skyground_core::cloud::Cloud;
use skyground_core::cloud::class::BUILDING;
use skyground_core::crs::{Crs, SourceFrame};
use skyground_core::footprint::{
    DeriveParams, Footprint, ParseError, ReadOptions, RingProblem, SplitParams, derive,
    footprints_of_scene, iou, match_footprints, split,
};
use skyground_core::io::load_scene;
use skyground_core::io::{
    FootprintError, SourceFootprints, load_footprints, parse_cityjson_footprints, parse_geojson,
    parse_geojson_with, parse_obj_footprints, read_footprints, resolve_source,
};
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::scene::{REFERENCE_SEED, Scene, reference_scene};

mod common;
use common::{city3d_001, conformance_file, real_file};

fn prior(scene: &Scene) -> Cloud {
    airborne_scan(&Caster::new(scene).unwrap(), &AirborneConfig::default()).unwrap()
}

fn building_points(cloud: &Cloud) -> Vec<[f32; 3]> {
    let labels = cloud.label.as_ref().unwrap();
    cloud
        .xyz
        .iter()
        .zip(labels)
        .filter(|(_, l)| **l == BUILDING)
        .map(|(p, _)| *p)
        .collect()
}

/// The aerial prior of a sparse city: one survey per tile of `tile` metres
/// that holds a building's centre (tile plus 30 m of margin), concatenated.
fn tiled_prior(scene: &Scene, fps: &[Footprint], tile: f64) -> Cloud {
    use std::collections::{BTreeSet, HashMap};
    let tiles: BTreeSet<(i64, i64)> = fps
        .iter()
        .filter_map(|f| f.bounds())
        .map(|b| {
            let c = [(b[0] + b[2]) / 2.0, (b[1] + b[3]) / 2.0];
            ((c[0] / tile).floor() as i64, (c[1] / tile).floor() as i64)
        })
        .collect();
    let mut out = Cloud {
        origin: scene.origin,
        label: Some(Vec::new()),
        building: Some(Vec::new()),
        ..Cloud::default()
    };
    for (i, j) in tiles {
        let lo = [i as f32 * tile as f32 - 30.0, j as f32 * tile as f32 - 30.0];
        let hi = [lo[0] + tile as f32 + 60.0, lo[1] + tile as f32 + 60.0];
        let mut sub = Scene {
            objects: scene.objects.clone(),
            origin: scene.origin,
            ..Scene::default()
        };
        let mut map: HashMap<u32, u32> = HashMap::new();
        for (t, &o) in scene.triangles.iter().zip(&scene.triangle_object) {
            let c = t.map(|v| scene.vertices[v as usize]);
            let inside = c
                .iter()
                .all(|p| p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1]);
            if !inside {
                continue;
            }
            let t = t.map(|v| {
                *map.entry(v).or_insert_with(|| {
                    sub.vertices.push(scene.vertices[v as usize]);
                    (sub.vertices.len() - 1) as u32
                })
            });
            sub.triangles.push(t);
            sub.triangle_object.push(o);
        }
        let config = AirborneConfig {
            pulse_rate_hz: 40_000.0,
            ..AirborneConfig::default()
        };
        let c = airborne_scan(&Caster::new(&sub).unwrap(), &config).unwrap();
        // Keep each tile's own centre so overlapping margins are not counted twice.
        let (tl, th) = ([lo[0] + 30.0, lo[1] + 30.0], [hi[0] - 30.0, hi[1] - 30.0]);
        for (k, p) in c.xyz.iter().enumerate() {
            if p[0] >= tl[0] && p[0] < th[0] && p[1] >= tl[1] && p[1] < th[1] {
                out.xyz.push(*p);
                out.label
                    .as_mut()
                    .unwrap()
                    .push(c.label.as_ref().unwrap()[k]);
                out.building
                    .as_mut()
                    .unwrap()
                    .push(c.building.as_ref().unwrap()[k]);
            }
        }
    }
    out
}

/// Share of building points (true id > 0) whose split id equals the true id.
fn split_accuracy(cloud: &Cloud, ids: &[u32]) -> (f64, usize) {
    let truth = cloud.building.as_ref().unwrap();
    let (mut ok, mut n) = (0usize, 0usize);
    for (t, got) in truth.iter().zip(ids) {
        if *t > 0 {
            n += 1;
            ok += usize::from(t == got);
        }
    }
    (ok as f64 / n.max(1) as f64, n)
}

#[test]
fn reference_scene_derived_footprints_match_the_truth() {
    let scene = reference_scene(REFERENCE_SEED);
    let truth = footprints_of_scene(&scene);
    assert_eq!(truth.len(), scene.building_count());
    let cloud = prior(&scene);
    let pts = building_points(&cloud);
    let derived = derive(&pts, &DeriveParams::default()).unwrap();
    let matches = match_footprints(&derived, &truth);
    println!(
        "reference scene: {} true footprints, {} derived from {} building points",
        truth.len(),
        derived.len(),
        pts.len()
    );
    println!(
        "{:>5} {:<22} {:>9} {:>8} {:>6}",
        "truth", "name", "area m²", "derived", "IoU"
    );
    for (m, t) in matches.iter().zip(&truth) {
        println!(
            "{:>5} {:<22} {:>9.1} {:>8} {:>6.3}",
            m.truth,
            t.name,
            t.area(),
            m.derived,
            m.iou
        );
    }
    // Neighbours closer than 5 m: were they told apart?
    for (i, a) in truth.iter().enumerate() {
        for b in &truth[i + 1..] {
            let gap = Euclidean.distance(&a.polygon, &b.polygon);
            if gap < 5.0 {
                let da = matches[i].derived;
                let db = matches.iter().find(|m| m.truth == b.id).unwrap().derived;
                println!(
                    "  {} and {}: gap {gap:.2} m, derived {da} / {db} ({})",
                    a.name,
                    b.name,
                    if da != db { "separated" } else { "MERGED" }
                );
                assert_ne!(da, db, "{} and {} merged", a.name, b.name);
            }
        }
    }
    let worst = matches.iter().map(|m| m.iou).fold(1.0, f64::min);
    println!("worst IoU {worst:.3}");
    for m in &matches {
        assert!(m.iou >= 0.9, "building {} IoU {:.3}", m.truth, m.iou);
    }
    // Every derived footprint is some building (no clutter outlines).
    assert_eq!(derived.len(), truth.len());

    // The height-jump split must not cut the podium from its towers.
    let cut = derive_with_height_split(&pts);
    let cut_matches = match_footprints(&cut, &truth);
    let cut_worst = cut_matches.iter().map(|m| m.iou).fold(1.0, f64::min);
    println!(
        "with height_jump_m = 3: {} derived, worst IoU {cut_worst:.3}",
        cut.len()
    );
    assert_eq!(cut.len(), truth.len());
    assert!(cut_worst >= 0.9);
}

#[test]
fn reference_prior_splits_by_true_footprints() {
    let scene = reference_scene(REFERENCE_SEED);
    let truth = footprints_of_scene(&scene);
    let cloud = prior(&scene);
    let ids = split(&cloud.xyz, &truth, &SplitParams::default()).unwrap();
    let (acc, n) = split_accuracy(&cloud, &ids);
    let labels = cloud.label.as_ref().unwrap();
    let (mut other_in, mut other) = (0usize, 0usize);
    for (l, id) in labels.iter().zip(&ids) {
        if *l != BUILDING {
            other += 1;
            other_in += usize::from(*id > 0);
        }
    }
    println!(
        "reference prior: {:.3} % of {n} building points get their true id; {:.2} % of {other} other points fall in a footprint",
        100.0 * acc,
        100.0 * other_in as f64 / other.max(1) as f64
    );
    assert!(acc >= 0.99, "split accuracy {acc:.4}");
}

#[test]
fn touching_buildings_split_at_height_jumps() {
    // Two terraced boxes sharing a wall (6 m and 12 m roofs), and a podium
    // (8 m) with a 30 m tower in its middle, 20 m away: roof points at 0.25 m.
    let mut pts = Vec::new();
    let mut grid = |x0: f32, y0: f32, w: f32, d: f32, z: f32| {
        let (nx, ny) = ((w / 0.25) as i32, (d / 0.25) as i32);
        for j in 0..=ny {
            for i in 0..=nx {
                pts.push([x0 + i as f32 * 0.25, y0 + j as f32 * 0.25, z]);
            }
        }
    };
    grid(0.0, 0.0, 10.0, 12.0, 6.0);
    grid(10.0, 0.0, 8.0, 12.0, 12.0);
    // Podium ring around the tower, then the tower.
    for (x0, y0, w, d) in [
        (40.0, 0.0, 30.0, 8.0),
        (40.0, 22.0, 30.0, 8.0),
        (40.0, 8.0, 10.0, 14.0),
        (60.0, 8.0, 10.0, 14.0),
    ] {
        grid(x0, y0, w, d, 8.0);
    }
    grid(50.0, 8.0, 10.0, 14.0, 30.0);

    let plain = derive(&pts, &DeriveParams::default()).unwrap();
    let cut = derive_with_height_split(&pts);
    println!(
        "touching pair + podium: {} footprints without the height split, {} with it",
        plain.len(),
        cut.len()
    );
    assert_eq!(plain.len(), 2, "without cuts the terrace is one cluster");
    assert_eq!(cut.len(), 3, "terrace cut in two, podium kept whole");
    let areas: Vec<f64> = cut.iter().map(Footprint::area).collect();
    let mut sorted = areas.clone();
    sorted.sort_by(f64::total_cmp);
    // 96 m², 120 m², 900 m² within a cell's worth of outline.
    for (got, want) in sorted.iter().zip([96.0, 120.0, 900.0]) {
        assert!((got - want).abs() / want < 0.1, "area {got:.1} vs {want}");
    }
}

#[test]
fn zurich_cityjson_footprints_split_the_simulated_prior() {
    let Some(path) = real_file("zurich_subset_lod2.json") else {
        return;
    };
    let scene = load_scene(path.to_str().unwrap()).unwrap();
    let loaded = load_footprints(&path, scene.origin).unwrap();
    let fps = &loaded.footprints;
    println!(
        "zurich: {} footprints ({} skipped), scene has {} buildings",
        fps.len(),
        loaded.skipped.len(),
        scene.building_count()
    );
    assert_eq!(fps.len(), 49);
    let areas: Vec<f64> = fps.iter().map(Footprint::area).collect();
    let total: f64 = areas.iter().sum();
    let (min, max) = areas
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    println!("  areas: min {min:.1} m², max {max:.1} m², total {total:.0} m²");
    assert!(min > 1.0 && max < 20_000.0);
    // Same ids as the scene: each file footprint (ground outline) lies
    // within the scene's projection of the same id (roofs overhang it).
    let scene_fps = footprints_of_scene(&scene);
    let by_id: BTreeMap<u32, &Footprint> = scene_fps.iter().map(|f| (f.id, f)).collect();
    let mut within = Vec::new();
    let mut ious = Vec::new();
    for f in fps {
        let s = by_id[&f.id];
        within.push(f.polygon.intersection(&s.polygon).unsigned_area() / f.area());
        ious.push(iou(&f.polygon, &s.polygon));
    }
    let worst_within = within.iter().copied().fold(1.0, f64::min);
    let mean_iou = ious.iter().sum::<f64>() / ious.len() as f64;
    println!(
        "  file outline within the scene's projection of the same id: worst {:.1} %; IoU mean {mean_iou:.3}, min {:.3} (eaves overhang the ground outline)",
        100.0 * worst_within,
        ious.iter().copied().fold(1.0, f64::min)
    );
    assert!(worst_within > 0.95);

    // The 49 buildings are spread over ~9 km × 10 km: fly each 150 m tile
    // that holds buildings (with its terrain) instead of the whole extent.
    let cloud = tiled_prior(&scene, &scene_fps, 150.0);
    let ids = split(&cloud.xyz, fps, &SplitParams::default()).unwrap();
    let (acc, n) = split_accuracy(&cloud, &ids);
    println!(
        "  prior: {:.2} % of {n} building points get their true id",
        100.0 * acc
    );
    assert!(acc >= 0.95, "split accuracy {acc:.4}");
}

#[test]
fn delft_lod1_loads() {
    let Some(path) = real_file("delft.json") else {
        return;
    };
    let loaded = load_footprints(&path, [84_616.0, 447_422.0, 0.0]).unwrap();
    let total: f64 = loaded.footprints.iter().map(Footprint::area).sum();
    println!(
        "delft: {} footprints ({} skipped), total {total:.0} m²",
        loaded.footprints.len(),
        loaded.skipped.len()
    );
    assert_eq!(loaded.footprints.len(), 160);
}

#[test]
fn city3d_points_fall_inside_their_footprint() {
    let Some((cloud, loaded)) = city3d_001() else {
        return;
    };
    assert_eq!(loaded.footprints.len(), 1);
    let fp = &loaded.footprints[0];
    let ring = &fp.polygon.0[0];
    println!(
        "city3d_001: footprint {} vertices, {:.0} m²",
        ring.exterior().0.len() - 1,
        fp.area()
    );
    assert_eq!(ring.exterior().0.len() - 1, 60);
    // The cloud also holds the ground and neighbouring buildings: check
    // the building's points, those 2 m or more above the ground (lowest 5 %).
    let mut zs: Vec<f32> = cloud.xyz.iter().map(|p| p[2]).collect();
    zs.sort_by(f32::total_cmp);
    let ground = zs[zs.len() / 20];
    let ids = split(&cloud.xyz, &loaded.footprints, &SplitParams::default()).unwrap();
    let inside = ids.iter().filter(|&&i| i == fp.id).count();
    let inside_high = ids
        .iter()
        .zip(&cloud.xyz)
        .filter(|(i, p)| **i == fp.id && p[2] >= ground + 2.0)
        .count();
    println!(
        "  {:.1} % of all {} points inside (0.5 m tolerance); {:.1} % of those inside are 2 m or more above ground",
        100.0 * inside as f64 / cloud.xyz.len() as f64,
        cloud.xyz.len(),
        100.0 * inside_high as f64 / inside.max(1) as f64
    );
    assert!(inside_high as f64 >= 0.9 * inside as f64);
    // The footprint is covered by the cloud: most of its 2 m cells hold points.
    let high: Vec<[f32; 3]> = cloud
        .xyz
        .iter()
        .filter(|p| p[2] >= ground + 2.0)
        .copied()
        .collect();
    let derived = derive(&high, &DeriveParams::default()).unwrap();
    let m = match_footprints(&derived, &loaded.footprints);
    // The outlines lying mostly inside the footprint: the building's pieces.
    let pieces: Vec<&Footprint> = derived
        .iter()
        .filter(|d| fp.polygon.intersection(&d.polygon).unsigned_area() >= 0.5 * d.area())
        .collect();
    let union = pieces
        .iter()
        .fold(geo::MultiPolygon::new(vec![]), |u, d| u.union(&d.polygon));
    let covered = fp.polygon.intersection(&union).unsigned_area() / fp.area();
    println!(
        "  derived from points 2 m above ground: {} outlines, {} inside the footprint; best match IoU {:.3}; together they cover {:.1} % of it",
        derived.len(),
        pieces.len(),
        m[0].iou,
        100.0 * covered
    );
    assert!(covered > 0.9);
    // Known over-split (docs/footprints.md): the valleys where a wing's roof
    // meets the main roof cut the wing off (before the valley split one
    // outline covered over 90 % of the footprint).
    assert!(pieces.len() <= 2, "{} pieces", pieces.len());
}

fn temp(dir: &Path, name: &str, content: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, content).unwrap();
    p
}

#[test]
fn geojson_polygons_holes_ids_and_origin() {
    let doc = br#"{"type":"FeatureCollection","features":[
      {"type":"Feature","properties":{"building":7,"name":"court"},"geometry":{"type":"Polygon","coordinates":[
        [[1000,2000],[1030,2000],[1030,2030],[1000,2030],[1000,2000]],
        [[1010,2010],[1010,2020],[1020,2020],[1020,2010],[1010,2010]]]}},
      {"type":"Feature","properties":{},"geometry":{"type":"MultiPolygon","coordinates":[
        [[[1100,2000],[1110,2000],[1110,2010],[1100,2010],[1100,2000]]],
        [[[1120,2000],[1130,2000],[1130,2010],[1120,2010],[1120,2000]]]]}},
      {"type":"Feature","properties":{"id":"3"},"geometry":{"type":"Point","coordinates":[0,0]}}
    ]}"#;
    let loaded = parse_geojson(doc, [1000.0, 2000.0, 0.0]).unwrap();
    let ids: Vec<u32> = loaded.footprints.iter().map(|f| f.id).collect();
    assert_eq!(ids, vec![7, 8]);
    assert!((loaded.footprints[0].area() - 800.0).abs() < 1e-6);
    assert_eq!(loaded.footprints[0].name, "court");
    assert!((loaded.footprints[1].area() - 200.0).abs() < 1e-6);
    assert_eq!(loaded.skipped.len(), 1);
    assert!(matches!(
        loaded.skipped[0].problem,
        RingProblem::NotPolygon(_)
    ));
    // The courtyard is outside, the wing inside, in the local frame.
    let ids = split(
        &[
            [15.0, 15.0, 0.0],
            [5.0, 5.0, 0.0],
            [105.0, 5.0, 0.0],
            [-3.0, 5.0, 0.0],
        ],
        &loaded.footprints,
        &SplitParams::default(),
    )
    .unwrap();
    assert_eq!(ids, vec![0, 7, 8, 0]);
    // Ring form round trip.
    let back = Footprint::from(&loaded.footprints[0].to_rings());
    assert!((back.area() - 800.0).abs() < 1e-6);
}

#[test]
fn bad_inputs_give_typed_errors_or_skips() {
    let o = [0.0; 3];
    // Empty and broken files.
    assert_eq!(parse_geojson(b"  \n", o).unwrap_err(), ParseError::Empty);
    assert!(matches!(
        parse_geojson(b"{\"type\": \"Feature\",", o),
        Err(ParseError::Json { .. })
    ));
    assert!(matches!(
        parse_geojson(b"[1,2,3]", o),
        Err(ParseError::Shape { .. })
    ));
    assert!(matches!(
        parse_geojson(br#"{"type":"LineString","coordinates":[[0,0],[1,1]]}"#, o),
        Err(ParseError::Shape { .. })
    ));
    assert!(matches!(
        parse_cityjson_footprints(br#"{"type":"FeatureCollection","features":[]}"#, o),
        Err(ParseError::Shape { .. })
    ));
    assert!(matches!(
        parse_obj_footprints(b"v 0 0 0\nv 1 0 0\nf 1 2 9\n", o),
        Err(ParseError::Shape { .. })
    ));
    assert_eq!(parse_obj_footprints(b"", o).unwrap_err(), ParseError::Empty);
    // Unclosed and two-vertex rings are skipped and counted; the good one loads.
    let doc = br#"{"type":"FeatureCollection","features":[
      {"type":"Feature","geometry":{"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,1]]]}},
      {"type":"Feature","geometry":{"type":"Polygon","coordinates":[[[0,0],[1,0],[0,0]]]}},
      {"type":"Feature","geometry":{"type":"Polygon","coordinates":[[[0,0],["a",0],[1,1],[0,0]]]}},
      {"type":"Feature","geometry":{"type":"Polygon","coordinates":[[[5,5],[6,5],[6,6],[5,6],[5,5]]]}}
    ]}"#;
    let loaded = parse_geojson(doc, o).unwrap();
    assert_eq!(loaded.footprints.len(), 1);
    let problems: Vec<&RingProblem> = loaded.skipped.iter().map(|s| &s.problem).collect();
    assert_eq!(
        problems,
        vec![
            &RingProblem::NotClosed,
            &RingProblem::TooFewVertices(2),
            &RingProblem::BadPosition
        ]
    );
    // Nothing usable at all is an error that says why.
    let only_bad = br#"{"type":"Polygon","coordinates":[[[0,0],[1,0],[2,0],[0,0]]]}"#;
    let e = parse_geojson(only_bad, o).unwrap_err();
    assert!(
        matches!(e, ParseError::NoFootprints { skipped: 1, .. }),
        "{e}"
    );
    // Self-touching rings (a figure 8; a hole touching its exterior) come out valid.
    let eight = br#"{"type":"Polygon","coordinates":[[[0,0],[2,2],[2,0],[0,2],[0,0]]]}"#;
    let fp = &parse_geojson(eight, o).unwrap().footprints[0];
    assert!((fp.area() - 2.0).abs() < 1e-9, "area {}", fp.area());
    let touching = br#"{"type":"Polygon","coordinates":[
        [[0,0],[4,0],[4,4],[0,4],[0,0]],[[0,0],[2,1],[1,2],[0,0]]]}"#;
    let fp = &parse_geojson(touching, o).unwrap().footprints[0];
    assert!((fp.area() - 14.5).abs() < 1e-9, "area {}", fp.area());
    // Files: missing, unknown extension, empty, wrong JSON, name in the message.
    let missing = load_footprints(Path::new("/nonexistent/fp.geojson"), o).unwrap_err();
    assert!(matches!(missing, FootprintError::Io(_)));
    let tmp = tempfile::tempdir().unwrap();
    let csv = temp(tmp.path(), "fp.csv", b"x,y\n");
    assert!(matches!(
        load_footprints(&csv, o),
        Err(FootprintError::UnknownFormat { .. })
    ));
    let empty = temp(tmp.path(), "empty.geojson", b"");
    let e = load_footprints(&empty, o).unwrap_err();
    assert!(
        e.to_string().contains("empty.geojson") && e.to_string().contains("empty"),
        "{e}"
    );
    let wrong = temp(tmp.path(), "wrong.json", b"{\"type\": 5}");
    assert!(matches!(
        load_footprints(&wrong, o),
        Err(FootprintError::Parse {
            source: ParseError::Shape { .. },
            ..
        })
    ));
    // Degenerate inputs to the algorithms: empty results, no panics.
    assert!(derive(&[], &DeriveParams::default()).unwrap().is_empty());
    assert!(
        derive(&[[f32::NAN, 0.0, 0.0]], &DeriveParams::default())
            .unwrap()
            .is_empty()
    );
    assert_eq!(
        split(&[[0.0, 0.0, 0.0]], &[], &SplitParams::default()).unwrap(),
        vec![0]
    );
    assert!(
        derive(
            &[[0.0; 3]],
            &DeriveParams {
                cell_m: skyground_core::density::Auto::Value(-1.0),
                ..DeriveParams::default()
            }
        )
        .is_err()
    );
    assert!(
        split(
            &[],
            &[],
            &SplitParams {
                tolerance_m: f64::NAN,
                ..SplitParams::default()
            }
        )
        .is_err()
    );
    assert_eq!(
        iou(
            &geo::MultiPolygon::new(vec![]),
            &geo::MultiPolygon::new(vec![])
        ),
        0.0
    );
    let _ = Area::unsigned_area(&geo::MultiPolygon::<f64>::new(vec![]));
}

/// Footprints derived with the height-jump split on (3 m), with the
/// enclosure share that keeps a tower on its podium (the valley split's
/// default, 0.1, lets the reference scene's tower go).
fn derive_with_height_split(pts: &[[f32; 3]]) -> Vec<Footprint> {
    let params = DeriveParams {
        height_jump_m: 3.0,
        min_open_share: 0.25,
        ..DeriveParams::default()
    };
    derive(pts, &params).unwrap()
}

/// Footprints of `spec` as surveys have them (own ids read the default way).
fn read(spec: &Path) -> SourceFootprints {
    read_footprints(&spec.display().to_string(), &ReadOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn delft_cityjson_keeps_its_bag_ids_and_the_scene_numbering() {
    let Some(path) = real_file("delft.json") else {
        return;
    };
    let fps = read(&path);
    assert_eq!(
        fps.crs.as_ref().and_then(|c| c.horizontal_epsg()),
        Some(28992)
    );
    let f = &fps.loaded.footprints;
    assert_eq!(f.len(), 160);
    // `identificatiebagpnd`: the BAG pand id (15 digits), not the BGT UUID.
    assert!(
        f.iter()
            .all(|f| f.name.len() == 15 && f.name.bytes().all(|b| b.is_ascii_digit())),
        "{:?}",
        f.iter().map(|f| &f.name).take(3).collect::<Vec<_>>()
    );
    assert!(f.iter().any(|f| f.name == "503100000000035"));
    // Numbered as the scene numbers its buildings: the same ids cover the same ground.
    let scene = load_scene(path.to_str().unwrap()).unwrap();
    let moved = read(&path)
        .in_frame(&SourceFrame::new(scene.origin, None))
        .unwrap();
    let truth = footprints_of_scene(&scene);
    for (a, b) in moved.footprints.iter().zip(&truth) {
        assert_eq!(a.id, b.id);
        assert!(iou(&a.polygon, &b.polygon) > 0.9, "building {}", a.id);
    }
    // The BGT UUID on request, and a field nobody has is refused by name.
    let by_uuid = read_footprints(
        &path.display().to_string(),
        &ReadOptions {
            id_field: Some("lokaalid".into()),
            ..ReadOptions::default()
        },
    )
    .unwrap();
    assert!(by_uuid.loaded.footprints[0].name.starts_with("G0503."));
    let e = read_footprints(
        &path.display().to_string(),
        &ReadOptions {
            id_field: Some("osm_id".into()),
            ..ReadOptions::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("`osm_id`"), "{e}");
}

#[test]
fn cityjson_ground_surfaces_join_building_parts_to_their_building() {
    // 3DBAG: LoD 2.2 BuildingParts with GroundSurface under Buildings without geometry,
    // as CityJSON and as CityJSONSeq (what 3DBAG serves).
    let (Some(city), Some(seq)) = (
        real_file("3dbag_2buildings.city.json"),
        conformance_file("cjseq_3dbag_b2.city.jsonl"),
    ) else {
        return;
    };
    for path in [city, seq] {
        let f = read(&path).loaded.footprints;
        let names: Vec<&str> = f.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "NL.IMBAG.Pand.0503100000028341",
                "NL.IMBAG.Pand.0503100000031927"
            ],
            "{}",
            path.display()
        );
        assert!(f.iter().all(|f| f.area() > 20.0 && f.area() < 2000.0));
    }
    // cjio's multi-LoD buildings: LoD 1.2 / 1.3 / 2.2 solids, the BAG id in `identificatie`.
    let Some(multi) = conformance_file("cjio_multi_lod.json") else {
        return;
    };
    let f = read(&multi).loaded.footprints;
    assert_eq!(f.len(), 10);
    assert!(
        f.iter().all(|f| f.name.starts_with("NL.IMBAG.Pand.")),
        "{:?}",
        f[0].name
    );
    // Zurich: 49 Buildings of 161 LoD2 parts.
    if let Some(z) = real_file("zurich_subset_lod2.json") {
        assert_eq!(read(&z).loaded.footprints.len(), 49);
    }
}

#[test]
fn cityjson_lod0_footprints_win_over_the_roof_outline() {
    // A Building with a LoD 0 footprint (10 × 10 m) and a LoD 2 part whose
    // roof overhangs it by 1 m all round (no GroundSurface).
    let doc = br#"{"type":"CityJSON","version":"2.0","transform":{"scale":[1,1,1],"translate":[0,0,0]},
      "CityObjects":{
        "b1":{"type":"Building","attributes":{"identificatie":"NL.IMBAG.Pand.1"},"children":["b1-0"],
          "geometry":[{"type":"MultiSurface","lod":"0","boundaries":[[[0,1,2,3]]]}]},
        "b1-0":{"type":"BuildingPart","parents":["b1"],
          "geometry":[{"type":"MultiSurface","lod":"2.2","boundaries":[[[4,5,6,7]]]}]}},
      "vertices":[[0,0,0],[10,0,0],[10,10,0],[0,10,0],[-1,-1,6],[11,-1,6],[11,11,6],[-1,11,6]]}"#;
    let loaded = parse_cityjson_footprints(doc, [0.0; 3]).unwrap();
    let f = &loaded.footprints[0];
    assert_eq!(f.name, "NL.IMBAG.Pand.1");
    assert!((f.area() - 100.0).abs() < 1e-9, "area {}", f.area());
}

fn read_parts(spec: &Path) -> SourceFootprints {
    let options = ReadOptions {
        parts: true,
        ..ReadOptions::default()
    };
    read_footprints(&spec.display().to_string(), &options).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn cityjson_footprints_per_part_keep_their_building() {
    // A Building with a LoD 0 outline of the whole and two LoD 2 parts side
    // by side (6 × 10 m and 4 × 10 m), and a Building without parts.
    let doc = br#"{"type":"CityJSON","version":"2.0","transform":{"scale":[1,1,1],"translate":[0,0,0]},
      "CityObjects":{
        "b1":{"type":"Building","attributes":{"identificatie":"NL.IMBAG.Pand.1"},"children":["b1-0","b1-1"],
          "geometry":[{"type":"MultiSurface","lod":"0","boundaries":[[[0,1,2,3]]]}]},
        "b1-0":{"type":"BuildingPart","parents":["b1"],
          "geometry":[{"type":"MultiSurface","lod":"2.2","boundaries":[[[0,4,5,3]]]}]},
        "b1-1":{"type":"BuildingPart","parents":["b1"],
          "geometry":[{"type":"MultiSurface","lod":"2.2","boundaries":[[[4,1,2,5]]]}]},
        "b2":{"type":"Building","attributes":{"identificatie":"NL.IMBAG.Pand.2"},
          "geometry":[{"type":"MultiSurface","lod":"2.2","boundaries":[[[6,7,8,9]]]}]}},
      "vertices":[[0,0,0],[10,0,0],[10,10,0],[0,10,0],[6,0,0],[6,10,0],
                  [20,0,0],[25,0,0],[25,5,0],[20,5,0]]}"#;
    let path =
        std::env::temp_dir().join(format!("skyground-parts-{}.city.json", std::process::id()));
    std::fs::write(&path, doc).unwrap();
    let joined = read(&path).loaded;
    let per_part = read_parts(&path).loaded;
    std::fs::remove_file(&path).unwrap();
    assert_eq!(joined.footprints.len(), 2);
    assert!(joined.part_of.is_empty());
    let got: Vec<(&str, f64)> = per_part
        .footprints
        .iter()
        .map(|f| (f.name.as_str(), f.area()))
        .collect();
    assert_eq!(
        got,
        [("b1-0", 60.0), ("b1-1", 40.0), ("NL.IMBAG.Pand.2", 25.0)],
        "each part its own outline, the whole's LoD 0 left out"
    );
    let ids: Vec<u32> = per_part.footprints.iter().map(|f| f.id).collect();
    assert_eq!(
        per_part.part_of,
        BTreeMap::from([
            (ids[0], "NL.IMBAG.Pand.1".to_string()),
            (ids[1], "NL.IMBAG.Pand.1".to_string())
        ]),
        "a Building without parts is no part"
    );
    // 3DBAG: each Building holds one LoD 2.2 part; Zurich: 161 parts in 49 Buildings.
    if let Some(city) = real_file("3dbag_2buildings.city.json") {
        let l = read_parts(&city).loaded;
        let parents: Vec<&str> = l.part_of.values().map(String::as_str).collect();
        assert_eq!(
            parents,
            [
                "NL.IMBAG.Pand.0503100000028341",
                "NL.IMBAG.Pand.0503100000031927"
            ]
        );
        assert!(
            l.footprints.iter().all(|f| f.name.ends_with("-0")),
            "{:?}",
            l.footprints[0].name
        );
    }
    if let Some(z) = real_file("zurich_subset_lod2.json") {
        let l = read_parts(&z).loaded;
        let buildings: std::collections::BTreeSet<&String> = l.part_of.values().collect();
        println!(
            "zurich per part: {} footprints, {} parts of {} buildings, {} skipped",
            l.footprints.len(),
            l.part_of.len(),
            buildings.len(),
            l.skipped.len()
        );
        assert!(
            l.footprints.len() > 49 && l.footprints.len() <= 161,
            "{}",
            l.footprints.len()
        );
    }
}

#[test]
fn geojson_bag_and_osm_ids_come_through() {
    // PDOK BAG panden (a MultiPolygon drawn as two features of one pand), OSM exports.
    let doc = br#"{"type":"FeatureCollection","features":[
      {"type":"Feature","properties":{"identificatie":"0503100000028341","bouwjaar":1930},
       "geometry":{"type":"Polygon","coordinates":[[[0,0],[10,0],[10,10],[0,10],[0,0]]]}},
      {"type":"Feature","properties":{"identificatie":"0503100000028341"},
       "geometry":{"type":"MultiPolygon","coordinates":[[[[10,0],[20,0],[20,10],[10,10],[10,0]]]]}},
      {"type":"Feature","id":"way/4242","properties":{"@id":"way/4242","building":"house"},
       "geometry":{"type":"Polygon","coordinates":[[[30,0],[40,0],[40,10],[30,10],[30,0]]]}},
      {"type":"Feature","properties":{"osm_id":"123456789","name":"Oude Kerk"},
       "geometry":{"type":"Polygon","coordinates":[[[50,0],[60,0],[60,10],[50,10],[50,0]]]}}
    ]}"#;
    let loaded = parse_geojson(doc, [0.0; 3]).unwrap();
    let got: Vec<(u32, &str, f64)> = loaded
        .footprints
        .iter()
        .map(|f| (f.id, f.name.as_str(), f.area()))
        .collect();
    assert_eq!(
        got,
        [
            (1, "0503100000028341", 200.0),
            (2, "way/4242", 100.0),
            (3, "123456789", 100.0)
        ]
    );
    let named = parse_geojson_with(
        doc,
        [0.0; 3],
        &ReadOptions {
            id_field: Some("name".into()),
            ..ReadOptions::default()
        },
    )
    .unwrap();
    assert_eq!(named.footprints.last().unwrap().name, "Oude Kerk");
}

#[test]
fn the_model_keyword_and_files_that_cannot_be_used() {
    let Some(delft) = real_file("delft.json") else {
        return;
    };
    let spec = resolve_source("model", delft.to_str()).unwrap();
    assert_eq!(read(Path::new(&spec)).loaded.footprints.len(), 160);
    let e = resolve_source("model", Some("reference")).unwrap_err();
    assert!(e.to_string().contains("not CityJSON"), "{e}");
    // Another CRS than the cloud's is refused, naming both.
    let zurich_frame = SourceFrame::new([0.0; 3], Crs::from_epsg(2056).ok());
    let e = read(&delft).in_frame(&zurich_frame).unwrap_err();
    assert!(matches!(e, FootprintError::CrsMismatch { .. }), "{e}");
    let text = e.to_string();
    assert!(text.contains("7415") && text.contains("2056"), "{text}");
    // GeoPackage: said why and what to do.
    let tmp = tempfile::tempdir().unwrap();
    let gpkg = temp(tmp.path(), "panden.gpkg", b"SQLite format 3\0");
    let e = read_footprints(&gpkg.display().to_string(), &ReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("ogr2ogr"), "{e}");
    let missing =
        read_footprints("/nonexistent/panden.geojson", &ReadOptions::default()).unwrap_err();
    assert!(
        missing.to_string().contains("/nonexistent/panden.geojson"),
        "{missing}"
    );
}

/// Points 0.25 m apart over a row of `n` houses 6 m wide (x) and 10 m deep
/// (y), each with a 45° gable roof whose ridge runs along y (`across`: a
/// valley between neighbours) or one ridge along the whole row (no cue).
fn gabled_row(n: usize, across: bool) -> Vec<[f32; 3]> {
    let mut pts = Vec::new();
    for i in 0..(n * 24) {
        for j in 0..40 {
            let (x, y) = (0.125 + 0.25 * i as f32, 0.125 + 0.25 * j as f32);
            let z = if across {
                9.0 - (x % 6.0 - 3.0).abs()
            } else {
                11.0 - (y - 5.0).abs()
            };
            pts.push([x, y, z]);
        }
    }
    pts
}

#[test]
fn rows_of_gabled_houses_split_at_their_valleys_only() {
    let rect = |x0: f64| {
        geo::MultiPolygon::new(vec![geo::Polygon::new(
            geo::LineString::from(vec![
                (x0, 0.0),
                (x0 + 6.0, 0.0),
                (x0 + 6.0, 10.0),
                (x0, 10.0),
                (x0, 0.0),
            ]),
            vec![],
        )])
    };
    let p = DeriveParams::default();
    let across = derive(&gabled_row(3, true), &p).unwrap();
    let ious: Vec<f64> = (0..3)
        .map(|k| {
            let t = rect(6.0 * k as f64);
            across
                .iter()
                .map(|d| iou(&d.polygon, &t))
                .fold(0.0, f64::max)
        })
        .collect();
    println!(
        "3 houses, ridges across the row: {} derived, IoU {ious:.3?}",
        across.len()
    );
    assert_eq!(across.len(), 3);
    assert!(ious.iter().all(|&v| v > 0.85), "{ious:?}");
    // One ridge along the row: the points show no party wall, no cut.
    let along = derive(&gabled_row(3, false), &p).unwrap();
    assert_eq!(along.len(), 1);
    // Off, the row stays one block.
    let off = DeriveParams { valley_m: 0.0, ..p };
    assert_eq!(derive(&gabled_row(3, true), &off).unwrap().len(), 1);
    // A bad depth is refused.
    let bad = DeriveParams {
        valley_m: f64::NAN,
        ..DeriveParams::default()
    };
    assert!(derive(&gabled_row(1, true), &bad).is_err());
}
