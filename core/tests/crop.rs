//! Cropping the real Zurich CityJSON block (49 buildings over 9.2 × 10 km) to
//! one cluster, as `skyground demo` does, and the crop's trip through OBJ.
//! Reads `../shared/data/real` (`SKYGROUND_REAL_DATA` overrides); absent →
//! `SKIPPED: ...`, the test passes.

use skyground_core::graph::{GraphParams, MAX_OCCUPANCY_CELLS};
use skyground_core::io::{ObjOptions, load_scene, obj_text, parse_obj};
use skyground_core::metrics::sample_building_surfaces;
use skyground_core::scene::{ObjectKind, Window, busiest_window, crop_scene};

mod common;
use common::real_file;

#[test]
fn zurich_busiest_250_m_window() {
    let Some(path) = real_file("zurich_subset_lod2.json") else {
        return;
    };
    let scene = load_scene(path.to_str().unwrap()).unwrap();
    assert_eq!(scene.building_count(), 49);
    let (lo, hi) = scene.bounds().unwrap();
    let size = [0, 1].map(|k| f64::from(hi[k] - lo[k]));
    // The whole block is far too large for the ground graph.
    assert!(GraphParams::default().occupancy_cells(size) > 7.0 * MAX_OCCUPANCY_CELLS);

    let w = busiest_window(&scene, 250.0).unwrap();
    assert_eq!(w, Window::new(4315.0, 5276.0, 4565.0, 5526.0).unwrap());
    let c = crop_scene(&scene, &w).unwrap();
    let kept: Vec<(u32, &str)> = c
        .buildings
        .iter()
        .map(|b| (b.source_id, b.name.as_str()))
        .collect();
    assert_eq!(
        kept,
        vec![
            (13, "UUID_3d17c044-55ac-4a43-a694-d7a59a230342"),
            (28, "UUID_11430239-5826-4a33-952a-9dd56926afa6")
        ]
    );
    assert_eq!(c.buildings_total, 49);
    // Each building's ground is its own patch in the file: the crop joins them.
    assert!(c.ground_filled);
    assert_eq!(c.extent, w);
    let (glo, ghi) = c.scene.bounds_of(|k| k == ObjectKind::Ground).unwrap();
    assert_eq!(
        [glo[0], glo[1], ghi[0], ghi[1]],
        [4315.0, 5276.0, 4565.0, 5526.0]
    );

    // Written and read back: same buildings, same source coordinates.
    let back = parse_obj(&obj_text(&c.scene), &ObjOptions::default()).unwrap();
    assert_eq!(back.building_count(), 2);
    assert_eq!(back.objects.len(), c.scene.objects.len());
    // The parts stay separate solids, so the ground truth is the same.
    let (a, b) = (
        sample_building_surfaces(&c.scene, 0.25).xyz.len(),
        sample_building_surfaces(&back, 0.25).xyz.len(),
    );
    assert!(a.abs_diff(b) * 1000 < a, "{a} vs {b} GT samples");
    let (blo, bhi) = back.bounds().unwrap();
    let (clo, chi) = c.scene.bounds().unwrap();
    for k in 0..3 {
        let src = |v: f32, o: f64| f64::from(v) + o;
        assert!((src(blo[k], back.origin[k]) - src(clo[k], c.scene.origin[k])).abs() < 1e-3);
        assert!((src(bhi[k], back.origin[k]) - src(chi[k], c.scene.origin[k])).abs() < 1e-3);
    }
}

#[test]
fn zurich_1_km_window_keeps_every_building_whose_centre_it_holds() {
    let Some(path) = real_file("zurich_subset_lod2.json") else {
        return;
    };
    let scene = load_scene(path.to_str().unwrap()).unwrap();
    let boxes = skyground_core::scene::crop::building_boxes(&scene);
    let w = busiest_window(&scene, 1000.0).unwrap();
    let c = crop_scene(&scene, &w).unwrap();
    let inside = boxes
        .iter()
        .filter(|b| {
            let m = b.xy.centre();
            w.contains(m[0], m[1])
        })
        .count();
    // The most buildings any 1 km window of this block holds (windows
    // anchored at building centres, as an optimal one can be).
    let centres: Vec<[f64; 2]> = boxes.iter().map(|b| b.xy.centre()).collect();
    let most = centres
        .iter()
        .flat_map(|a| centres.iter().map(move |b| (a[0], b[1])))
        .map(|(x0, y0)| {
            centres
                .iter()
                .filter(|c| {
                    (x0..=x0 + 1000.0).contains(&c[0]) && (y0..=y0 + 1000.0).contains(&c[1])
                })
                .count()
        })
        .max()
        .unwrap();
    println!(
        "zurich, 1 km window {w:?}: {} of 49 buildings kept; the most any 1 km window holds: {most}",
        c.buildings.len()
    );
    assert_eq!(
        c.buildings.len(),
        inside,
        "every building centred inside is kept"
    );
    assert!(c.buildings.len() > 2, "{} buildings", c.buildings.len());
    assert!(most >= c.buildings.len());
}
