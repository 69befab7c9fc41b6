use super::*;
use crate::scene::{MeshPart, SceneBuilder};

/// A closed box `[x0, x1] × [y0, y1] × [0, h]`.
fn block(x0: f64, y0: f64, x1: f64, y1: f64, h: f64) -> MeshPart {
    block_on(x0, y0, x1, y1, 0.0, h)
}

/// A closed box `[x0, x1] × [y0, y1] × [z, z + h]`.
fn block_on(x0: f64, y0: f64, x1: f64, y1: f64, z: f64, h: f64) -> MeshPart {
    let mut m = MeshPart::default();
    let ring = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
    let lo = m.ring(&ring, z);
    let hi = m.ring(&ring, z + h);
    m.walls(&lo, &hi);
    m.cap(&[&hi], true);
    m.cap(&[&lo], false);
    m
}

/// Ground 0..100 × 0..100 as two triangles (so every crop must clip them);
/// buildings a (10–20, 10–20, 10 m high), b (40–50, 10–20), c (80–95,
/// 80–95) and d in two parts (85–88 × 40–50, 85–88 × 50–60); a tree at (30, 30).
fn town() -> Scene {
    let mut b = SceneBuilder::new([2_600_000.0, 1_200_000.0, 400.0]);
    let mut ground = MeshPart::default();
    let g = ground.ring(
        &[[0.0, 0.0], [100.0, 0.0], [100.0, 100.0], [0.0, 100.0]],
        0.0,
    );
    ground.quad(g[0], g[1], g[2], g[3]);
    b.add("terrain", ObjectKind::Ground, 0, &ground);
    let blocks: [(&str, ObjectKind, u32, [f64; 5]); 6] = [
        ("a", ObjectKind::Building, 1, [10.0, 10.0, 20.0, 20.0, 10.0]),
        ("b", ObjectKind::Building, 2, [40.0, 10.0, 50.0, 20.0, 10.0]),
        ("c", ObjectKind::Building, 3, [80.0, 80.0, 95.0, 95.0, 10.0]),
        (
            "d_south",
            ObjectKind::Building,
            4,
            [85.0, 40.0, 88.0, 50.0, 6.0],
        ),
        (
            "d_north",
            ObjectKind::Building,
            4,
            [85.0, 50.0, 88.0, 60.0, 6.0],
        ),
        (
            "tree_1",
            ObjectKind::Vegetation,
            0,
            [29.0, 29.0, 31.0, 31.0, 8.0],
        ),
    ];
    for (name, kind, id, [x0, y0, x1, y1, h]) in blocks {
        b.add(name, kind, id, &block(x0, y0, x1, y1, h));
    }
    b.finish()
}

fn names(c: &Cropped) -> Vec<(u32, u32, &str)> {
    c.buildings
        .iter()
        .map(|b| (b.source_id, b.id, b.name.as_str()))
        .collect()
}

fn kind_area(s: &Scene, kind: ObjectKind) -> f64 {
    (0..s.triangles.len())
        .filter(|&t| s.triangle_kind(t).is_some_and(|o| o.kind == kind))
        .map(|t| s.triangle_area(t))
        .sum()
}

#[test]
fn keeps_buildings_whose_centre_is_inside_and_clips_the_ground() {
    let scene = town();
    let c = crop_scene(&scene, &Window::new(0.0, 0.0, 60.0, 30.0).unwrap()).unwrap();
    assert_eq!(names(&c), vec![(1, 1, "a"), (2, 2, "b")]);
    assert_eq!(c.buildings_total, 4);
    assert_eq!(c.scene.origin, scene.origin);
    // The tree's centre (30, 30) is on the edge: edges are inside.
    assert_eq!(c.scene.object_count(ObjectKind::Vegetation), 1);
    assert_eq!(c.extent, c.window);
    let (lo, hi) = c.scene.bounds_of(|k| k == ObjectKind::Ground).unwrap();
    assert_eq!((lo, hi), ([0.0, 0.0, 0.0], [60.0, 30.0, 0.0]));
    assert!((kind_area(&c.scene, ObjectKind::Ground) - 1800.0).abs() < 1e-6);
    // Whole buildings: 2 · 10 · 10 + 4 · 10 · 10 = 600 m² each.
    assert!((kind_area(&c.scene, ObjectKind::Building) - 1200.0).abs() < 1e-6);
    assert_eq!(c.scene.building_ids(), vec![1, 2]);
}

#[test]
fn a_building_over_the_edge_stays_whole_and_the_ground_grows_under_it() {
    let scene = town();
    let c = crop_scene(&scene, &Window::new(0.0, 0.0, 15.0, 15.0).unwrap()).unwrap();
    assert_eq!(names(&c), vec![(1, 1, "a")]);
    assert_eq!(c.extent, Window::new(0.0, 0.0, 20.0, 20.0).unwrap());
    assert!((kind_area(&c.scene, ObjectKind::Ground) - 400.0).abs() < 1e-6);
    assert!((kind_area(&c.scene, ObjectKind::Building) - 600.0).abs() < 1e-6);
    assert_eq!(c.scene.object_count(ObjectKind::Vegetation), 0);
}

#[test]
fn ids_are_renumbered_and_parts_stay_together() {
    let scene = town();
    let c = crop_scene(&scene, &Window::new(70.0, 30.0, 100.0, 100.0).unwrap()).unwrap();
    assert_eq!(names(&c), vec![(3, 1, "c"), (4, 2, "d_south")]);
    assert_eq!(c.scene.object_count(ObjectKind::Building), 3);
    assert_eq!(c.scene.building_count(), 2);
    assert_eq!(c.extent, Window::new(70.0, 30.0, 100.0, 100.0).unwrap());
    // d's two parts: 2 · (2 · 3 · 10 + 2 · 6 · 13) = 432 m²; c: 2 · 225 + 4 · 150 = 1050 m².
    assert!((kind_area(&c.scene, ObjectKind::Building) - 1482.0).abs() < 1e-6);
}

#[test]
fn empty_and_invalid_windows_are_errors() {
    let scene = town();
    let err = crop_scene(&scene, &Window::new(60.0, 60.0, 70.0, 70.0).unwrap()).unwrap_err();
    assert_eq!(
        err,
        CropError::EmptyWindow {
            window: Window::new(60.0, 60.0, 70.0, 70.0).unwrap(),
            buildings: Window::new(15.0, 15.0, 87.5, 87.5).unwrap(),
        }
    );
    assert!(err.to_string().contains("holds no building"));
    assert!(matches!(
        Window::new(10.0, 0.0, 5.0, 5.0),
        Err(CropError::InvalidWindow { .. })
    ));
    assert!(matches!(
        "0,0,nan,1".parse::<Window>(),
        Err(CropError::InvalidWindow { .. })
    ));
    assert!(matches!(
        "1,2,3".parse::<Window>(),
        Err(CropError::Syntax { .. })
    ));
    assert_eq!(
        " 1, 2,3 ,4".parse::<Window>().unwrap(),
        Window::new(1.0, 2.0, 3.0, 4.0).unwrap()
    );
    let no_buildings = Scene::default();
    assert_eq!(
        crop_scene(&no_buildings, &Window::new(0.0, 0.0, 1.0, 1.0).unwrap()),
        Err(CropError::NoBuildingsInScene)
    );
    assert_eq!(
        busiest_window(&scene, 0.0),
        Err(CropError::InvalidSize { size: 0.0 })
    );
    assert_eq!(
        busiest_window(&no_buildings, 50.0),
        Err(CropError::NoBuildingsInScene)
    );
}

#[test]
fn busiest_window_holds_the_most_surface() {
    let scene = town();
    // 50 m: c + d (centres (87.5, 87.5) and (86.5, 50), 1050 + 432 m²) beat
    // a + b (1200 m²); the window is centred between their centres, rounded.
    let w = busiest_window(&scene, 50.0).unwrap();
    assert_eq!(w, Window::square([87.0, 69.0], 50.0).unwrap());
    let c = crop_scene(&scene, &w).unwrap();
    assert_eq!(names(&c), vec![(3, 1, "c"), (4, 2, "d_south")]);
    // 35 m: c and d no longer fit together (37.5 m apart in y); a + b (30 m
    // apart) hold 1200 m² against c's 1050.
    let w = busiest_window(&scene, 35.0).unwrap();
    assert_eq!(w, Window::square([30.0, 15.0], 35.0).unwrap());
    let c = crop_scene(&scene, &w).unwrap();
    assert_eq!(names(&c), vec![(1, 1, "a"), (2, 2, "b")]);
    // 20 m: one building at a time; c is the largest.
    let w = busiest_window(&scene, 20.0).unwrap();
    assert_eq!(w, Window::square([88.0, 88.0], 20.0).unwrap());
}

#[test]
fn clipped_neighbours_share_their_cut_points() {
    // Both ground triangles are cut along their shared diagonal's crossing.
    let scene = town();
    let c = crop_scene(&scene, &Window::new(5.0, 5.0, 60.0, 30.0).unwrap()).unwrap();
    let ground: Vec<usize> = (0..c.scene.triangles.len())
        .filter(|&t| {
            c.scene
                .triangle_kind(t)
                .is_some_and(|o| o.kind == ObjectKind::Ground)
        })
        .collect();
    let mut verts: Vec<u32> = ground.iter().flat_map(|&t| c.scene.triangles[t]).collect();
    verts.sort_unstable();
    verts.dedup();
    // Rectangle corners + the two points where the diagonal y = x crosses
    // the window's edges (5, 5) – a corner – and (30, 30) on the top edge.
    assert_eq!(verts.len(), 5);
    assert!((kind_area(&c.scene, ObjectKind::Ground) - 55.0 * 25.0).abs() < 1e-6);
}

/// A flat square of ground `[x0, x1] × [y0, y1]` at height `z`.
fn patch(x0: f64, y0: f64, x1: f64, y1: f64, z: f64) -> MeshPart {
    let mut m = MeshPart::default();
    let g = m.ring(&[[x0, y0], [x1, y0], [x1, y1], [x0, y1]], z);
    m.quad(g[0], g[1], g[2], g[3]);
    m
}

/// The ground's height at `(x, y)` in a cropped scene.
fn ground_at(s: &Scene, x: f64, y: f64) -> Option<f64> {
    let tris: Vec<[[f64; 3]; 3]> = (0..s.triangles.len())
        .filter(|&t| {
            s.triangle_kind(t)
                .is_some_and(|o| o.kind == ObjectKind::Ground)
        })
        .map(|t| s.triangle_corners(t).unwrap().map(crate::scene::vec3::wide))
        .collect();
    let extent = Window::new(-1e4, -1e4, 1e4, 1e4).unwrap();
    fill::GroundLookup::new(&tris, &extent).height(x, y)
}

#[test]
fn ground_islands_become_one_ground() {
    // Two CityJSON-like patches (z 2 and 4) with a 30 m gap between them.
    let mut b = SceneBuilder::new([0.0; 3]);
    b.add(
        "terrain",
        ObjectKind::Ground,
        0,
        &patch(0.0, 0.0, 30.0, 30.0, 2.0),
    );
    b.add(
        "terrain",
        ObjectKind::Ground,
        0,
        &patch(60.0, 0.0, 100.0, 30.0, 4.0),
    );
    b.add(
        "a",
        ObjectKind::Building,
        1,
        &block_on(10.0, 10.0, 20.0, 20.0, 2.0, 10.0),
    );
    b.add(
        "b",
        ObjectKind::Building,
        2,
        &block_on(70.0, 10.0, 80.0, 20.0, 4.0, 10.0),
    );
    let scene = b.finish();
    let c = crop_scene(&scene, &Window::new(0.0, 0.0, 100.0, 30.0).unwrap()).unwrap();
    assert!(c.ground_filled);
    assert_eq!(c.scene.object_count(ObjectKind::Ground), 1);
    // 100 × 30 m, a little more where the gap slopes from 2 m to 4 m.
    let area = kind_area(&c.scene, ObjectKind::Ground);
    assert!((3000.0..3006.0).contains(&area), "{area}");
    // The patches keep their heights; the gap blends the bases (3 m halfway).
    assert_eq!(ground_at(&c.scene, 5.0, 5.0), Some(2.0));
    assert_eq!(ground_at(&c.scene, 95.0, 25.0), Some(4.0));
    let mid = ground_at(&c.scene, 45.0, 15.0).unwrap();
    assert!((mid - 3.0).abs() < 1e-5, "{mid}");
    // A window over one patch only needs no fill.
    let c = crop_scene(&scene, &Window::new(0.0, 0.0, 30.0, 30.0).unwrap()).unwrap();
    assert!(!c.ground_filled);
    assert!((kind_area(&c.scene, ObjectKind::Ground) - 900.0).abs() < 1e-6);
}
