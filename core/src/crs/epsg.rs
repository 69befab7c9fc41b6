//! EPSG codes: reading them from CRS references, and what the EPSG registry
//! (through the `crs-definitions` table) says about a code.

use super::LinearUnit;
use super::wkt::{WktArg, WktFacts, WktNode, parse_wkt, wkt_facts};

/// What the registry says about one EPSG code.
#[derive(Debug, Clone, PartialEq)]
pub struct EpsgEntry {
    /// The code.
    pub code: u32,
    /// The registry's WKT1 text.
    pub wkt: &'static str,
    /// Name, units and component codes read from that WKT.
    pub facts: WktFacts,
}

/// The registry entry of `code`, when the table has it.
pub fn epsg_entry(code: u32) -> Option<EpsgEntry> {
    let def = crs_definitions::from_code(u16::try_from(code).ok()?)?;
    let facts = wkt_facts(def.wkt).ok()?;
    Some(EpsgEntry {
        code,
        wkt: def.wkt,
        facts,
    })
}

/// The EPSG code a CRS reference names: `EPSG:2056`, `urn:ogc:def:crs:EPSG::2056`,
/// `urn:ogc:def:crs:EPSG:6.6:2056`, `https://www.opengis.net/def/crs/EPSG/0/7415`.
/// `OGC CRS84` (GeoJSON's RFC 7946 default) is EPSG:4326 with axes swapped: 4326.
pub fn epsg_from_reference(reference: &str) -> Option<u32> {
    let r = reference.trim();
    let upper = r.to_ascii_uppercase();
    if upper.ends_with("CRS84") {
        return Some(4326);
    }
    let at = upper.rfind("EPSG")?;
    let tail = &r[at + 4..];
    let code = tail.rsplit([':', '/']).next()?;
    code.trim().parse().ok().filter(|c| *c > 0)
}

/// The unit of a registry entry's horizontal axes (None when geographic or absent).
pub fn epsg_unit(code: u32) -> Option<LinearUnit> {
    epsg_entry(code)?.facts.horizontal_unit
}

/// Angle tolerance when matching projection parameters, degrees.
const ANGLE_TOL: f64 = 1e-7;
/// Length tolerance when matching false eastings/northings, metres.
const LENGTH_TOL: f64 = 1e-3;

/// proj4 keys of the WKT1 parameters we compare; lengths are scaled to metres.
fn proj4_key(parameter: &str) -> Option<(&'static str, bool)> {
    Some(match parameter.to_ascii_lowercase().as_str() {
        "standard_parallel_1" => ("lat_1", false),
        "standard_parallel_2" => ("lat_2", false),
        "latitude_of_origin" | "latitude_of_center" => ("lat_0", false),
        "central_meridian" | "longitude_of_center" => ("lon_0", false),
        "false_easting" => ("x_0", true),
        "false_northing" => ("y_0", true),
        "scale_factor" => ("k", false),
        _ => return None,
    })
}

fn proj4_method(projection: &str) -> Option<&'static str> {
    match projection.to_ascii_lowercase().as_str() {
        "lambert_conformal_conic" | "lambert_conformal_conic_2sp" => Some("lcc"),
        "transverse_mercator" => Some("tmerc"),
        _ => None,
    }
}

fn proj4_units(unit: &LinearUnit) -> Option<&'static str> {
    match unit {
        LinearUnit::Metre => Some("m"),
        LinearUnit::Foot => Some("ft"),
        LinearUnit::UsSurveyFoot => Some("us-ft"),
        LinearUnit::Other { .. } => None,
    }
}

/// `+key=value` pairs of a proj4 string.
fn proj4_pairs(proj4: &str) -> Vec<(&str, &str)> {
    proj4
        .split_whitespace()
        .filter_map(|t| t.strip_prefix('+')?.split_once('='))
        .collect()
}

/// Projection method and parameters (proj4 keys, lengths in metres) of a WKT1 PROJCS.
fn wkt_projection(
    top: &WktNode,
    unit: &LinearUnit,
) -> Option<(&'static str, Vec<(&'static str, f64)>)> {
    let method = top.child(&["PROJECTION"])?;
    let Some(WktArg::Text(name)) = method.args.first() else {
        return None;
    };
    let method = proj4_method(name)?;
    let params = top
        .children()
        .filter(|c| c.keyword == "PARAMETER")
        .filter_map(|p| {
            let (Some(WktArg::Text(n)), Some(WktArg::Number(v))) = (p.args.first(), p.args.get(1))
            else {
                return None;
            };
            let (key, length) = proj4_key(n)?;
            Some((key, if length { v * unit.to_metre() } else { *v }))
        })
        .collect();
    Some((method, params))
}

/// Whether a registry proj4 string has the same method, unit and parameters.
fn same_projection(proj4: &str, method: &str, units: &str, params: &[(&str, f64)]) -> bool {
    let pairs = proj4_pairs(proj4);
    let get = |k: &str| pairs.iter().find(|(key, _)| *key == k).map(|(_, v)| *v);
    if get("proj") != Some(method) || get("units") != Some(units) {
        return false;
    }
    let num = |k: &str| get(k).and_then(|v| v.parse::<f64>().ok());
    let value = |k: &str| match k {
        "k" => num("k").or_else(|| num("k_0")).unwrap_or(1.0),
        _ => num(k).unwrap_or(0.0),
    };
    let ours = |k: &str| params.iter().find(|(key, _)| *key == k).map(|(_, v)| *v);
    let near = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol;
    // Standard parallels are a set: their order does not change the projection.
    let (a1, a2) = (ours("lat_1"), ours("lat_2"));
    if let (Some(a1), Some(a2)) = (a1, a2) {
        let (b1, b2) = (value("lat_1"), value("lat_2"));
        let same = (near(a1, b1, ANGLE_TOL) && near(a2, b2, ANGLE_TOL))
            || (near(a1, b2, ANGLE_TOL) && near(a2, b1, ANGLE_TOL));
        if !same {
            return false;
        }
    }
    params.iter().all(|(k, v)| match *k {
        "lat_1" | "lat_2" => true,
        "x_0" | "y_0" => near(*v, value(k), LENGTH_TOL),
        _ => near(*v, value(k), ANGLE_TOL),
    })
}

/// The EPSG code of a projected CRS given only as WKT without an authority:
/// the registry's one CRS with the same projection, parameters and unit and,
/// when `geographic` is known (GeoTIFF `GeographicTypeGeoKey`), the same base,
/// and when the WKT's datum has an EPSG code, the same datum.
/// `None` when no or several codes match (we do not guess).
pub fn identify_projected(wkt: &str, unit: &LinearUnit, geographic: Option<u32>) -> Option<u32> {
    let top = parse_wkt(wkt).ok()?;
    let (method, params) = wkt_projection(&top, unit)?;
    let units = proj4_units(unit)?;
    let our_datum = top
        .child(&["GEOGCS"])
        .and_then(|g| g.child(&["DATUM"]))
        .and_then(WktNode::epsg);
    let mut found = None;
    for code in 1024..=u16::MAX {
        let Some(def) = crs_definitions::from_code(code) else {
            continue;
        };
        if !same_projection(def.proj4, method, units, &params) {
            continue;
        }
        let theirs = parse_wkt(def.wkt).ok();
        let their_base = theirs.as_ref().and_then(|t| t.child(&["GEOGCS"]));
        if geographic.is_some() && their_base.and_then(WktNode::epsg) != geographic {
            continue;
        }
        let their_datum = their_base
            .and_then(|g| g.child(&["DATUM"]))
            .and_then(WktNode::epsg);
        if our_datum.is_some() && their_datum != our_datum {
            continue;
        }
        if found.replace(u32::from(code)).is_some() {
            return None;
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_in_every_spelling() {
        assert_eq!(epsg_from_reference("EPSG:2154"), Some(2154));
        assert_eq!(
            epsg_from_reference("urn:ogc:def:crs:EPSG::2056"),
            Some(2056)
        );
        assert_eq!(
            epsg_from_reference("urn:ogc:def:crs:EPSG:6.6:28992"),
            Some(28992)
        );
        assert_eq!(
            epsg_from_reference("https://www.opengis.net/def/crs/EPSG/0/7415"),
            Some(7415)
        );
        assert_eq!(
            epsg_from_reference("urn:ogc:def:crs:OGC:1.3:CRS84"),
            Some(4326)
        );
        assert_eq!(epsg_from_reference("LOCAL_CS[\"x\"]"), None);
        assert_eq!(epsg_from_reference("EPSG:"), None);
    }

    #[test]
    fn registry_knows_units_of_projected_and_compound_codes() {
        assert_eq!(epsg_unit(2154), Some(LinearUnit::Metre));
        assert_eq!(epsg_unit(6880), Some(LinearUnit::UsSurveyFoot));
        assert_eq!(
            epsg_unit(2994),
            Some(LinearUnit::Foot),
            "NAD83(HARN) / Oregon GIC Lambert (ft)"
        );
        let rd = epsg_entry(7415).unwrap();
        assert_eq!(rd.facts.horizontal_unit, Some(LinearUnit::Metre));
        assert_eq!(rd.facts.vertical_unit, Some(LinearUnit::Metre));
        assert_eq!(rd.facts.horizontal_epsg, Some(28992));
        assert!(epsg_entry(4326).unwrap().facts.geographic);
        assert_eq!(epsg_entry(1), None);
    }

    #[test]
    fn nebraska_wkt_without_authority_is_identified_with_its_geotiff_base() {
        let wkt = r#"PROJCS["NAD83_2011_Nebraska_ft",GEOGCS["GCS_NAD_1983_2011",DATUM["D_NAD83_NATIONAL_SPATIAL_REFERENCE_SYSTEM_2011",SPHEROID["GRS_1980",6378137,298.257222101]],PRIMEM["Greenwich",0],UNIT["Degree",0.017453292519943295]],PROJECTION["Lambert_Conformal_Conic"],PARAMETER["scale_factor",1],PARAMETER["standard_parallel_1",40],PARAMETER["standard_parallel_2",43],PARAMETER["central_meridian",-100],PARAMETER["latitude_of_origin",39.83333333333334],PARAMETER["false_easting",1640416.666666667],PARAMETER["false_northing",0],UNIT["Foot_US",0.30480060960121924]]"#;
        assert_eq!(
            identify_projected(wkt, &LinearUnit::UsSurveyFoot, Some(6318)),
            Some(6880)
        );
        // Without the base several datums share these parameters: no guess.
        assert_eq!(
            identify_projected(wkt, &LinearUnit::UsSurveyFoot, None),
            None
        );
        assert_eq!(
            identify_projected(wkt, &LinearUnit::Metre, Some(6318)),
            None
        );
    }
}
