//! Models per footprint on a real city: the AHN3 Delft tiles (a real
//! airborne survey, producer's classes) with delft.json's own footprints
//! (BAG ids). The roof parts' size (`min_plane_points`, `min_region_m2`)
//! was chosen on tile 1 and the reference scene; tile 2 is held out.
//!
//! Reads `../shared/data/real` (`SKYGROUND_REAL_DATA` overrides); absent →
//! `SKIPPED: ...`, test passes.

use skyground_core::cloud::read_cloud;
use skyground_core::crs::SourceFrame;
use skyground_core::footprint::Footprint;
use skyground_core::footprint::ReadOptions;
use skyground_core::geom::triangle::height_over;
use skyground_core::io::read_footprints;
use skyground_core::prior::join_tiles;
use skyground_core::reconstruct::party::{PartyWall, ground_plan, party_walls, shared_stretches};
use skyground_core::reconstruct::{
    Lod, Model, ReconstructParams, Reconstruction, Skip, reconstruct_cloud,
};

mod common;
use common::real_file;

#[test]
fn every_delft_building_the_survey_covers_gets_a_valid_model_with_its_bag_id() {
    let (Some(t1), Some(t2), Some(city)) = (
        real_file("ahn3_delft_1.laz"),
        real_file("ahn3_delft_2.laz"),
        real_file("delft.json"),
    ) else {
        return;
    };
    let tiles: Vec<(String, _)> = [t1, t2]
        .iter()
        .map(|p| (p.display().to_string(), read_cloud(p).unwrap()))
        .collect();
    let cloud = join_tiles(&tiles).unwrap();
    let fps = read_footprints(&city.display().to_string(), &ReadOptions::default())
        .unwrap()
        .in_frame(&SourceFrame::new(cloud.origin, None))
        .unwrap()
        .footprints;
    assert_eq!(fps.len(), 160);
    let rec = reconstruct_cloud(&cloud, Some(&fps), &ReconstructParams::default()).unwrap();
    let covered = fps.len()
        - rec
            .skipped
            .iter()
            .filter(|(_, why)| *why == Skip::NoPoints)
            .count();
    let n = rec.models.len();
    eprintln!(
        "delft: {n} models for {covered} covered footprints, skipped {:?}",
        rec.skipped
    );
    assert!(n as f64 >= 0.98 * covered as f64, "{n} of {covered}");
    let valid = rec
        .models
        .iter()
        .filter(|m| m.quality.val3dity.is_empty())
        .count();
    // (id, codes) of the models whose `which` codes are not empty.
    let failing = |which: fn(&Model) -> &Vec<u16>| -> Vec<(u32, Vec<u16>)> {
        rec.models
            .iter()
            .filter(|m| !which(m).is_empty())
            .map(|m| (m.id, which(m).clone()))
            .collect()
    };
    let codes = failing(|m| &m.quality.val3dity);
    let replaced = failing(|m| &m.quality.rejected_val3dity);
    eprintln!(
        "delft: {valid} of {n} valid; failing {codes:?}; invalid LoD 2.2 replaced by LoD 1.2 {replaced:?}"
    );
    // Issue 48's bar; the LoD 2.2 solids alone gave 97.5 % at 4da4053.
    assert!(valid as f64 >= 0.98 * n as f64, "{codes:?}");
    assert!(replaced.len() <= 8, "{replaced:?}");
    for m in rec
        .models
        .iter()
        .filter(|m| !m.quality.rejected_val3dity.is_empty())
    {
        assert_eq!(m.fallback, Some(Skip::InvalidSolid), "building {}", m.id);
        assert!(m.quality.val3dity.is_empty(), "building {}", m.id);
    }
    let median_of = |f: fn(&Model) -> Option<f64>| {
        let mut v: Vec<f64> = rec.models.iter().filter_map(f).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let median = median_of(|m| m.quality.rmse_m);
    let strict = median_of(|m| m.quality.rmse_roof_points_m);
    let mut iou: Vec<f64> = rec
        .models
        .iter()
        .filter_map(|m| m.quality.footprint_iou)
        .collect();
    iou.sort_by(f64::total_cmp);
    let lod12 = rec.models.iter().filter(|m| m.lod == Lod::Lod12).count();
    eprintln!(
        "delft: median RMSE roof-plane points → roof faces {median:.3} m, every roof point {strict:.3} m; {lod12} LoD 1.2; footprint IoU median {:.3}, lowest {:.3}",
        iou[iou.len() / 2],
        iou[0]
    );
    assert_party_walls_meet("delft", &fps, &rec);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("models.city.json");
    skyground_core::io::cityjson::models::write_cityjson(&out, &rec).unwrap();
    let cj = cjval_verdict(&out);
    eprintln!("delft: models.city.json by cjval: {cj}");
    assert_ne!(cj, "invalid");
    // Issue 48's bar, b3_rmse_lod22's meaning (the points on roof planes):
    // 0.036 m. Every roof point (stricter): 0.184 m with smaller roof parts
    // (min_plane_points 8, chosen on tile 1 and the reference scene), 0.302
    // m before; tile 2 alone (held out) 0.126 m, tile 1 0.199 m. AHN3's
    // roofs (5–11 pts/m²) keep the sparse part size whatever the density
    // rule's dense end is set to.
    assert!(median <= 0.15, "{median}");
    assert!(strict < 0.19, "{strict}");
    for m in &rec.models {
        let f = fps.iter().find(|f| f.id == m.id).unwrap();
        assert_eq!(m.name, f.name, "the BAG id goes through");
        assert_eq!(
            m.lod == Lod::Lod12,
            m.fallback.is_some(),
            "building {}",
            m.id
        );
        assert!(m.quality.footprint_iou.unwrap() > 0.5, "building {}", m.id);
    }
}

/// Where the Delft RMSE comes from, per AHN3 tile on its own: the points
/// (class 6 inside the footprint) binned by their distance to the
/// footprint's edge, each bin's share of the points and of the squared
/// error, the points over 0.5 m off (above or below the model), and per
/// building its planes, LoD and RMSE. `SKYGROUND_RECON_PARAMS` (JSON)
/// overrides the defaults, to compare settings on tile 1 before scoring
/// tile 2.
#[test]
fn delft_rmse_breakdown_per_tile() {
    use geo::{Contains, Coord, Distance, Euclidean, Point};
    use skyground_core::metrics::{MeshBackend, MeshDistance};
    use skyground_core::reconstruct::SurfaceType;
    let (Some(t1), Some(t2), Some(city)) = (
        real_file("ahn3_delft_1.laz"),
        real_file("ahn3_delft_2.laz"),
        real_file("delft.json"),
    ) else {
        return;
    };
    let params: ReconstructParams = std::env::var("SKYGROUND_RECON_PARAMS")
        .ok()
        .map_or_else(ReconstructParams::default, |s| {
            serde_json::from_str(&s).unwrap()
        });
    for (tile, path) in [(1, t1), (2, t2)] {
        let cloud = read_cloud(&path).unwrap();
        let fps = read_footprints(&city.display().to_string(), &ReadOptions::default())
            .unwrap()
            .in_frame(&SourceFrame::new(cloud.origin, None))
            .unwrap()
            .footprints;
        let rec = reconstruct_cloud(&cloud, Some(&fps), &params).unwrap();
        let building = cloud.xyz_of_class(6);
        const EDGES: [f64; 4] = [0.5, 1.0, 2.0, f64::INFINITY];
        let (mut n_bin, mut sq_bin, mut sq_roof_bin) = ([0usize; 4], [0f64; 4], [0f64; 4]);
        let (mut above, mut below) = (0usize, 0usize);
        let mut rows = Vec::new();
        let (mut med_all, mut med_roof) = (Vec::new(), Vec::new());
        for m in &rec.models {
            let f = fps.iter().find(|f| f.id == m.id).unwrap();
            let tris = m.shell.triangles();
            let all: Vec<[[f64; 3]; 3]> = tris.iter().map(|t| t.0).collect();
            let roof: Vec<[[f64; 3]; 3]> = tris
                .iter()
                .filter(|t| t.1 == SurfaceType::RoofSurface)
                .map(|t| t.0)
                .collect();
            let (da, dr) = (
                MeshDistance::new(all, MeshBackend::default()),
                MeshDistance::new(roof.clone(), MeshBackend::default()),
            );
            let inside: Vec<[f64; 3]> = building
                .iter()
                .map(|p| p.map(f64::from))
                .filter(|p| f.polygon.contains(&Coord { x: p[0], y: p[1] }))
                .collect();
            if inside.is_empty() {
                continue;
            }
            let (mut sa, mut sr, mut far) = (0.0, 0.0, 0usize);
            for p in &inside {
                let a = da.distance(*p, 50.0).unwrap_or(50.0);
                let r = dr.distance(*p, 50.0).unwrap_or(50.0);
                let e = f
                    .polygon
                    .iter()
                    .flat_map(|pg| std::iter::once(pg.exterior()).chain(pg.interiors()))
                    .map(|ls| Euclidean.distance(&Point::new(p[0], p[1]), ls))
                    .fold(f64::MAX, f64::min);
                let b = EDGES.iter().position(|&x| e < x).unwrap();
                n_bin[b] += 1;
                sq_bin[b] += a * a;
                sq_roof_bin[b] += r * r;
                if r > 0.5 {
                    far += 1;
                    // Above or below the roof face nearest in plan.
                    let z = roof
                        .iter()
                        .filter_map(|t| height_over(t, p[0], p[1], 0.0))
                        .fold(f64::NAN, f64::max);
                    if p[2] > z {
                        above += 1;
                    } else if p[2] <= z {
                        below += 1;
                    }
                }
                sa += a * a;
                sr += r * r;
            }
            let n = inside.len() as f64;
            med_all.push((sa / n).sqrt());
            med_roof.push((sr / n).sqrt());
            rows.push((
                (sr / n).sqrt(),
                m.id,
                inside.len(),
                m.planes,
                m.lod.as_str(),
                far as f64 / n,
            ));
        }
        let med = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let mut q: Vec<f64> = rec
            .models
            .iter()
            .filter_map(|m| m.quality.rmse_roof_points_m)
            .collect();
        let mut b3: Vec<f64> = rec.models.iter().filter_map(|m| m.quality.rmse_m).collect();
        let valid = rec
            .models
            .iter()
            .filter(|m| m.quality.val3dity.is_empty())
            .count();
        let lod12 = rec.models.iter().filter(|m| m.lod == Lod::Lod12).count();
        let (median, b3) = (med(&mut q), med(&mut b3));
        // The held-out tile under the defaults: every roof point 0.126 m
        // (issue 48's bar is 0.15 m), every model valid.
        if tile == 2 && std::env::var_os("SKYGROUND_RECON_PARAMS").is_none() {
            assert!(median <= 0.13, "{median}");
            assert!(b3 <= 0.05, "{b3}");
            assert_eq!(valid, rec.models.len());
        }
        eprintln!(
            "tile {tile}: median quality RMSE roof-plane points (b3) {b3:.3} m, every roof point {median:.3} m; {valid} valid, {lod12} LoD 1.2, {} replaced",
            rec.models
                .iter()
                .filter(|m| !m.quality.rejected_val3dity.is_empty())
                .count()
        );
        let total: usize = n_bin.iter().sum();
        let (sq, sqr): (f64, f64) = (sq_bin.iter().sum(), sq_roof_bin.iter().sum());
        eprintln!(
            "tile {tile}: {} models, median RMSE all faces {:.3} m, roof faces only {:.3} m; points > 0.5 m off the roof: {above} above, {below} below",
            rec.models.len(),
            med(&mut med_all),
            med(&mut med_roof)
        );
        for b in 0..4 {
            eprintln!(
                "  edge distance < {:>4} m: {:5.1} % of points, {:5.1} % of squared error (all faces), {:5.1} % (roof only)",
                EDGES[b],
                100.0 * n_bin[b] as f64 / total as f64,
                100.0 * sq_bin[b] / sq,
                100.0 * sq_roof_bin[b] / sqr
            );
        }
        rows.sort_by(|a, b| b.0.total_cmp(&a.0));
        for r in rows.iter().take(15) {
            eprintln!(
                "  worst: rmse {:.3} id {} points {} planes {} lod {} far {:.2}",
                r.0, r.1, r.2, r.3, r.4, r.5
            );
        }
        assert_eq!(total, rows.iter().map(|r| r.2).sum::<usize>());
    }
}

/// What the RMSE counts as roof points (`b3_rmse_lod22` measures the roof).
#[test]
fn facade_points_under_the_eaves_are_not_roof_points_but_a_low_porch_is() {
    let mut pts: Vec<[f32; 3]> = Vec::new();
    // A roof at 6 m over x, y in [0, 4], eaves reaching to x = -0.4.
    for i in 0..=22 {
        for j in 0..=20 {
            pts.push([-0.4 + 0.2 * i as f32, 0.2 * j as f32, 6.0]);
        }
    }
    let roof = pts.len();
    // A facade at x = 0 from 0.5 m to 5 m, under the eaves.
    for k in 0..10 {
        pts.push([0.05, 2.0, 0.5 + 0.5 * k as f32]);
    }
    // A porch roof at 3 m beside the house, nothing over it.
    pts.push([-2.0, 2.0, 3.0]);
    let seen = skyground_core::reconstruct::quality::seen_from_above(&pts);
    assert!(seen[..roof].iter().all(|s| *s));
    assert!(seen[roof..roof + 10].iter().all(|s| !*s));
    assert!(seen[roof + 10]);
}

/// Issue 48's must-show on the multi-building CityJSON files of other
/// projects (`../shared/data/conformance`, and 3DBAG's two buildings in
/// `../shared/data/real`): the simulated airborne survey of each (config/aerial.yaml's
/// survey, its true classes), reconstructed per the file's own buildings
/// (`--footprints model`). Per file: a model for ≥ 98 % of the buildings,
/// ≥ 98 % of the models valid by our ISO 19107 checks, models.city.json
/// valid by cjval (when installed), the median RMSE printed.
#[test]
fn every_building_of_the_multi_building_city_files_gets_a_valid_model() {
    use skyground_core::io::cityjson::models::write_cityjson;
    use skyground_core::io::load_scene;
    use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
    const FILES: [&str; 8] = [
        "3dfier_testarea.json",
        "cjio_multi_lod.json",
        "val3dity_twobuildings_m.json",
        "cjval_address.json",
        "val3dity_several_lods_valid.json",
        "cjio_mt-1-triangulated.json",
        "cjseq_3dbag_b2.city.jsonl",
        "cjval_many.json",
    ];
    let mut paths: Vec<_> = FILES
        .iter()
        .filter_map(|f| common::conformance_file(f))
        .collect();
    if paths.len() < FILES.len() {
        return;
    }
    paths.extend(real_file("3dbag_2buildings.city.json"));
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for path in &paths {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let scene = load_scene(path.to_str().unwrap()).unwrap();
        let caster = Caster::new(&scene).unwrap();
        let survey = AirborneConfig {
            seed: 1,
            ..AirborneConfig::default()
        };
        let cloud = airborne_scan(&caster, &survey).unwrap();
        // Per BuildingPart where the file models its buildings so (3DBAG), as `--parts`.
        let per_part = ReadOptions {
            parts: true,
            ..ReadOptions::default()
        };
        let loaded = read_footprints(&path.display().to_string(), &per_part)
            .unwrap()
            .in_frame(&SourceFrame::new(cloud.origin, None))
            .unwrap();
        let fps = loaded.footprints;
        let mut rec = reconstruct_cloud(&cloud, Some(&fps), &ReconstructParams::default()).unwrap();
        rec.part_of = loaded.part_of;
        let n = rec.models.len();
        let valid = rec
            .models
            .iter()
            .filter(|m| m.quality.val3dity.is_empty())
            .count();
        let lod12 = rec.models.iter().filter(|m| m.lod == Lod::Lod12).count();
        let mut rmse: Vec<f64> = rec.models.iter().filter_map(|m| m.quality.rmse_m).collect();
        rmse.sort_by(f64::total_cmp);
        let median = rmse.get(rmse.len() / 2).copied().unwrap_or(f64::NAN);
        let out = dir.path().join(format!("{name}.models.city.json"));
        write_cityjson(&out, &rec).unwrap();
        let cj = cjval_verdict(&out);
        eprintln!(
            "{name}: {n} models / {} buildings, {valid} valid, {lod12} LoD 1.2, median RMSE {median:.3} m, cjval {cj}; skipped {:?}",
            fps.len(),
            rec.skipped
        );
        if (n as f64) < 0.98 * fps.len() as f64 || (valid as f64) < 0.98 * n as f64 {
            failures.push(format!(
                "{name}: {n} models, {valid} valid of {}",
                fps.len()
            ));
        }
        // Issue 48's RMSE bar, where a median says something (≥ 10 buildings).
        if fps.len() >= 10 && (median.is_nan() || median > 0.15) {
            failures.push(format!("{name}: median RMSE {median:.3} m"));
        }
        if cj == "invalid" {
            failures.push(format!("{name}: cjval finds models.city.json invalid"));
        }
        // A part's model is a BuildingPart of the Building named by the input.
        let doc: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
        let objects = doc["CityObjects"].as_object().unwrap();
        let written_parts = objects
            .values()
            .filter(|o| o["type"] == "BuildingPart")
            .count();
        if written_parts != rec.part_of.len()
            || rec
                .part_of
                .values()
                .any(|b| objects.get(b).is_none_or(|o| o["type"] != "Building"))
        {
            failures.push(format!(
                "{name}: {written_parts} BuildingParts written for {} part models",
                rec.part_of.len()
            ));
        }
        if name == "3dfier_testarea.json" {
            assert_party_walls_meet(&name, &fps, &rec);
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Issue 48 part 3: where two footprints share a stretch of boundary, the
/// two models' ground plans meet on it, with neither a gap nor an overlap
/// wider than 1 mm (the welding tolerance: the plans are the footprints'
/// rings, which meet exactly, so only welding can move them apart).
/// Measured on the reconstruction the caller already made; the figures are
/// printed per file.
fn assert_party_walls_meet(name: &str, fps: &[Footprint], rec: &Reconstruction) {
    const TOL_M: f64 = 0.001;
    let started = std::time::Instant::now();
    let plans: Vec<_> = rec
        .models
        .iter()
        .map(|m| (m.id, ground_plan(&m.shell)))
        .collect();
    let walls = party_walls(fps, &plans);
    let stat = |f: &dyn Fn(&PartyWall) -> f64| -> (f64, f64, f64) {
        let mut v: Vec<f64> = walls.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        let med = v.get(v.len() / 2).copied().unwrap_or(0.0);
        (med, v.last().copied().unwrap_or(0.0), v.iter().sum())
    };
    let length = stat(&|w| w.models.length_m).2;
    let (fo, fg) = (
        stat(&|w| w.footprints.max_offset_m),
        stat(&|w| w.footprints.gap_m2),
    );
    let fov = stat(&|w| w.footprints.overlap_m2);
    let fc = stat(&|w| w.footprints.missing_corners as f64).2;
    let mc = stat(&|w| w.models.missing_corners as f64).2;
    let (g, o) = (stat(&|w| w.models.gap_m2), stat(&|w| w.models.overlap_m2));
    let (d, x) = (
        stat(&|w| w.models.max_offset_m),
        stat(&|w| w.models.intersection_m2),
    );
    let off = walls
        .iter()
        .filter(|w| w.models.max_offset_m > TOL_M)
        .count();
    eprintln!(
        "{name}: party walls: {} pairs, {length:.1} m shared; footprints: max offset {:.4} m, gap {:.4} m², overlap {:.4} m², {fc} corners one lacks",
        walls.len(),
        fo.1,
        fg.2,
        fov.2
    );
    eprintln!(
        "{name}: party walls, models: gap median {:.3} max {:.3} total {:.2} m²; overlap median {:.3} max {:.3} total {:.2} m²; wall offset median {:.4} max {:.4} m ({off} pairs over 1 mm); plans intersect max {:.4} m²; {mc} footprint corners on a shared wall missing from a model; measured in {:.2} s",
        g.0,
        g.1,
        g.2,
        o.0,
        o.1,
        o.2,
        d.0,
        d.1,
        x.1,
        started.elapsed().as_secs_f64()
    );
    // Every shared stretch whose two footprints got a model is measured.
    let modelled = |id: u32| rec.models.iter().any(|m| m.id == id);
    let expected = shared_stretches(fps)
        .iter()
        .filter(|s| modelled(s.a) && modelled(s.b))
        .count();
    assert_eq!(walls.len(), expected, "{name}");
    for w in &walls {
        let bound = TOL_M * w.models.length_m;
        assert!(
            w.models.max_offset_m <= TOL_M
                && w.models.gap_m2 <= bound
                && w.models.overlap_m2 <= bound
                && w.models.intersection_m2 <= bound
                && w.models.missing_corners <= w.footprints.missing_corners,
            "{name}: models {} and {} along their shared wall: {:?} (footprints: {:?})",
            w.a,
            w.b,
            w.models,
            w.footprints
        );
    }
}

/// cjval's verdict on `path` ("valid", "invalid"; "SKIPPED" without cjval).
fn cjval_verdict(path: &std::path::Path) -> &'static str {
    let local = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../.tools/bin/cjval");
    let exe = if local.is_file() {
        local
    } else {
        std::path::PathBuf::from("cjval")
    };
    let Ok(out) = std::process::Command::new(&exe)
        .arg("-r")
        .arg(path)
        .output()
    else {
        eprintln!("SKIPPED: cjval not installed (tests/run_all.sh installs it into .tools)");
        return "SKIPPED";
    };
    // cjval exits 0 either way: its verdict is in the JSON report.
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or_default();
    if report["valid"] == true && report["has_warnings"] == false {
        "valid"
    } else {
        eprintln!(
            "{}: {}",
            path.display(),
            String::from_utf8_lossy(&out.stdout)
        );
        "invalid"
    }
}
