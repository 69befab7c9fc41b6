//! What a successful run must have produced, checked against the input
//! itself (its header's point count, its model's vertices), not against
//! recorded results.

use std::path::Path;

use serde_json::Value;
use skyground_core::cloud::read_cloud;

use super::plan::{Command, EARLIER, Layout, extension};

/// `Err(why)` when an output of a successful run is missing or wrong.
pub fn outputs(file: &Path, command: Command, layout: &Layout, stdout: &str) -> Result<(), String> {
    if let Some(seed) = &layout.seeded
        && std::fs::read(seed).is_ok_and(|b| b == EARLIER)
    {
        return Err(format!(
            "exit 0 but {} is the earlier run's",
            seed.display()
        ));
    }
    let o = &layout.outputs;
    match command {
        Command::Info => info(file, &json(stdout)?),
        Command::Classify => same_points(file, &layout.out),
        Command::Detect => {
            present(o, &["detection.json", "targets.json", "detection.png"])?;
            let classified = ["classified.laz", "classified.las"]
                .iter()
                .map(|n| o.join(n))
                .find(|p| p.is_file())
                .ok_or("no classified.laz/.las")?;
            same_points(file, &classified)?;
            read_cloud(&o.join("missing.las")).map_err(|e| e.to_string())?;
            array(&read_json(&o.join("detection.json"))?)
        }
        Command::Reconstruct => {
            present(o, &["models.obj", "reconstruct.json"])?;
            let model = read_json(&o.join("models.city.json"))?;
            match model["type"].as_str() {
                Some("CityJSON") => Ok(()),
                other => Err(format!("models.city.json has type {other:?}")),
            }
        }
        Command::Aerial => {
            present(o, &["aerial.ply", "gt_samples.ply"])?;
            read_json(&o.join("summary.json"))?;
            read_cloud(&o.join("aerial.las"))
                .map(drop)
                .map_err(|e| e.to_string())
        }
        Command::Demo => {
            present(o, &["report.md"])?;
            read_json(&o.join("report.json")).map(drop)
        }
    }
}

fn present(dir: &Path, names: &[&str]) -> Result<(), String> {
    match names.iter().find(|n| !dir.join(n).is_file()) {
        None => Ok(()),
        Some(n) => Err(format!("exit 0 but no {n}")),
    }
}

fn json(text: &str) -> Result<Value, String> {
    serde_json::from_str(text.trim()).map_err(|e| format!("stdout is not JSON: {e}"))
}

fn read_json(path: &Path) -> Result<Value, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

fn array(v: &Value) -> Result<(), String> {
    v.as_array()
        .map(drop)
        .ok_or_else(|| "detection.json is not a list".to_string())
}

/// The written cloud holds the input's points, as many and in order.
fn same_points(input: &Path, written: &Path) -> Result<(), String> {
    let a = read_cloud(input).map_err(|e| format!("input: {e}"))?;
    let b = read_cloud(written).map_err(|e| format!("output: {e}"))?;
    if a.len() != b.len() {
        return Err(format!("{} points in, {} out", a.len(), b.len()));
    }
    // Positions in metres, absolute; the writer's grid is at worst 1 mm
    // (or the input's own), the f32 local frame ~1e-7 of the extent.
    for (i, (p, q)) in a.xyz.iter().zip(&b.xyz).enumerate() {
        for k in 0..3 {
            let pa = a.origin[k] + f64::from(p[k]);
            let pb = b.origin[k] + f64::from(q[k]);
            let tol = 2e-3 + 1e-6 * pa.abs().max(f64::from(p[k].abs()));
            if (pa - pb).abs() > tol {
                return Err(format!("point {i} moved: {pa} → {pb} (axis {k})"));
            }
        }
    }
    Ok(())
}

/// `info --json` agrees with the file: a cloud's point count is its
/// header's, a city model's extent lies within its own vertices.
fn info(file: &Path, v: &Value) -> Result<(), String> {
    let kind = v["kind"].as_str().unwrap_or_default();
    if kind == "cloud" {
        let points = v["points"].as_u64().ok_or("no point count")?;
        if let Some(n) = las_header_count(file)
            && n != points
        {
            return Err(format!("{points} points, the header says {n}"));
        }
    }
    let Some(bounds) = city_vertex_bounds(file) else {
        return Ok(());
    };
    // A model without buildings skyground can use is described by its
    // objects and a note; it has no scene to give the extent of.
    if v["extent"].is_null() && v["buildings"] == 0 && v["note"].is_string() {
        return Ok(());
    }
    let (min, max) = (&v["extent"]["min"], &v["extent"]["max"]);
    for k in 0..3 {
        let (lo, hi) = (min[k].as_f64(), max[k].as_f64());
        let (Some(lo), Some(hi)) = (lo, hi) else {
            return Err(format!("no extent on axis {k}"));
        };
        let tol = 1e-3 * (1.0 + bounds.1[k].abs());
        if lo < bounds.0[k] - tol || hi > bounds.1[k] + tol {
            return Err(format!(
                "extent [{lo}, {hi}] on axis {k} beyond the model's vertices [{}, {}]",
                bounds.0[k], bounds.1[k]
            ));
        }
    }
    Ok(())
}

/// The point count a LAS/LAZ header states (the 1.4 64-bit one when set).
fn las_header_count(file: &Path) -> Option<u64> {
    if !matches!(extension(file).as_str(), "las" | "laz") {
        return None;
    }
    let head = std::fs::read(file).ok()?;
    let u32_at = |a: usize| Some(u32::from_le_bytes(head.get(a..a + 4)?.try_into().ok()?));
    let legacy = u64::from(u32_at(107)?);
    let large = (head.get(25) >= Some(&4))
        .then(|| Some(u64::from_le_bytes(head.get(247..255)?.try_into().ok()?)))
        .flatten();
    Some(match large {
        Some(n) if n > 0 => n,
        _ => legacy,
    })
}

/// The bounds of a CityJSON (or CityJSONSeq) file's vertices in its own
/// unit, `transform` applied.
fn city_vertex_bounds(file: &Path) -> Option<([f64; 3], [f64; 3])> {
    let text = std::fs::read_to_string(file).ok()?;
    let docs: Vec<Value> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(serde_json::from_str)
        .collect::<Result<_, _>>()
        .ok()
        .or_else(|| serde_json::from_str(&text).ok().map(|d| vec![d]))?;
    let first = docs.first()?;
    if !first["type"].as_str()?.starts_with("CityJSON") {
        return None;
    }
    let t = &first["transform"];
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for d in &docs {
        for v in d["vertices"].as_array().into_iter().flatten() {
            for k in 0..3 {
                let raw = v[k].as_f64()?;
                let x = raw * t["scale"][k].as_f64().unwrap_or(1.0)
                    + t["translate"][k].as_f64().unwrap_or(0.0);
                lo[k] = lo[k].min(x);
                hi[k] = hi[k].max(x);
            }
        }
    }
    lo[0].is_finite().then_some((lo, hi))
}
