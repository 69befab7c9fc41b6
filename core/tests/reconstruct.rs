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
    let rec = reconstruct_cloud(
        &cloud,
        Some(&loaded.footprints),
        &ReconstructParams::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(rec.models.len(), 1, "skipped: {:?}", rec.skipped);
    let m = &rec.models[0];
    let check = m.shell.check();
    assert!(check.valid(), "{check:?}");
    // The file also holds points around the building: City3D's measure is
    // over the building's own points (on its footprint).
    let (d, n) = points_to_models(&rec, &cloud.xyz).expect("distances");
    eprintln!(
        "city3d_001: {} roof planes, {} faces, mean points → model distance {d:.3} m over {n} of {} points",
        m.planes,
        m.shell.faces.len(),
        cloud.len()
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
