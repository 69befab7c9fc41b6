//! What the integration tests share: where the real data is.

use std::path::PathBuf;

use skyground_core::cloud::{Cloud, read_cloud};
use skyground_core::footprint::{Loaded, load_footprints};

/// `name` in the real-data folder (`SKYGROUND_REAL_DATA`, else
/// `../shared/data/real`); `None`, said plainly, when the folder is absent.
pub fn real_file(name: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("SKYGROUND_REAL_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/real"),
        PathBuf::from,
    );
    if !dir.is_dir() {
        eprintln!(
            "SKIPPED: ../shared/data/real not found (looked in {})",
            dir.display()
        );
        return None;
    }
    Some(dir.join(name))
}

/// The City3D sample building: its cloud, and its footprint (OBJ) loaded in
/// the cloud's frame; `None` when the real data is absent.
#[allow(dead_code)] // Not every test file that shares this module reads it.
pub fn city3d_001() -> Option<(Cloud, Loaded)> {
    let (ply, obj) = (
        real_file("city3d_001.ply")?,
        real_file("city3d_001_footprint.obj")?,
    );
    let cloud = read_cloud(&ply).unwrap_or_else(|e| panic!("{e}"));
    let loaded = load_footprints(&obj, cloud.origin).unwrap_or_else(|e| panic!("{e}"));
    Some((cloud, loaded))
}
