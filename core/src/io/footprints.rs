//! Choosing a footprint reader by extension, then by content; the CRS the
//! file names; moving the footprints into a cloud's frame.

use std::path::{Path, PathBuf};

use geo::{BoundingRect, Coord, MapCoordsInPlace};
use serde_json::Value;

use super::cityjson::{city_files, read_city_model};
use crate::crs::{Crs, JsonCrs, SourceFrame, epsg_from_reference, geojson_crs};
use crate::file;

use super::FootprintError;
use super::cityjson::footprints::cityjson_footprints;
use super::geojson::footprints::parse_geojson_with;
use super::obj::footprints::parse_obj_footprints;
use crate::footprint::{Loaded, ReadOptions};

/// The `--footprints` keyword for a CityJSON scene's own buildings.
pub const MODEL_KEYWORD: &str = "model";

/// Footprints as a file holds them: source CRS and unit, no origin taken off.
#[derive(Debug, Clone)]
pub struct SourceFootprints {
    /// The file (the first one, for CityJSON tiles).
    pub path: PathBuf,
    /// The CRS the file names, when the registry resolves it.
    pub crs: Option<Crs>,
    /// GeoJSON without a `crs` member (RFC 7946 says WGS 84 longitude/latitude).
    pub rfc7946: bool,
    /// What the reader found.
    pub loaded: Loaded,
}

/// Reads footprints from `spec`: a GeoJSON (`.geojson`, `.json`), CityJSON
/// (`.json`, `.city.json`) or CityJSONSeq (`.jsonl`), FlatGeobuf (`.fgb`)
/// or OBJ (`.obj`) file, or several CityJSON files (tiles) joined by
/// commas; `.json` files are told apart by their top-level `type`.
/// Coordinates stay in the file's CRS and unit.
pub fn read_footprints(
    spec: &str,
    options: &ReadOptions,
) -> Result<SourceFootprints, FootprintError> {
    let paths: Vec<PathBuf> = spec
        .split(',')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(PathBuf::from)
        .collect();
    let Some(first) = paths.first().cloned() else {
        return Err(FootprintError::UnknownFormat {
            path: PathBuf::from(spec),
        });
    };
    let parse_err = |path: &Path| {
        let path = path.to_path_buf();
        move |source| FootprintError::Parse { path, source }
    };
    let data = if paths.len() == 1 && !is_city(&first)? {
        file::read(&first)?
    } else {
        return read_city(&paths, options);
    };
    let ext = extension(&first);
    let (loaded, crs, rfc7946) = match ext.as_str() {
        "obj" => (
            parse_obj_footprints(&data, [0.0; 3]).map_err(parse_err(&first))?,
            None,
            false,
        ),
        "fgb" => {
            let (loaded, crs) =
                super::flatgeobuf::parse_fgb(&data, options).map_err(parse_err(&first))?;
            (loaded, crs, false)
        }
        "geojson" | "json" => {
            let loaded = parse_geojson_with(&data, [0.0; 3], options).map_err(parse_err(&first))?;
            let v: Value = serde_json::from_slice(&data).unwrap_or_default();
            match geojson_crs(&v) {
                Ok(JsonCrs::Epsg(crs)) => (loaded, Some(crs), false),
                Ok(JsonCrs::Wgs84Default) => (loaded, None, true),
                _ => (loaded, None, false),
            }
        }
        "gpkg" => return Err(FootprintError::GeoPackage { path: first }),
        _ => return Err(FootprintError::UnknownFormat { path: first }),
    };
    Ok(SourceFootprints {
        path: first,
        crs,
        rfc7946,
        loaded,
    })
}

fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default()
}

/// Whether `path` is a city model: `.jsonl`, or `.json` whose top-level
/// `type` is `CityJSON` (writers put it anywhere: cjio's delft.json has it
/// 1 MB in, after the vertices).
fn is_city(path: &Path) -> Result<bool, FootprintError> {
    #[derive(serde::Deserialize)]
    struct Kind {
        #[serde(rename = "type")]
        kind: Option<String>,
    }
    match extension(path).as_str() {
        "jsonl" => Ok(true),
        "json" => {
            let data = file::read(path)?;
            let kind: Option<Kind> = serde_json::from_slice(&data).ok();
            Ok(kind.and_then(|k| k.kind).as_deref() == Some("CityJSON"))
        }
        _ => Ok(false),
    }
}

fn read_city(paths: &[PathBuf], options: &ReadOptions) -> Result<SourceFootprints, FootprintError> {
    let first = paths[0].clone();
    let model = read_city_model(paths).map_err(|source| FootprintError::City {
        source: Box::new(source),
    })?;
    let loaded =
        cityjson_footprints(&model, [0.0; 3], options).map_err(|source| FootprintError::Parse {
            path: first.clone(),
            source,
        })?;
    Ok(SourceFootprints {
        path: first,
        crs: model.crs(),
        rfc7946: false,
        loaded,
    })
}

/// `--footprints` as a spec [`read_footprints`] takes: the keyword
/// [`MODEL_KEYWORD`] is the CityJSON scene's own files (`scene`, a scene
/// spec), anything else a path.
pub fn resolve_source(spec: &str, scene: Option<&str>) -> Result<String, FootprintError> {
    if spec.trim() != MODEL_KEYWORD {
        return Ok(spec.to_string());
    }
    let not_city = || FootprintError::ModelWithoutCity {
        scene: scene.map(str::to_string),
    };
    let scene = scene.ok_or_else(not_city)?;
    let files = city_files(scene).map_err(|_| not_city())?;
    let all_city = !files.is_empty()
        && files
            .iter()
            .all(|f| is_city(f).unwrap_or(false) && f.is_file());
    if !all_city {
        return Err(not_city());
    }
    Ok(files
        .iter()
        .map(|f| f.display().to_string())
        .collect::<Vec<_>>()
        .join(","))
}

impl SourceFootprints {
    /// The footprints in a cloud's `frame` (local, metres): their
    /// coordinates are in the CRS the file names, else in the cloud's own
    /// CRS and unit (a layer drawn over the survey). A file naming another
    /// horizontal CRS than the cloud's is refused, and so is an RFC 7946
    /// GeoJSON in longitude/latitude over a projected cloud.
    pub fn in_frame(&self, frame: &SourceFrame) -> Result<Loaded, FootprintError> {
        if let (Some(file), Some(cloud)) = (self.crs.as_ref(), frame.crs.as_ref())
            && let (Some(a), Some(b)) = (file.horizontal_epsg(), cloud.horizontal_epsg())
            && a != b
        {
            return Err(FootprintError::CrsMismatch {
                path: self.path.clone(),
                file: file.label(),
                cloud: cloud.label(),
            });
        }
        if self.rfc7946 && self.looks_geographic() && !frame_is_geographic(frame) {
            return Err(FootprintError::LongitudeLatitude {
                path: self.path.clone(),
                cloud: frame
                    .crs
                    .as_ref()
                    .map_or_else(|| "a projected frame".to_string(), Crs::label),
            });
        }
        let f = self.crs.as_ref().map_or(frame.to_metre(), Crs::to_metre);
        let origin = frame.origin;
        let mut loaded = self.loaded.clone();
        for fp in &mut loaded.footprints {
            fp.polygon.map_coords_in_place(|c| Coord {
                x: c.x * f[0] - origin[0],
                y: c.y * f[1] - origin[1],
            });
        }
        Ok(loaded)
    }

    /// Every coordinate within longitude/latitude's range.
    fn looks_geographic(&self) -> bool {
        self.loaded.footprints.iter().all(|f| {
            f.polygon.bounding_rect().is_none_or(|r| {
                r.min().x >= -180.0 && r.max().x <= 180.0 && r.min().y >= -90.0 && r.max().y <= 90.0
            })
        })
    }
}

/// A frame whose origin could be longitude/latitude (or that says so).
fn frame_is_geographic(frame: &SourceFrame) -> bool {
    let o = frame.to_source([0.0; 3]);
    o[0].abs() <= 180.0 && o[1].abs() <= 90.0
}

/// Reads footprints from `path` ([`read_footprints`]) with `origin`
/// subtracted, in the file's own unit.
pub fn load_footprints(path: &Path, origin: [f64; 3]) -> Result<Loaded, FootprintError> {
    let mut loaded = read_footprints(&path.display().to_string(), &ReadOptions::default())?.loaded;
    for fp in &mut loaded.footprints {
        fp.polygon.map_coords_in_place(|c| Coord {
            x: c.x - origin[0],
            y: c.y - origin[1],
        });
    }
    Ok(loaded)
}

/// Reads footprints that go with a cloud in `frame`
/// ([`SourceFootprints::in_frame`]).
pub fn load_footprints_in(path: &Path, frame: &SourceFrame) -> Result<Loaded, FootprintError> {
    read_footprints(&path.display().to_string(), &ReadOptions::default())?.in_frame(frame)
}

/// Footprints as a node's params give them (completeness_detector's
/// `footprints`, `footprint_id`, `crs`, `origin`, as the demo passes them):
/// `spec` read ([`read_footprints`]; each one's id from the field
/// `id_field`, blank: the usual ones) and moved into the frame whose origin
/// is `origin` (coordinates not given are 0) in the CRS `crs` (`EPSG:N`;
/// blank: none known). The error says why, without the file's name.
pub fn load_given(spec: &str, id_field: &str, crs: &str, origin: &[f64]) -> Result<Loaded, String> {
    let crs = match crs.trim() {
        "" => None,
        c => Some(
            epsg_from_reference(c)
                .ok_or_else(|| format!("crs `{c}` names no EPSG code (EPSG:N expected)"))
                .and_then(|code| Crs::from_epsg(code).map_err(|e| e.to_string()))?,
        ),
    };
    let origin = [0, 1, 2].map(|k| origin.get(k).copied().unwrap_or(0.0));
    let options = ReadOptions {
        id_field: Some(id_field.trim().to_string()).filter(|f| !f.is_empty()),
        ..ReadOptions::default()
    };
    read_footprints(spec, &options)
        .and_then(|s| s.in_frame(&SourceFrame::new(origin, crs)))
        .map_err(|e| e.to_string())
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
        let text = e.to_string();
        assert!(
            text.contains("EPSG:28992") && text.contains("EPSG:2994"),
            "{e}"
        );
    }

    #[test]
    fn longitude_latitude_over_a_projected_cloud_is_refused() {
        let doc = br#"{"type":"Feature","properties":{"@id":"way/1"},"geometry":{"type":"Polygon",
            "coordinates":[[[4.35,52.0],[4.351,52.0],[4.351,52.001],[4.35,52.0]]]}}"#;
        let path =
            std::env::temp_dir().join(format!("skyground-{}-osm.geojson", std::process::id()));
        std::fs::write(&path, doc).expect("temp file");
        let read = read_footprints(&path.display().to_string(), &ReadOptions::default());
        let _ = std::fs::remove_file(&path);
        let read = read.expect("reads");
        assert_eq!(read.loaded.footprints[0].name, "way/1");
        let rd = SourceFrame::new([84_000.0, 447_000.0, 0.0], Crs::from_epsg(28992).ok());
        let e = read.in_frame(&rd).expect_err("degrees over metres");
        assert!(matches!(e, FootprintError::LongitudeLatitude { .. }), "{e}");
        assert!(e.to_string().contains("EPSG:28992"), "{e}");
    }

    #[test]
    fn given_footprints_take_the_params_crs_and_origin() {
        let path = write("given.geojson", None);
        let spec = path.display().to_string();
        let origin = [990.0 * FOOT_M, 1990.0 * FOOT_M];
        let got = load_given(&spec, " ", "EPSG:2994", &origin);
        let refused = load_given(&spec, "", "feet", &origin);
        let _ = std::fs::remove_file(&path);
        let r = got.expect("reads").footprints[0].polygon.bounding_rect();
        let min = r.expect("a polygon").min();
        assert!((min.x - 10.0 * FOOT_M).abs() < 1e-6 && (min.y - 10.0 * FOOT_M).abs() < 1e-6);
        let e = refused.expect_err("no EPSG code");
        assert_eq!(e, "crs `feet` names no EPSG code (EPSG:N expected)");
    }

    #[test]
    fn the_model_keyword_needs_a_city_scene() {
        assert_eq!(
            resolve_source("a.geojson", None).ok().as_deref(),
            Some("a.geojson")
        );
        for scene in [None, Some("reference"), Some("/nonexistent/city.json")] {
            let e = resolve_source("model", scene).expect_err("no city model");
            assert!(matches!(e, FootprintError::ModelWithoutCity { .. }), "{e}");
        }
    }
}
