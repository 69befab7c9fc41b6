//! `targets.geojson`: ground stops (Points) and regions to explore (Polygons),
//! each with its building and why it is there.

use geo::{Area, Contains, Coord, LineString, Point, Polygon};
use serde_json::{Value, json};

use crate::crs::SourceFrame;
use crate::io::geojson::write::{feature, feature_collection, position, ring};
use crate::missing::{Detection, MissingPoint, Strategy};
use crate::targets::TargetSet;

fn strategy(s: Strategy) -> &'static str {
    match s {
        Strategy::PointBased => "point_based",
        Strategy::RegionBased => "region_based",
    }
}

fn round3(v: f64) -> f64 {
    (v * 1e3).round() / 1e3
}

/// The targets as a FeatureCollection in the source CRS and unit.
///
/// Points say which building's gap they look at, the nearest missing point
/// (distance and height, source unit) and the building's R_missing; regions
/// say their area (source unit²) and how many missing points lie inside.
pub fn targets_geojson(targets: &TargetSet, detection: &Detection, frame: &SourceFrame) -> Value {
    let unit = frame.unit();
    let f = frame.to_metre();
    let building = |id: u32| detection.buildings.iter().find(|b| b.building == id);
    let own_id = |id: u32| {
        building(id)
            .map(|b| b.footprint_id.as_str())
            .filter(|s| !s.is_empty())
    };
    let mut features = Vec::new();
    for (i, t) in targets.points.iter().enumerate() {
        let b = building(t.building);
        let missing: &[MissingPoint] = b.map_or(&[][..], |b| b.missing.as_slice());
        let nearest = missing
            .iter()
            .map(|m| {
                let d = (m.xyz[0] - t.xyz[0]).hypot(m.xyz[1] - t.xyz[1]);
                (d, m.xyz[2] - t.xyz[2])
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let r = b.map_or(0.0, |b| b.r_missing);
        let why = match nearest {
            Some((d, h)) => format!(
                "ground stop seeing missing wall of building {} ({:.1} {sym} away, {:.1} {sym} up; R_missing {:.2} < θ: point-based)",
                t.building,
                frame.length_to_source(f64::from(d)),
                f64::from(h) / f[2],
                r,
                sym = unit.symbol()
            ),
            None => format!("ground stop for building {}", t.building),
        };
        let p = t.xyz.map(f64::from);
        features.push(feature(
            json!({"type": "Point", "coordinates": position(frame, p)}),
            json!({
                "kind": "point",
                "index": i,
                "building": t.building,
                "footprint_id": own_id(t.building),
                "strategy": strategy(Strategy::PointBased),
                "why": why,
                "gap_distance": nearest.map(|n| round3(frame.length_to_source(f64::from(n.0)))),
                "gap_height": nearest.map(|n| round3(f64::from(n.1) / f[2])),
                "building_missing_points": missing.len(),
                "r_missing": r,
            }),
        ));
    }
    for (i, reg) in targets.regions.iter().enumerate() {
        let b = building(reg.building);
        let poly = Polygon::new(
            LineString::from(
                reg.polygon
                    .iter()
                    .map(|p| Coord { x: p[0], y: p[1] })
                    .collect::<Vec<_>>(),
            ),
            vec![],
        );
        let inside: Vec<&MissingPoint> = b.map_or(Vec::new(), |b| {
            b.missing
                .iter()
                .filter(|m| poly.contains(&Point::new(f64::from(m.xyz[0]), f64::from(m.xyz[1]))))
                .collect()
        });
        let area = poly.unsigned_area() / (f[0] * f[0]);
        let r = b.map_or(0.0, |b| b.r_missing);
        let why = format!(
            "region to explore around a large gap of building {} ({} missing points inside, {:.0} {}²; R_missing {:.2} ≥ θ: region-based)",
            reg.building,
            inside.len(),
            area,
            unit.symbol(),
            r
        );
        features.push(feature(
            json!({"type": "Polygon", "coordinates": [ring(frame, &reg.polygon)]}),
            json!({
                "kind": "region",
                "index": i,
                "building": reg.building,
                "footprint_id": own_id(reg.building),
                "strategy": strategy(Strategy::RegionBased),
                "why": why,
                "area": round3(area),
                "gap_points": inside.len(),
                "ground_z": round3(frame.to_source([0.0, 0.0, f64::from(reg.z)])[2]),
                "r_missing": r,
            }),
        ));
    }
    feature_collection(frame, "targets", features)
}
