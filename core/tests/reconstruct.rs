//! LoD2 reconstruction of City3D's real building 001 (57,379 airborne
//! points and its footprint): a valid closed model whose surface the
//! points lie close to (City3D's own measure), and valid CityJSON (cjval,
//! when installed: `tests/run_all.sh` puts it in `.tools/bin`).

use std::path::PathBuf;

use skyground_core::io::cityjson::models as cityjson;
use skyground_core::reconstruct::evaluate::points_to_models;
use skyground_core::reconstruct::{ReconstructParams, reconstruct_cloud};

mod common;
use common::city3d_001;

/// `cjval` from `SKYGROUND_CJVAL`, the workspace's `.tools/bin`, or PATH.
fn cjval() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("SKYGROUND_CJVAL") {
        return Some(PathBuf::from(p));
    }
    let local = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../.tools/bin/cjval");
    if local.is_file() {
        return Some(local);
    }
    std::process::Command::new("cjval")
        .arg("--version")
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|_| PathBuf::from("cjval"))
}

#[test]
fn city3d_001_gives_a_valid_model_close_to_its_points() {
    let Some((cloud, loaded)) = city3d_001() else {
        return;
    };
    assert_eq!(loaded.footprints.len(), 1);
    // `SKYGROUND_RECON_PARAMS` (JSON) overrides the defaults, to compare settings.
    let params: ReconstructParams = std::env::var("SKYGROUND_RECON_PARAMS")
        .ok()
        .map_or_else(ReconstructParams::default, |s| {
            serde_json::from_str(&s).unwrap()
        });
    let rec = reconstruct_cloud(&cloud, Some(&loaded.footprints), &params)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(rec.models.len(), 1, "skipped: {:?}", rec.skipped);
    let m = &rec.models[0];
    let check = m.shell.check();
    assert!(check.valid(), "{check:?}");
    // The file also holds points around the building: City3D's measure is
    // over the building's own points (on its footprint).
    let (d, n) = points_to_models(&rec, &cloud.xyz).expect("distances");
    eprintln!(
        "city3d_001: {} roof planes, {} faces, mean points → model distance {d:.3} m over {n} of {} points; LoD {}, rejected LoD 2.2 codes {:?}",
        m.planes,
        m.shell.faces.len(),
        cloud.len(),
        m.lod.as_str(),
        m.quality.rejected_val3dity
    );
    let given =
        skyground_core::footprint::split(&cloud.xyz, &loaded.footprints, &Default::default())
            .unwrap_or_else(|e| panic!("{e}"));
    let on_given = given.iter().filter(|id| **id != 0).count();
    assert!(
        n * 20 >= on_given * 19,
        "{n} points on the model's outline, {on_given} on the given footprint"
    );
    // Issue 13's bar. 0.070 m measured; 0.253 m before long narrow roof
    // slopes (linearity > 0.95) stopped being taken for rows of points.
    assert!(d <= 0.25, "mean points → model distance {d:.3} m");
    let Some(cjval) = cjval() else {
        eprintln!(
            "SKIPPED (cjval part): cjval not installed (cargo install cjval --features build-binary)"
        );
        return;
    };
    let path =
        std::env::temp_dir().join(format!("skyground_city3d_{}.city.json", std::process::id()));
    cityjson::write_cityjson(&path, &rec).unwrap_or_else(|e| panic!("{e}"));
    let out = std::process::Command::new(&cjval)
        .arg("-s")
        .arg(&path)
        .output()
        .unwrap_or_else(|e| panic!("{}: {e}", cjval.display()));
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    let _ = std::fs::remove_file(&path);
    assert!(
        text.contains("File is valid") && !text.contains("File is invalid"),
        "cjval: {text}"
    );
}

/// The reference scene's simulated prior (config/aerial.yaml's survey),
/// reconstructed on derived footprints and on the scene's own: the models'
/// mean symmetric distance to the true buildings and the median RMSE
/// (roof points to roof faces). `SKYGROUND_RECON_PARAMS` (JSON) overrides
/// the defaults, to compare settings.
#[test]
fn reference_prior_models_lie_close_to_the_true_buildings() {
    use skyground_core::footprint::footprints_of_scene;
    use skyground_core::io::load_scene;
    use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
    use skyground_core::metrics::sample_building_surfaces;
    use skyground_core::reconstruct::evaluate_models;
    let params: ReconstructParams = std::env::var("SKYGROUND_RECON_PARAMS")
        .ok()
        .map_or_else(ReconstructParams::default, |s| {
            serde_json::from_str(&s).unwrap()
        });
    let scene = load_scene("reference").unwrap();
    let caster = Caster::new(&scene).unwrap();
    let survey = AirborneConfig {
        seed: 1,
        ..AirborneConfig::default()
    };
    let cloud = airborne_scan(&caster, &survey).unwrap();
    let gt = sample_building_surfaces(&scene, 0.25);
    let own = footprints_of_scene(&scene);
    for (what, fps) in [("derived", None), ("own", Some(own.as_slice()))] {
        let rec = reconstruct_cloud(&cloud, fps, &params).unwrap();
        let ev = evaluate_models(&scene, &gt, &rec, 0.25);
        let mut rmse: Vec<f64> = rec.models.iter().filter_map(|m| m.quality.rmse_m).collect();
        rmse.sort_by(f64::total_cmp);
        let median = rmse[rmse.len() / 2];
        let mean = ev.distance.mean.unwrap();
        let valid = rec
            .models
            .iter()
            .filter(|m| m.quality.val3dity.is_empty())
            .count();
        eprintln!(
            "reference prior, {what} footprints: {} models, {valid} valid, mean distance to the truth {mean:.4} m, median RMSE {median:.3} m, without model {:?}",
            rec.models.len(),
            ev.without_model
        );
        for b in ev
            .buildings
            .iter()
            .filter(|b| b.distance.mean.is_none_or(|d| d > 0.1))
        {
            eprintln!(
                "  far: building {} models {:?} mean {:?} roof error {:?} iou {:?}",
                b.building, b.models, b.distance.mean, b.roof_error, b.footprint_iou
            );
        }
        assert!(
            ev.without_model.is_empty(),
            "{what}: {:?}",
            ev.without_model
        );
        assert_eq!(valid, rec.models.len(), "{what}");
        assert!(mean < 0.1, "{what}: {mean}");
    }
}
