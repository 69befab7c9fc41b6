//! Choosing a footprint reader by extension, then by content.

use std::path::Path;

use serde_json::Value;

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
    let data = std::fs::read(path).map_err(|source| FootprintError::Io {
        path: path.to_path_buf(),
        source,
    })?;
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
        "obj" => parse_obj_footprints(&data, origin).map_err(parse_err),
        "geojson" => parse_geojson(&data, origin).map_err(parse_err),
        "json" => {
            let v = super::json::parse(&data).map_err(parse_err)?;
            if v.get("type").and_then(Value::as_str) == Some("CityJSON") {
                parse_cityjson_footprints(&data, origin).map_err(parse_err)
            } else {
                parse_geojson(&data, origin).map_err(parse_err)
            }
        }
        _ => Err(FootprintError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}
