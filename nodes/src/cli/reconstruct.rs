//! `skyground reconstruct`: LoD2 models of a cloud's buildings
//! (docs/design.md step 10), written as CityJSON 2.0 and OBJ; with `--gt`,
//! their accuracy against a scene's buildings.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use skyground_core::cloud::Cloud;
use skyground_core::cloud::extent::check_plan_extent;
use skyground_core::crs::SourceFrame;
use skyground_core::footprint::Footprint;
use skyground_core::io::SourceFootprints;
use skyground_core::io::cityjson::models as cityjson;
use skyground_core::io::obj::models as obj;
use skyground_core::metrics::{building_points, sample_building_surfaces};
use skyground_core::reconstruct::evaluate::points_to_models;
use skyground_core::reconstruct::{
    BeforeAfter, ModelEvaluation, ReconstructParams, Reconstruction, evaluate_models,
    reconstruct_cloud,
};
use skyground_core::scene::Scene;

use super::err;
use crate::runtime::RuntimeError;

/// Options of `skyground reconstruct`.
#[derive(Debug, Clone, clap::Args)]
pub struct ReconstructArgs {
    /// The cloud (LAS/LAZ/PLY); building points are class 6 (all points when
    /// unlabelled or only 0/1, unclassified). Tiles of one survey: repeat `--in` or join them by commas.
    #[arg(long = "in", required = true, value_delimiter = ',')]
    pub input: Vec<PathBuf>,
    #[command(flatten)]
    pub footprints: super::footprints::FootprintsArg,
    /// Output folder: models.city.json, models.obj, reconstruct.json.
    #[arg(long)]
    pub out: PathBuf,
    /// Ground truth to measure against: reference, reference:SEED, or a scene file.
    #[arg(long)]
    pub gt: Option<String>,
    /// A cloud from before (e.g. the aerial prior; needs --gt): also writes
    /// models_before.* / models_after.*, a before/after table (models.md) and models.png.
    #[arg(long, requires = "gt")]
    pub before: Option<PathBuf>,
    #[command(flatten)]
    pub units: super::units::UnitsArg,
    /// Spacing of the surface samples for the accuracy measures, m.
    #[arg(long, default_value_t = 0.25)]
    pub gt_spacing: f32,
    /// Reconstruction parameters: a JSON object, inline (`'{"min_region_m2":3}'`)
    /// or a file holding one (any of `ReconstructParams`' fields; the rest
    /// keep their defaults).
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// Print the result as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// With CityJSON footprints: a model per BuildingPart, written as a BuildingPart of its
    /// Building (as 3DBAG and Zurich's LoD2 model them); default: one per Building, its parts joined.
    #[arg(long, requires = "footprints")]
    pub parts: bool,
}

/// Reads `--params`: a JSON object of reconstruction parameters, given
/// inline (it starts with `{`) or in a file.
fn read_params(path: Option<&Path>) -> Result<ReconstructParams, RuntimeError> {
    let Some(p) = path else {
        return Ok(ReconstructParams::default());
    };
    let bad = |e: &dyn std::fmt::Display| err(format!("--params {}: {e}", p.display()));
    let given = p.to_string_lossy();
    let text = if given.trim_start().starts_with('{') {
        given.into_owned()
    } else {
        std::fs::read_to_string(p).map_err(|e| bad(&e))?
    };
    let params: ReconstructParams = serde_json::from_str(&text).map_err(|e| bad(&e))?;
    params.validate().map_err(|e| bad(&e))?;
    Ok(params)
}

/// `k / n`, `None` for nothing counted.
fn share(k: usize, n: usize) -> Option<f64> {
    (n > 0).then(|| k as f64 / n as f64)
}

/// The median of `v`, `None` when empty.
fn median(v: impl Iterator<Item = f64>) -> Option<f64> {
    let mut v: Vec<f64> = v.collect();
    v.sort_by(f64::total_cmp);
    (!v.is_empty()).then(|| v[v.len() / 2])
}

fn metres(v: Option<f64>) -> String {
    v.map_or_else(|| "–".into(), |v| format!("{v:.3}"))
}

/// The footprints models are made on, one model each; a BuildingPart's
/// model is written under its Building, whose id `part_of` keeps.
#[derive(Debug, Clone, Default)]
pub struct ModelFootprints {
    /// The footprints, in the cloud's frame.
    pub footprints: Vec<Footprint>,
    /// Per BuildingPart footprint id, its Building's id (empty: none are parts).
    pub part_of: BTreeMap<u32, String>,
}

impl ModelFootprints {
    /// The footprints `read` moved into a cloud's `frame` (CRS checked),
    /// with the Buildings its parts belong to.
    pub fn in_frame(
        read: &SourceFootprints,
        frame: &SourceFrame,
    ) -> Result<ModelFootprints, RuntimeError> {
        Ok(ModelFootprints {
            footprints: super::footprints::in_frame(read, frame)?,
            part_of: read.loaded.part_of.clone(),
        })
    }
}

/// Reconstructs `cloud` and writes `DIR/NAME.city.json` and `DIR/NAME.obj`
/// in its CRS and unit.
pub fn reconstruct_and_write(
    cloud: &Cloud,
    footprints: Option<&ModelFootprints>,
    (dir, name): (&Path, &str),
    params: &ReconstructParams,
) -> Result<Reconstruction, RuntimeError> {
    let given = footprints.map(|f| &f.footprints[..]);
    let mut rec = reconstruct_cloud(cloud, given, params).map_err(err)?;
    if let Some(f) = footprints {
        rec.part_of.clone_from(&f.part_of);
    }
    std::fs::create_dir_all(dir).map_err(|e| err(format!("{}: {e}", dir.display())))?;
    cityjson::write_cityjson(&dir.join(format!("{name}.city.json")), &rec).map_err(err)?;
    obj::write_obj(&dir.join(format!("{name}.obj")), &rec).map_err(err)?;
    Ok(rec)
}

/// One paragraph on [`BeforeAfter`]: the buildings whose prior model was
/// off, whether each came closer, and the noise on the rest.
pub fn verdict_md(v: &BeforeAfter) -> String {
    let rest = v
        .largest_rise_elsewhere
        .map_or("–".to_string(), |r| format!("{r:+.3} m"));
    format!(
        "Buildings whose model from the prior alone was off by more than {:.2} m (the walls it missed changed its shape): {:?}; closer to the truth after: {}. On the other buildings the prior's roof edges already gave the walls; their largest change is {rest}, the scanners' noise.\n",
        v.prior_off_m,
        v.prior_off,
        if v.not_improved.is_empty() {
            "every one".to_string()
        } else {
            format!("not {:?}", v.not_improved)
        }
    )
}

/// Per-building rows of one or two evaluations as a Markdown table (the
/// paper's model-accuracy table): before and after when both are given.
pub fn table(before: &ModelEvaluation, after: Option<&ModelEvaluation>) -> String {
    let mut s = String::new();
    match after {
        None => {
            s.push_str("| building | models | mean sym. dist (m) | RMSE | P95 | roof error | footprint IoU | watertight |\n|---|---|---|---|---|---|---|---|\n");
            for b in &before.buildings {
                s.push_str(&format!(
                    "| {} | {} | {} | {} | {} | {} | {} | {} |\n",
                    b.building,
                    b.models.len(),
                    metres(b.distance.mean),
                    metres(b.distance.rmse),
                    metres(b.distance.p95),
                    metres(b.roof_error),
                    b.footprint_iou.map_or("–".into(), |v| format!("{v:.3}")),
                    if b.watertight { "yes" } else { "no" }
                ));
            }
            s.push_str(&format!(
                "| **all** | {} | {} | {} | {} | {} | | {} |\n",
                before.models,
                metres(before.distance.mean),
                metres(before.distance.rmse),
                metres(before.distance.p95),
                metres(before.roof_error),
                if before.all_watertight { "yes" } else { "no" }
            ));
        }
        Some(after) => {
            s.push_str("| building | mean sym. dist before (m) | after | RMSE before | after | P95 before | after | roof error before | after | IoU before | after | watertight |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
            for b in &before.buildings {
                let a = after.buildings.iter().find(|a| a.building == b.building);
                let iou = |v: Option<f64>| v.map_or("–".into(), |v| format!("{v:.3}"));
                s.push_str(&format!(
                    "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                    b.building,
                    metres(b.distance.mean),
                    metres(a.and_then(|a| a.distance.mean)),
                    metres(b.distance.rmse),
                    metres(a.and_then(|a| a.distance.rmse)),
                    metres(b.distance.p95),
                    metres(a.and_then(|a| a.distance.p95)),
                    metres(b.roof_error),
                    metres(a.and_then(|a| a.roof_error)),
                    iou(b.footprint_iou),
                    iou(a.and_then(|a| a.footprint_iou)),
                    match (b.watertight, a.is_some_and(|a| a.watertight)) {
                        (true, true) => "yes",
                        _ => "no",
                    }
                ));
            }
            s.push_str(&format!(
                "| **all** | {} | {} | {} | {} | {} | {} | {} | {} | | | {} |\n",
                metres(before.distance.mean),
                metres(after.distance.mean),
                metres(before.distance.rmse),
                metres(after.distance.rmse),
                metres(before.distance.p95),
                metres(after.distance.p95),
                metres(before.roof_error),
                metres(after.roof_error),
                if before.all_watertight && after.all_watertight {
                    "yes"
                } else {
                    "no"
                }
            ));
        }
    }
    s
}

/// Measures `rec` against `scene`'s buildings.
pub fn evaluate_against(scene: &Scene, rec: &Reconstruction, spacing: f32) -> ModelEvaluation {
    let gt = sample_building_surfaces(scene, spacing);
    evaluate_models(scene, &gt, rec, f64::from(spacing))
}

/// Runs the reconstruction; an error names the input.
pub fn run(a: &ReconstructArgs) -> Result<serde_json::Value, RuntimeError> {
    reconstruct_file(a).map_err(|e| super::about(&a.input, e))
}

fn reconstruct_file(a: &ReconstructArgs) -> Result<serde_json::Value, RuntimeError> {
    if a.gt_spacing.is_nan() || a.gt_spacing <= 0.0 {
        return Err(err(format!(
            "--gt-spacing ({}) must be positive",
            a.gt_spacing
        )));
    }
    let params = read_params(a.params.as_deref())?;
    let given = a.footprints.read_parts(a.gt.as_deref(), a.parts)?;
    let cloud = a.units.read_tiles(&a.input)?;
    check_plan_extent(&cloud).map_err(err)?;
    if let Some(c) = cloud.crs.as_ref().filter(|c| c.epsg.is_none()) {
        // CityJSON names a CRS by an authority's URL; a WKT alone has none.
        eprintln!(
            "note: the cloud's CRS ({}) has no EPSG code, so models.city.json names none (its coordinates are in {}); state the code with --crs EPSG:N",
            c.label(),
            c.horizontal_unit.name()
        );
    }
    let footprints = given
        .as_ref()
        .map(|r| ModelFootprints::in_frame(r, &cloud.frame()))
        .transpose()?;
    let t0 = std::time::Instant::now();
    let rec = reconstruct_and_write(&cloud, footprints.as_ref(), (&a.out, "models"), &params)?;
    let seconds = t0.elapsed().as_secs_f64();
    let pts = building_points(&cloud, cloud.origin);
    let fit = points_to_models(&rec, &pts);
    let (fit, fit_points) = (fit.map(|f| f.0), fit.map_or(0, |f| f.1));
    let checks: Vec<_> = rec.models.iter().map(|m| m.shell.check()).collect();
    let eval = match &a.gt {
        Some(s) => {
            let scene =
                skyground_core::io::load_scene(s).map_err(|e| err(format!("scene {s}: {e}")))?;
            Some(evaluate_against(&scene, &rec, a.gt_spacing))
        }
        None => None,
    };
    let before_after = match (&a.before, &a.gt) {
        (Some(b), Some(s)) => {
            let scene =
                skyground_core::io::load_scene(s).map_err(|e| err(format!("scene {s}: {e}")))?;
            let prior = a.units.read(b)?;
            let (mb, ma) = before_after(
                &a.out,
                &scene,
                &prior,
                &cloud,
                a.gt_spacing,
                footprints.as_ref(),
            )?;
            let pictured = write_picture(
                &a.out.join("models.png"),
                &scene,
                &mb,
                &ma,
                3,
                &cloud.frame().unit(),
            )?;
            let verdict = skyground_core::reconstruct::compare(
                &mb,
                &ma,
                skyground_core::reconstruct::PRIOR_OFF_M,
            );
            let md = format!(
                "# LoD2 models before ({}) and after ({})\n\n`models.png`: buildings {pictured:?} (rows, each labelled with its id), before left, after right, coloured by distance to the truth 0 → 0.5 m; each column's head gives its mean distance; scale bar in the input's unit; north up.\n\n{}\n{}",
                b.display(),
                super::units::describe(&a.input),
                table(&mb, Some(&ma)),
                verdict_md(&verdict)
            );
            skyground_core::file::write(&a.out.join("models.md"), &md)
                .map_err(|e| err(format!("{}: {e}", a.out.display())))?;
            if !a.json {
                eprintln!("{md}");
            }
            Some(serde_json::json!({
                "model_dist_before": mb.distance.mean, "model_dist_after": ma.distance.mean,
                "models_before": mb, "models_after": ma, "models_pictured": pictured,
                "models_compared": verdict,
            }))
        }
        _ => None,
    };
    // Coordinates in the cloud's CRS and unit; distances in metres.
    let frame = rec.frame();
    let models: Vec<serde_json::Value> = rec
        .models
        .iter()
        .zip(&checks)
        .map(|(m, c)| {
            serde_json::json!({
                "id": m.id, "name": m.name, "faces": m.shell.faces.len(),
                "vertices": m.shell.vertices.len(), "roof_planes": m.planes,
                "points": m.points, "roof_density": m.roof_density, "base": frame.to_source([0.0, 0.0, m.base])[2], "open_ground_floor": m.open_base,
                "walls": m.walls, "check": c, "watertight": c.watertight(),
                "valid": m.quality.val3dity.is_empty(), "val3dity": m.quality.val3dity,
                "lod": m.lod, "fallback_reason": m.fallback, "rejected_val3dity": m.quality.rejected_val3dity,
                "rmse_m": m.quality.rmse_m, "rmse_roof_points_m": m.quality.rmse_roof_points_m,
                "footprint_iou": m.quality.footprint_iou,
                "part_of": rec.part_of.get(&m.id),
            })
        })
        .collect();
    let value = serde_json::json!({
        "input": super::units::describe(&a.input),
        "crs": super::info::crs_json(cloud.crs.as_ref()),
        "footprints": a.footprints.footprints,
        "models_written": a.out.join("models.city.json"),
        "models": rec.models.len(),
        "skipped": rec.skipped.iter().map(|(id, why)| serde_json::json!({"id": id, "why": why})).collect::<Vec<_>>(),
        "all_watertight": checks.iter().all(|c| c.watertight()),
        "all_valid": rec.models.iter().all(|m| m.quality.val3dity.is_empty()),
        "valid_share": share(rec.models.iter().filter(|m| m.quality.val3dity.is_empty()).count(), rec.models.len()),
        "lod12_fallbacks": rec.models.iter().filter(|m| m.fallback.is_some()).count(),
        // Of those, LoD 2.2 solids that failed the ISO 19107 checks.
        "invalid_lod22_replaced": rec.models.iter().filter(|m| !m.quality.rejected_val3dity.is_empty()).count(),
        "rmse_median_m": median(rec.models.iter().filter_map(|m| m.quality.rmse_m)),
        "rmse_roof_points_median_m": median(rec.models.iter().filter_map(|m| m.quality.rmse_roof_points_m)),
        "points_to_model_mean": fit,
        "building_points": pts.len(),
        "points_on_models": fit_points,
        "seconds": seconds,
        "evaluation": eval,
        "before_after": before_after,
        "per_model": models,
    });
    skyground_core::file::write(&a.out.join("reconstruct.json"), format!("{value:#}\n"))
        .map_err(|e| err(format!("{}: {e}", a.out.display())))?;
    if !a.json {
        eprintln!(
            "{} models ({} skipped) in {seconds:.2} s, all watertight: {}; mean points → model distance {} m ({fit_points} of {} points lie on the models' footprints)",
            rec.models.len(),
            rec.skipped.len(),
            checks.iter().all(|c| c.watertight()),
            metres(fit),
            pts.len()
        );
        if let Some(e) = &eval {
            eprintln!("{}", table(e, None));
        }
    }
    Ok(value)
}

/// The demo's step 10: models from the aerial prior and from the merged
/// cloud (`DIR/models_before.*`, `DIR/models_after.*`), each measured
/// against `scene`'s buildings.
pub fn before_after(
    dir: &Path,
    scene: &Scene,
    prior: &Cloud,
    merged: &Cloud,
    spacing: f32,
    footprints: Option<&ModelFootprints>,
) -> Result<(ModelEvaluation, ModelEvaluation), RuntimeError> {
    Ok((
        models_of(dir, "models_before", scene, prior, spacing, footprints)?,
        models_of(dir, "models_after", scene, merged, spacing, footprints)?,
    ))
}

/// Reconstructs `cloud`, writes `DIR/NAME.city.json` and `.obj`, and
/// evaluates the models against the scene's buildings.
pub fn models_of(
    dir: &Path,
    name: &str,
    scene: &Scene,
    cloud: &Cloud,
    spacing: f32,
    footprints: Option<&ModelFootprints>,
) -> Result<ModelEvaluation, RuntimeError> {
    let rec = reconstruct_and_write(
        cloud,
        footprints,
        (dir, name),
        &ReconstructParams::default(),
    )?;
    Ok(evaluate_against(scene, &rec, spacing))
}

/// A picture's row label: the scene's name for the building (its CityObject
/// or OBJ object id) and the id report.json lists it under.
fn view_id(f: &skyground_core::footprint::Footprint) -> String {
    if f.name.is_empty() {
        format!("id {}", f.id)
    } else {
        format!("{} (id {})", f.name, f.id)
    }
}

/// Writes `models.png`: the `n` buildings whose models improved most,
/// before and after, coloured by distance to the truth (0 → 0.5 m), each
/// row labelled with its building's id; the scale bar in `unit`.
pub fn write_picture(
    path: &Path,
    scene: &Scene,
    before: &ModelEvaluation,
    after: &ModelEvaluation,
    n: usize,
    unit: &skyground_core::crs::LinearUnit,
) -> Result<Vec<u32>, RuntimeError> {
    let outlines = skyground_core::footprint::footprints_of_scene(scene);
    let mut gains: Vec<(f64, u32)> = before
        .buildings
        .iter()
        .filter_map(|b| {
            let a = after.buildings.iter().find(|a| a.building == b.building)?;
            Some((b.distance.mean? - a.distance.mean?, b.building))
        })
        .collect();
    gains.sort_by(|x, y| y.0.total_cmp(&x.0));
    let chosen: Vec<u32> = gains.iter().take(n).map(|g| g.1).collect();
    let views: Vec<skyground_core::plot::ModelView> = chosen
        .iter()
        .filter_map(|id| {
            let b = before.buildings.iter().find(|b| b.building == *id)?;
            let a = after.buildings.iter().find(|a| a.building == *id)?;
            let f = outlines.iter().find(|f| f.id == *id)?;
            Some(skyground_core::plot::ModelView {
                id: view_id(f),
                before: b.samples.clone(),
                after: a.samples.clone(),
                outline: f.polygon.clone(),
            })
        })
        .collect();
    skyground_core::plot::models_picture(&views, 0.5, 1800, unit)
        .and_then(|c| c.save(path))
        .map_err(err)?;
    Ok(chosen)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_inline_or_in_a_file_and_a_bad_value_named() {
        let inline = read_params(Some(Path::new(r#"{"min_region_m2": 3.0}"#))).unwrap();
        assert_eq!(inline.min_region_m2, 3.0);
        let f = std::env::temp_dir().join(format!("skyground_params_{}.json", std::process::id()));
        std::fs::write(&f, r#"{"min_plane_points": 30}"#).unwrap();
        let from_file = read_params(Some(&f)).unwrap();
        let _ = std::fs::remove_file(&f);
        assert_eq!(from_file.min_plane_points, 30);
        let e = read_params(Some(Path::new(r#"{"min_region_m2": -1}"#))).unwrap_err();
        assert!(e.to_string().contains("min_region_m2"), "{e}");
    }
}
