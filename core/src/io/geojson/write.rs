//! GeoJSON pieces in the source CRS: positions, rings, the collection.

use geo::MultiPolygon;
use serde_json::{Value, json};

use crate::crs::SourceFrame;

/// Rounds a source coordinate to 0.1 mm of its unit (keeps files readable).
fn round(v: f64) -> f64 {
    (v * 1e4).round() / 1e4
}

/// A local point (metres) as a GeoJSON position in the source CRS and unit.
pub fn position(frame: &SourceFrame, p: [f64; 3]) -> Value {
    let q = frame.to_source(p);
    json!([round(q[0]), round(q[1]), round(q[2])])
}

/// A local xy ring as a closed GeoJSON linear ring in the source CRS.
pub fn ring(frame: &SourceFrame, pts: &[[f64; 2]]) -> Value {
    let mut out: Vec<Value> = pts
        .iter()
        .map(|p| {
            let q = frame.to_source_xy(*p);
            json!([round(q[0]), round(q[1])])
        })
        .collect();
    if let (Some(first), Some(last)) = (out.first().cloned(), out.last())
        && &first != last
    {
        out.push(first);
    }
    Value::Array(out)
}

/// A local multipolygon as a GeoJSON MultiPolygon geometry in the source CRS.
pub fn multipolygon(frame: &SourceFrame, mp: &MultiPolygon<f64>) -> Value {
    let coords: Vec<Value> =
        mp.0.iter()
            .map(|p| {
                let rings: Vec<Value> = std::iter::once(p.exterior())
                    .chain(p.interiors())
                    .map(|r| {
                        let pts: Vec<[f64; 2]> = r.0.iter().map(|c| [c.x, c.y]).collect();
                        ring(frame, &pts)
                    })
                    .collect();
                Value::Array(rings)
            })
            .collect();
    json!({"type": "MultiPolygon", "coordinates": coords})
}

/// A FeatureCollection naming the source CRS and unit.
///
/// `crs` is GeoJSON 2008's member (RFC 7946 dropped it and assumes WGS 84;
/// projected survey data is kept projected, as GDAL writes it). The foreign
/// member `units` says what a coordinate step measures.
pub fn feature_collection(frame: &SourceFrame, name: &str, features: Vec<Value>) -> Value {
    let unit = frame.unit();
    let mut fc = json!({
        "type": "FeatureCollection",
        "name": name,
        "units": {"horizontal": unit.name(), "vertical": frame.crs.as_ref().map_or("metre", |c| c.vertical_unit.name()), "to_metre": frame.to_metre()},
        "features": features,
    });
    match frame.geojson_crs_member() {
        Some(crs) => fc["crs"] = crs,
        None => {
            fc["crs_note"] = json!("unknown CRS: coordinates as in the input file, metres assumed")
        }
    }
    fc
}

/// One GeoJSON Feature.
pub fn feature(geometry: Value, properties: Value) -> Value {
    json!({"type": "Feature", "geometry": geometry, "properties": properties})
}
