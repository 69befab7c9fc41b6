//! The CRS named by a CityJSON or GeoJSON document.

use serde_json::Value;

use super::{Crs, CrsError, epsg_from_reference};

/// What a JSON document says about its CRS.
#[derive(Debug, Clone, PartialEq)]
pub enum JsonCrs {
    /// It names an EPSG code (resolved through the registry).
    Epsg(Crs),
    /// It names a CRS we cannot resolve (the reference as written).
    Unresolved(String),
    /// GeoJSON without a `crs` member: RFC 7946's WGS 84 longitude/latitude.
    Wgs84Default,
    /// It says nothing (CityJSON without `metadata.referenceSystem`).
    Unstated,
}

fn resolve(reference: &str) -> Result<JsonCrs, CrsError> {
    match epsg_from_reference(reference) {
        Some(code) => Ok(JsonCrs::Epsg(Crs::from_epsg(code)?)),
        None => Ok(JsonCrs::Unresolved(reference.to_string())),
    }
}

/// CityJSON's `metadata.referenceSystem` (1.0 `urn:ogc:def:crs:EPSG::n`,
/// 1.1/2.0 `https://www.opengis.net/def/crs/EPSG/0/n`).
pub fn cityjson_crs(doc: &Value) -> Result<JsonCrs, CrsError> {
    match doc
        .pointer("/metadata/referenceSystem")
        .and_then(Value::as_str)
    {
        Some(r) => resolve(r),
        None => Ok(JsonCrs::Unstated),
    }
}

/// GeoJSON's legacy `crs` member (`{"type":"name","properties":{"name":...}}`,
/// what GDAL writes for projected data); without it RFC 7946's WGS 84.
pub fn geojson_crs(doc: &Value) -> Result<JsonCrs, CrsError> {
    match doc.pointer("/crs/properties/name").and_then(Value::as_str) {
        Some(r) => resolve(r),
        None => Ok(JsonCrs::Wgs84Default),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::crs::LinearUnit;

    #[test]
    fn cityjson_reference_systems_resolve_with_units() {
        let doc = serde_json::json!({"metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/7415"}});
        let JsonCrs::Epsg(crs) = cityjson_crs(&doc).unwrap() else {
            panic!("not resolved")
        };
        assert_eq!(crs.epsg, Some(7415));
        assert_eq!(crs.vertical_unit, LinearUnit::Metre);
        let none = serde_json::json!({"type": "CityJSON"});
        assert_eq!(cityjson_crs(&none), Ok(JsonCrs::Unstated));
        let odd = serde_json::json!({"metadata": {"referenceSystem": "my local grid"}});
        assert_eq!(
            cityjson_crs(&odd),
            Ok(JsonCrs::Unresolved("my local grid".into()))
        );
    }

    #[test]
    fn geojson_legacy_crs_member_and_rfc7946_default() {
        let doc = serde_json::json!({"crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::2994"}}});
        let JsonCrs::Epsg(crs) = geojson_crs(&doc).unwrap() else {
            panic!("not resolved")
        };
        assert_eq!(crs.horizontal_unit, LinearUnit::Foot);
        let plain = serde_json::json!({"type": "FeatureCollection", "features": []});
        assert_eq!(geojson_crs(&plain), Ok(JsonCrs::Wgs84Default));
        let wgs = serde_json::json!({"crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:OGC:1.3:CRS84"}}});
        assert!(matches!(
            geojson_crs(&wgs),
            Err(CrsError::Geographic { .. })
        ));
    }
}
