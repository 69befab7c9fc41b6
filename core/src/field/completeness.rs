//! `completeness.geojson` and `completeness.csv`: one row per building with
//! its outline and how complete its walls are.

use geo::{Centroid, MultiPolygon};
use serde_json::{Value, json};

use crate::crs::SourceFrame;
use crate::io::geojson::write::{feature, feature_collection, multipolygon};
use crate::missing::{Detection, Strategy};
use crate::targets::TargetSet;

/// One building's figures.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildingFigures {
    /// Building id.
    pub building: u32,
    /// Its footprint's own id (BAG `identificatie`, OSM id, CityObject id),
    /// empty when unknown.
    pub footprint_id: String,
    /// Outline, local frame (metres).
    pub outline: MultiPolygon<f64>,
    /// What detection found for it, when a detected building matches it.
    pub detection: Option<DetectedFigures>,
    /// Point targets made for it.
    pub target_points: usize,
    /// Regions made for it.
    pub target_regions: usize,
    /// Measured completeness before the mission (0–1), when known.
    pub before: Option<f64>,
    /// Measured completeness after the mission (0–1), when known.
    pub after: Option<f64>,
}

/// Detection's figures for one building.
#[derive(Debug, Clone, PartialEq)]
pub struct DetectedFigures {
    /// The detected building's footprint id (empty when it had none).
    pub footprint_id: String,
    /// Building points in the prior.
    pub points: usize,
    /// Why it was not analysed, when it was not.
    pub skipped: Option<String>,
    /// Boundary points of its global contour.
    pub boundary_points: usize,
    /// Boundary points detected as missing wall.
    pub missing_points: usize,
    /// R_missing = missing / boundary.
    pub r_missing: f64,
    /// Point- or region-based, when analysed.
    pub strategy: Option<Strategy>,
}

/// The figures detection gives: detected completeness is 1 − R_missing.
pub fn detection_figures(detection: &Detection, targets: &TargetSet) -> Vec<BuildingFigures> {
    detection
        .buildings
        .iter()
        .map(|b| BuildingFigures {
            building: b.building,
            footprint_id: b.footprint_id.clone(),
            outline: b.global_contour.clone(),
            detection: Some(DetectedFigures {
                footprint_id: b.footprint_id.clone(),
                points: b.points,
                skipped: b.skipped.as_ref().map(ToString::to_string),
                boundary_points: b.boundary.len(),
                missing_points: b.missing.len(),
                r_missing: f64::from(b.r_missing),
                strategy: b.skipped.is_none().then_some(b.strategy),
            }),
            target_points: targets.counts_of(b.building).0,
            target_regions: targets.counts_of(b.building).1,
            before: None,
            after: None,
        })
        .collect()
}

fn strategy_name(s: Option<Strategy>) -> &'static str {
    match s {
        Some(Strategy::PointBased) => "point_based",
        Some(Strategy::RegionBased) => "region_based",
        None => "",
    }
}

impl DetectedFigures {
    /// Detected completeness, 1 − R_missing, when it was analysed.
    pub fn completeness(&self) -> Option<f64> {
        (self.skipped.is_none() && self.boundary_points > 0).then_some(1.0 - self.r_missing)
    }
}

/// The buildings' outlines with their figures, in the source CRS and unit
/// (buildings without an outline are left out of the GeoJSON, not the CSV).
pub fn completeness_geojson(rows: &[BuildingFigures], frame: &SourceFrame) -> Value {
    let features = rows
        .iter()
        .filter(|b| !b.outline.0.is_empty())
        .map(|b| {
            let d = b.detection.as_ref();
            feature(
                multipolygon(frame, &b.outline),
                json!({
                    "building": b.building,
                    "footprint_id": (!b.footprint_id.is_empty()).then_some(&b.footprint_id),
                    "points": d.map(|d| d.points),
                    "skipped": d.and_then(|d| d.skipped.clone()),
                    "boundary_points": d.map(|d| d.boundary_points),
                    "missing_points": d.map(|d| d.missing_points),
                    "r_missing": d.map(|d| d.r_missing),
                    "detected_completeness": d.and_then(DetectedFigures::completeness),
                    "strategy": d.map(|d| strategy_name(d.strategy)),
                    "target_points": b.target_points,
                    "target_regions": b.target_regions,
                    "completeness_before": b.before,
                    "completeness_after": b.after,
                }),
            )
        })
        .collect();
    feature_collection(frame, "completeness", features)
}

/// The same figures as CSV, with each outline's centroid in the source CRS
/// (a building no detected building matches has empty detection cells).
pub fn completeness_csv(rows: &[BuildingFigures], frame: &SourceFrame) -> String {
    let sym = frame.unit().symbol().to_string();
    let mut out = format!(
        "building,footprint_id,centroid_x_{sym},centroid_y_{sym},points,skipped,boundary_points,missing_points,r_missing,detected_completeness,strategy,target_points,target_regions,completeness_before,completeness_after\n"
    );
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.4}"));
    for b in rows {
        let c = b
            .outline
            .centroid()
            .map(|c| frame.to_source_xy([c.x(), c.y()]));
        let (cx, cy) = c.map_or((String::new(), String::new()), |c| {
            (format!("{:.3}", c[0]), format!("{:.3}", c[1]))
        });
        let detected = b.detection.as_ref().map_or_else(
            || ",,,,,,".to_string(),
            |d| {
                let skipped = d.skipped.as_deref().map_or(String::new(), csv_text);
                format!(
                    "{},{skipped},{},{},{:.4},{},{}",
                    d.points,
                    d.boundary_points,
                    d.missing_points,
                    d.r_missing,
                    opt(d.completeness()),
                    strategy_name(d.strategy)
                )
            },
        );
        out.push_str(&format!(
            "{},{},{cx},{cy},{detected},{},{},{},{}\n",
            b.building,
            csv_text(&b.footprint_id),
            b.target_points,
            b.target_regions,
            opt(b.before),
            opt(b.after),
        ));
    }
    out
}

/// A CSV cell: quoted when it holds a comma, quote or line break (RFC 4180).
fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}
