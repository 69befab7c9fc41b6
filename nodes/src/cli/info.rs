//! `skyground info FILE`: what a file holds before anything is run on it —
//! points or objects, extent, CRS and unit, density, classes, returns.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::{Value, json};
use skyground_core::cloud::info::{DENSITY_CELL_M, cloud_info};
use skyground_core::crs::{Crs, JsonCrs, cityjson_crs, geojson_crs};
use skyground_core::io::load_footprints;
use skyground_core::io::{
    CityJsonError, CityJsonOptions, SceneError, load_scene, read_city_files_and_crs,
};
use skyground_core::scene::Scene;

use super::err;
use crate::runtime::RuntimeError;

/// Options of `skyground info`.
#[derive(Debug, Clone, clap::Args)]
pub struct InfoArgs {
    /// A cloud (LAS, LAZ, PLY), a scene (CityJSON, CityJSONSeq, OBJ) or footprints (GeoJSON).
    pub file: PathBuf,
    #[command(flatten)]
    pub units: super::units::UnitsArg,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

const UNKNOWN: &str = "unknown CRS, metres assumed";

/// The CRS as JSON: label, EPSG, units and where they came from.
pub fn crs_json(crs: Option<&Crs>) -> Value {
    match crs {
        None => {
            json!({"label": UNKNOWN, "epsg": null, "unit": "metre", "vertical_unit": "metre", "unit_source": "assumed", "to_metre": [1.0, 1.0, 1.0]})
        }
        Some(c) => json!({
            "label": c.label(),
            "epsg": c.epsg,
            "vertical_epsg": c.vertical_epsg,
            "name": c.name,
            "unit": c.horizontal_unit.name(),
            "vertical_unit": c.vertical_unit.name(),
            "unit_source": c.unit_source,
            "to_metre": c.to_metre(),
            "has_wkt": c.wkt.is_some(),
            "las_records": c.las_records.iter().map(|r| r.record_id).collect::<Vec<_>>(),
        }),
    }
}

fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default()
}

/// Summarises the file; prints it (unless `--json`) and returns it.
pub fn run(a: &InfoArgs) -> Result<Value, RuntimeError> {
    let out = match extension(&a.file).as_str() {
        "las" | "laz" | "ply" => cloud(a)?,
        "json" | "geojson" => json_file(&a.file)?,
        "jsonl" => city_model(&a.file, &first_line(&a.file)?)?,
        "obj" => scene(&a.file, None)?,
        other => {
            return Err(err(format!(
                "{}: unknown extension `{other}` (LAS, LAZ, PLY, CityJSON, CityJSONSeq, GeoJSON, OBJ)",
                a.file.display()
            )));
        }
    };
    if !a.json {
        print!("{}", text(&out));
    }
    Ok(out)
}

fn cloud(a: &InfoArgs) -> Result<Value, RuntimeError> {
    let c = a.units.read(&a.file)?;
    let Some(info) = cloud_info(&c) else {
        return Ok(json!({
            "file": a.file,
            "kind": "cloud",
            "points": 0,
            "crs": crs_json(c.crs.as_ref()),
            "extent": null,
        }));
    };
    // The reader keeps every point's echo columns (PLY has none).
    let returns = c
        .return_number
        .as_ref()
        .zip(c.number_of_returns.as_ref())
        .map(|(rn, nr)| {
            let mut counts = BTreeMap::new();
            for (r, n) in rn.iter().zip(nr) {
                *counts.entry(format!("{r}/{n}")).or_insert(0usize) += 1;
            }
            counts
        });
    let multiple = returns.as_ref().map(|r| {
        let several: usize = r
            .iter()
            .filter(|(k, _)| !k.ends_with("/1") && !k.ends_with("/0"))
            .map(|(_, c)| c)
            .sum();
        several as f64 / info.points.max(1) as f64
    });
    Ok(json!({
        "file": a.file,
        "kind": "cloud",
        "points": info.points,
        "crs": crs_json(c.crs.as_ref()),
        "extent": {"min": info.min, "max": info.max, "size": info.size, "size_m": info.size_m},
        "density_per_m2": info.density_per_m2,
        "density_cell_m": DENSITY_CELL_M,
        "occupied_m2": info.occupied_m2,
        "classes": info.classes,
        "returns": returns,
        "share_multiple_returns": multiple,
        // What the classifier will do with them (`Cloud::echoes`).
        "echoes_usable": c.echoes().is_some(),
    }))
}

fn json_file(path: &Path) -> Result<Value, RuntimeError> {
    let data = std::fs::read(path).map_err(|e| err(format!("{}: {e}", path.display())))?;
    let doc: Value =
        serde_json::from_slice(&data).map_err(|e| err(format!("{}: {e}", path.display())))?;
    if doc.get("type").and_then(Value::as_str) == Some("CityJSON") {
        return city_model(path, &doc);
    }
    let crs = geojson_crs(&doc).map_err(err)?;
    let loaded = load_footprints(path, [0.0; 3]).map_err(err)?;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for b in loaded.footprints.iter().filter_map(|f| f.bounds()) {
        lo = [lo[0].min(b[0]), lo[1].min(b[1])];
        hi = [hi[0].max(b[2]), hi[1].max(b[3])];
    }
    let f = json_crs_factor(&crs);
    let extent = lo[0].is_finite().then(|| {
        let size = [hi[0] - lo[0], hi[1] - lo[1]];
        json!({"min": lo, "max": hi, "size": size, "size_m": size.map(|s| s * f)})
    });
    Ok(json!({
        "file": path,
        "kind": "footprints",
        "objects": loaded.footprints.len(),
        "skipped": loaded.skipped.len(),
        "crs": json_crs_json(&crs),
        "extent": extent,
    }))
}

fn json_crs_factor(crs: &JsonCrs) -> f64 {
    match crs {
        JsonCrs::Epsg(c) => c.to_metre()[0],
        _ => 1.0,
    }
}

fn json_crs_json(crs: &JsonCrs) -> Value {
    match crs {
        JsonCrs::Epsg(c) => crs_json(Some(c)),
        JsonCrs::Unresolved(r) => {
            json!({"label": format!("{r} (not resolved; metres assumed)"), "epsg": null, "unit": "metre", "unit_source": "assumed"})
        }
        JsonCrs::Wgs84Default => {
            json!({"label": "WGS 84 longitude/latitude (RFC 7946 default: no crs member)", "epsg": 4326, "unit": "degree", "unit_source": "assumed"})
        }
        JsonCrs::Unstated => crs_json(None),
    }
}

/// The first line of a CityJSONSeq file (its `CityJSON` header).
fn first_line(path: &Path) -> Result<Value, RuntimeError> {
    let data = std::fs::read(path).map_err(|e| err(format!("{}: {e}", path.display())))?;
    let line = data.split(|&b| b == b'\n').next().unwrap_or_default();
    serde_json::from_slice(line).map_err(|e| err(format!("{}: line 1: {e}", path.display())))
}

/// A CityJSON or CityJSONSeq model (`header` its document or first line)
/// as it is, without the ground the scene reader adds around buildings;
/// one without buildings skyground can use is described all the same.
fn city_model(path: &Path, header: &Value) -> Result<Value, RuntimeError> {
    let crs = cityjson_crs(header).map_err(err)?;
    let options = CityJsonOptions { terrain: None };
    match read_city_files_and_crs(&[path.to_path_buf()], &options) {
        Ok((s, _)) => Ok(scene_json(path, &s, crs)),
        Err(SceneError::CityJson {
            source: e @ CityJsonError::NoBuildings { .. },
            ..
        }) => Ok(json!({
            "file": path,
            "kind": "scene",
            "objects": header["CityObjects"].as_object().map_or(0, serde_json::Map::len),
            "buildings": 0,
            "note": e.to_string(),
            "crs": json_crs_json(&crs),
            "extent": null,
        })),
        Err(e) => Err(err(e)),
    }
}

fn scene(path: &Path, crs: Option<JsonCrs>) -> Result<Value, RuntimeError> {
    let spec = path.to_str().ok_or_else(|| err("path is not UTF-8"))?;
    let s = load_scene(spec).map_err(err)?;
    Ok(scene_json(path, &s, crs.unwrap_or(JsonCrs::Unstated)))
}

/// A loaded scene's summary; `crs` says what unit its extent is told in.
fn scene_json(path: &Path, s: &Scene, crs: JsonCrs) -> Value {
    let f = [0, 1, 2].map(|k| {
        if k < 2 {
            json_crs_factor(&crs)
        } else {
            match &crs {
                JsonCrs::Epsg(c) => c.to_metre()[2],
                _ => 1.0,
            }
        }
    });
    // The scene is loaded in metres; the extent is told in the model's unit.
    let extent = s.bounds().map(|(lo, hi)| {
        let min_m = [0, 1, 2].map(|k| s.origin[k] + f64::from(lo[k]));
        let max_m = [0, 1, 2].map(|k| s.origin[k] + f64::from(hi[k]));
        let size_m = [0, 1, 2].map(|k| max_m[k] - min_m[k]);
        let [min, max, size] = [min_m, max_m, size_m].map(|v| [0, 1, 2].map(|k| v[k] / f[k]));
        json!({"min": min, "max": max, "size": size, "size_m": size_m})
    });
    json!({
        "file": path,
        "kind": "scene",
        "objects": s.objects.len(),
        "buildings": s.building_count(),
        "triangles": s.triangles.len(),
        "crs": json_crs_json(&crs),
        "extent": extent,
    })
}

/// The summary as lines for a person.
fn text(v: &Value) -> String {
    let mut s = String::new();
    let line = |s: &mut String, k: &str, val: String| s.push_str(&format!("{k:<10} {val}\n"));
    line(
        &mut s,
        "file",
        v["file"].as_str().unwrap_or_default().to_string(),
    );
    let kind = v["kind"].as_str().unwrap_or_default();
    if kind == "cloud" {
        line(&mut s, "points", v["points"].to_string());
    } else {
        line(&mut s, "objects", v["objects"].to_string());
    }
    let crs = &v["crs"];
    line(
        &mut s,
        "crs",
        crs["label"].as_str().unwrap_or_default().to_string(),
    );
    line(
        &mut s,
        "unit",
        format!(
            "{} (vertical {}; from {})",
            crs["unit"].as_str().unwrap_or("?"),
            crs["vertical_unit"].as_str().unwrap_or("same"),
            crs["unit_source"].as_str().unwrap_or("?")
        ),
    );
    if let Some(note) = v["note"].as_str() {
        line(&mut s, "note", note.to_string());
    }
    let e = &v["extent"];
    if !e.is_null() {
        let f = |x: &Value| {
            x.as_array()
                .map(|a| {
                    a.iter()
                        .map(|n| format!("{:.2}", n.as_f64().unwrap_or(f64::NAN)))
                        .collect::<Vec<_>>()
                        .join(" × ")
                })
                .unwrap_or_default()
        };
        let sym = crs["unit"].as_str().unwrap_or("m");
        line(
            &mut s,
            "extent",
            format!("{} ({sym}) = {} m", f(&e["size"]), f(&e["size_m"])),
        );
        line(&mut s, "min", f(&e["min"]));
        line(&mut s, "max", f(&e["max"]));
    }
    if kind == "cloud" {
        line(
            &mut s,
            "density",
            format!(
                "{:.1} points/m² over {:.0} m² of occupied {} m cells",
                v["density_per_m2"].as_f64().unwrap_or(0.0),
                v["occupied_m2"].as_f64().unwrap_or(0.0),
                v["density_cell_m"]
            ),
        );
        if let Some(c) = v["classes"].as_object() {
            let mut classes: Vec<(u32, &Value)> = c
                .iter()
                .filter_map(|(k, n)| Some((k.parse().ok()?, n)))
                .collect();
            classes.sort_by_key(|(k, _)| *k);
            let parts: Vec<String> = classes.iter().map(|(k, n)| format!("{k}:{n}")).collect();
            line(&mut s, "classes", parts.join(" "));
        }
        if let Some(r) = v["returns"].as_object() {
            let parts: Vec<String> = r.iter().map(|(k, n)| format!("{k}:{n}")).collect();
            line(&mut s, "returns", parts.join(" "));
            line(
                &mut s,
                "multiple",
                format!(
                    "{:.1} % of points from pulses with several returns{}",
                    100.0 * v["share_multiple_returns"].as_f64().unwrap_or(0.0),
                    if v["echoes_usable"].as_bool() == Some(false) {
                        " (no echo cue: classified without echoes)"
                    } else {
                        ""
                    }
                ),
            );
        }
    }
    s
}
