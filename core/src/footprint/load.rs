//! Choosing a footprint reader by extension, then by content.

use std::path::Path;

use geo::{Coord, MapCoordsInPlace};
use serde_json::Value;

use crate::crs::{Crs, JsonCrs, SourceFrame, cityjson_crs, geojson_crs};
use crate::file;

use super::cityjson::parse_cityjson_footprints;
use super::error::FootprintError;
use super::geojson::parse_geojson;
use super::obj::parse_obj_footprints;
use super::types::Loaded;

/// Reads footprints from a GeoJSON (`.geojson`, `.json`), CityJSON (`.json`,
/// `.city.json`) or OBJ (`.obj`) file; `.json` files are told apart by their
/// top-level `type`. Coordinates have `origin` subtracted (the local frame of
/// the cloud or scene they go with).
pub fn load_footprints(path: &Path, origin: [f64; 3]) -> Result<Loaded, FootprintError> {
    parse_file(path, &read(path)?, origin)
}

/// Reads footprints that go with a cloud in `frame`: their coordinates are in
/// the CRS the file names (GeoJSON `crs`, CityJSON `referenceSystem`), else
/// in the cloud's own CRS and unit (a layer drawn over the survey), and come
/// out in metres in the cloud's local frame. A file naming another
/// horizontal CRS than the cloud's is refused.
pub fn load_footprints_in(path: &Path, frame: &SourceFrame) -> Result<Loaded, FootprintError> {
    let data = read(path)?;
    let stated = stated_crs(&data);
    if let (Some(file), Some(cloud)) = (stated.as_ref(), frame.crs.as_ref())
        && let (Some(a), Some(b)) = (file.horizontal_epsg(), cloud.horizontal_epsg())
        && a != b
    {
        return Err(FootprintError::CrsMismatch {
            path: path.to_path_buf(),
            file: file.label(),
            cloud: cloud.label(),
        });
    }
    let f = stated.as_ref().map_or(frame.to_metre(), Crs::to_metre);
    let origin = [0, 1, 2].map(|k| frame.origin[k] / f[k]);
    let mut loaded = parse_file(path, &data, origin)?;
    if f[..2] != [1.0, 1.0] {
        for fp in &mut loaded.footprints {
            fp.polygon.map_coords_in_place(|c| Coord {
                x: c.x * f[0],
                y: c.y * f[1],
            });
        }
    }
    Ok(loaded)
}

fn read(path: &Path) -> Result<Vec<u8>, FootprintError> {
    Ok(file::read(path)?)
}

/// The CRS a GeoJSON or CityJSON file names and the registry resolves
/// (a GeoJSON without `crs` is RFC 7946 WGS 84, which no survey is in:
/// taken as unstated).
fn stated_crs(data: &[u8]) -> Option<Crs> {
    let v: Value = serde_json::from_slice(data).ok()?;
    let named = if v.get("type").and_then(Value::as_str) == Some("CityJSON") {
        cityjson_crs(&v)
    } else {
        geojson_crs(&v)
    };
    match named {
        Ok(JsonCrs::Epsg(crs)) => Some(crs),
        _ => None,
    }
}

fn parse_file(path: &Path, data: &[u8], origin: [f64; 3]) -> Result<Loaded, FootprintError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let parse_err = |source| FootprintError::Parse {
        path: path.to_path_buf(),
        source,
    };
    match ext.as_str() {
        "obj" => parse_obj_footprints(data, origin).map_err(parse_err),
        "geojson" => parse_geojson(data, origin).map_err(parse_err),
        "json" => {
            let v = super::json::parse(data).map_err(parse_err)?;
            if v.get("type").and_then(Value::as_str) == Some("CityJSON") {
                parse_cityjson_footprints(data, origin).map_err(parse_err)
            } else {
                parse_geojson(data, origin).map_err(parse_err)
            }
        }
        _ => Err(FootprintError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::crs::{FOOT_M, LinearUnit};

    /// A 100 × 50 ft footprint at (1000, 2000) ft, with or without a `crs`.
    fn write(name: &str, crs: Option<&str>) -> std::path::PathBuf {
        let member = crs.map_or(String::new(), |c| {
            format!(r#""crs": {{"type": "name", "properties": {{"name": "{c}"}}}},"#)
        });
        let doc = format!(
            r#"{{"type": "FeatureCollection", {member} "features": [{{"type": "Feature",
            "properties": {{}}, "geometry": {{"type": "Polygon", "coordinates":
            [[[1000, 2000], [1100, 2000], [1100, 2050], [1000, 2050], [1000, 2000]]]}}}}]}}"#
        );
        let path = std::env::temp_dir().join(format!("skyground-{}-{name}", std::process::id()));
        std::fs::write(&path, doc).expect("temp file");
        path
    }

    fn feet_frame() -> SourceFrame {
        // A cloud in feet: its local origin (990, 1990) ft, in metres.
        SourceFrame::new(
            [990.0 * FOOT_M, 1990.0 * FOOT_M, 0.0],
            Some(Crs::from_epsg(2994).expect("registry")),
        )
    }

    #[test]
    fn footprints_in_feet_come_out_in_metres_in_the_cloud_frame() {
        let frame = feet_frame();
        assert_eq!(frame.unit(), LinearUnit::Foot);
        for (name, crs) in [
            ("plain.geojson", None),
            ("named.geojson", Some("urn:ogc:def:crs:EPSG::2994")),
        ] {
            let path = write(name, crs);
            let loaded = load_footprints_in(&path, &frame).expect("loads");
            let b = loaded.footprints[0].bounds().expect("bounds");
            let want = [10.0, 10.0, 110.0, 60.0].map(|v| v * FOOT_M);
            for k in 0..4 {
                assert!((b[k] - want[k]).abs() < 1e-6, "{name}: {b:?} vs {want:?}");
            }
            assert!((loaded.footprints[0].area() - 5000.0 * FOOT_M * FOOT_M).abs() < 1e-3);
            let _ = std::fs::remove_file(path);
        }
    }

    #[test]
    fn footprints_in_another_crs_are_refused() {
        let path = write("rd.geojson", Some("urn:ogc:def:crs:EPSG::28992"));
        let e = load_footprints_in(&path, &feet_frame()).expect_err("another CRS");
        let _ = std::fs::remove_file(&path);
        assert!(matches!(e, FootprintError::CrsMismatch { .. }), "{e}");
        assert!(e.to_string().contains("EPSG:28992"), "{e}");
    }
}
