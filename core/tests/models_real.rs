//! Models per footprint on a real city: the AHN3 Delft tiles (a real
//! airborne survey, producer's classes) with delft.json's own footprints
//! (BAG ids). Nothing was tuned on these files: the reconstruction's
//! parameters were set on simulated scenes.
//!
//! Reads `../shared/data/real` (`SKYGROUND_REAL_DATA` overrides); absent →
//! `SKIPPED: ...`, test passes.

use skyground_core::cloud::read_cloud;
use skyground_core::crs::SourceFrame;
use skyground_core::footprint::ReadOptions;
use skyground_core::io::read_footprints;
use skyground_core::prior::join_tiles;
use skyground_core::reconstruct::{Lod, Model, ReconstructParams, Skip, reconstruct_cloud};

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
    let mut rmse: Vec<f64> = rec.models.iter().filter_map(|m| m.quality.rmse_m).collect();
    rmse.sort_by(f64::total_cmp);
    let median = rmse[rmse.len() / 2];
    eprintln!("delft: median RMSE points → model {median:.3} m");
    assert!(median < 0.3, "{median}");
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
