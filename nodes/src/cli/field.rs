//! Writing what a survey team takes to the field (targets, route,
//! completeness) next to the outputs of `skyground detect` and `plan`.

use std::path::{Path, PathBuf};

use skyground_core::cloud::Cloud;
use skyground_core::crs::SourceFrame;
use skyground_core::field::{
    FieldRoute, completeness_csv, completeness_geojson, detection_figures, route_geojson,
    targets_geojson,
};
use skyground_core::missing::Detection;
use skyground_core::targets::TargetSet;

use crate::runtime::RuntimeError;

fn write(path: PathBuf, text: String) -> Result<PathBuf, RuntimeError> {
    skyground_core::file::write(&path, text).map_err(|e| RuntimeError::Node(e.to_string()))?;
    Ok(path)
}

/// `targets.geojson`, `completeness.geojson` and `completeness.csv` in `dir`,
/// in the cloud's CRS and unit.
pub fn write_detection(
    dir: &Path,
    cloud: &Cloud,
    detection: &Detection,
    targets: &TargetSet,
) -> Result<Vec<PathBuf>, RuntimeError> {
    let frame = cloud.frame();
    let rows = detection_figures(detection, targets);
    Ok(vec![
        write(
            dir.join("targets.geojson"),
            format!("{:#}\n", targets_geojson(targets, detection, &frame)),
        )?,
        write(
            dir.join("completeness.geojson"),
            format!("{:#}\n", completeness_geojson(&rows, &frame)),
        )?,
        write(
            dir.join("completeness.csv"),
            completeness_csv(&rows, &frame),
        )?,
    ])
}

/// `route.geojson` in `dir`, in the cloud's CRS and unit.
pub fn write_route(
    dir: &Path,
    cloud: &Cloud,
    plan: &FieldRoute<'_>,
    targets: &TargetSet,
) -> Result<PathBuf, RuntimeError> {
    let frame = cloud.frame();
    write(
        dir.join("route.geojson"),
        format!("{:#}\n", route_geojson(plan, targets, &frame)),
    )
}

/// One building of a mission: outline and measured completeness before/after.
pub struct MissionBuilding<'a> {
    /// Building id.
    pub building: u32,
    /// Footprint, local frame.
    pub outline: &'a geo::MultiPolygon<f64>,
    /// Detection's figures and the targets made for it, matched by overlap.
    pub detected: super::detections::TrueBuildingRow,
    /// Completeness before and after (walls + roofs), 0–1.
    pub before_after: (Option<f64>, Option<f64>),
}

/// The demo's field outputs: `route.geojson` (the driven path) and each
/// building's completeness (`completeness.geojson`, `.csv`) with the measured
/// before/after, the first detection's figures and the targets of every round.
pub fn write_mission(
    dir: &Path,
    frame: &SourceFrame,
    buildings: &[MissionBuilding<'_>],
    path: &[[f32; 3]],
    length_m: f64,
) -> Result<Vec<PathBuf>, RuntimeError> {
    use skyground_core::field::{BuildingFigures, path_geojson};
    let rows: Vec<BuildingFigures> = buildings
        .iter()
        .map(|b| BuildingFigures {
            building: b.building,
            // The given footprint's own id, as the detector's status carries it.
            footprint_id: b
                .detected
                .detection
                .as_ref()
                .map(|d| d.footprint_id.clone())
                .unwrap_or_default(),
            outline: b.outline.clone(),
            detection: b.detected.detection.clone(),
            target_points: b.detected.target_points,
            target_regions: b.detected.target_regions,
            before: b.before_after.0,
            after: b.before_after.1,
        })
        .collect();
    Ok(vec![
        write(
            dir.join("route.geojson"),
            format!("{:#}\n", path_geojson(path, length_m, frame)),
        )?,
        write(
            dir.join("completeness.geojson"),
            format!("{:#}\n", completeness_geojson(&rows, frame)),
        )?,
        write(dir.join("completeness.csv"), completeness_csv(&rows, frame))?,
    ])
}
