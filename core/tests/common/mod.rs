//! What the integration tests share: where the real data is.

use std::path::PathBuf;

use skyground_core::classify::{
    DEFAULT_DENSITIES, FileRole, Model, TrainParams, default_training_set, file_training_clouds,
    pulse_sample, train,
};
use skyground_core::cloud::{Cloud, read_cloud};
use skyground_core::footprint::Loaded;
use skyground_core::ground::CsfParams;
use skyground_core::io::load_footprints;

/// The forest the shipped model learned as vegetation.
#[allow(dead_code)]
pub const BC_FOREST: &str = "lasr_bcts_forest_1.laz";
/// The IGN LiDAR HD tiles (producer classes 2–6).
#[allow(dead_code)]
pub const IGN: [&str; 2] = ["ign_montpellier_150x100m.laz", "ign_stbarth_100x100m.laz"];

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

/// `name` in the conformance folder next to the real one
/// (`../shared/data/conformance`); `None`, said plainly, when it is absent.
#[allow(dead_code)]
pub fn conformance_file(name: &str) -> Option<PathBuf> {
    let real = real_file("")?;
    let path = real.parent()?.join("conformance").join(name);
    if !path.is_file() {
        eprintln!("SKIPPED: {} not found", path.display());
        return None;
    }
    Some(path)
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

/// AHN3 Delft 2 (held out from the shipped model) kept to 22 % of its
/// pulses (seed 7), about 2.25 pts/m²: a sparse survey with the producer's
/// classes; `None` when the real data is absent.
#[allow(dead_code)]
pub fn sparse_delft_2() -> Option<Cloud> {
    let path = real_file("ahn3_delft_2.laz")?;
    let full = read_cloud(&path).unwrap_or_else(|e| panic!("ahn3_delft_2.laz: {e}"));
    Some(full.subset(&pulse_sample(&full, 0.22, 7)))
}

/// The shipped model (config/classifier_model.json.gz).
#[allow(dead_code)]
pub fn shipped() -> Model {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../config/classifier_model.json.gz");
    Model::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// A model trained as `skyground train --in LABELLED --vegetation-in
/// BC_FOREST` would train it; `None` when the real data is absent.
#[allow(dead_code)]
pub fn trained_on(labelled: &[&str]) -> Option<Model> {
    trained_with_forests(labelled, &[BC_FOREST])
}

/// A model trained as `skyground train --in LABELLED [--vegetation-in
/// FORESTS]` would train it; `None` when the real data is absent.
#[allow(dead_code)]
pub fn trained_with_forests(labelled: &[&str], forests: &[&str]) -> Option<Model> {
    let mut set = default_training_set().unwrap_or_else(|e| panic!("{e}"));
    let labelled = labelled.iter().map(|n| (*n, FileRole::Labelled));
    let forests = forests.iter().map(|n| (*n, FileRole::Forest));
    for (name, role) in labelled.chain(forests) {
        let cloud = read_cloud(&real_file(name)?).unwrap_or_else(|e| panic!("{name}: {e}"));
        let clouds =
            file_training_clouds(name, cloud, role, &DEFAULT_DENSITIES, &CsfParams::default())
                .unwrap_or_else(|e| panic!("{name}: {e}"));
        set.extend(clouds);
    }
    Some(train(&set, &TrainParams::default()).unwrap_or_else(|e| panic!("{e}")))
}
