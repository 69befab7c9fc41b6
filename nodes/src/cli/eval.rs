//! `skyground eval`: the before/after evaluation of a mission offline
//! (docs/design.md "Metrics"): an aerial cloud and a merged cloud against a scene.

use std::path::{Path, PathBuf};

use skyground_core::cloud::read_cloud;
use skyground_core::io::load_scene_and_crs;
use skyground_core::metrics::{Evaluation, evaluate, sample_building_surfaces};

use super::err;
use crate::runtime::RuntimeError;

/// Options of `skyground eval`.
#[derive(Debug, Clone, clap::Args)]
pub struct EvalArgs {
    /// The aerial prior (LAS/LAZ/PLY).
    #[arg(long)]
    pub aerial: PathBuf,
    /// The merged cloud: aerial + ground scans (LAS/LAZ/PLY).
    #[arg(long)]
    pub resampled: PathBuf,
    /// The scene whose buildings are the ground truth: reference, reference:SEED, or a file.
    #[arg(long, default_value = "reference")]
    pub scene: String,
    /// Evaluate on one cluster of buildings of the scene, as `skyground demo --crop`.
    #[command(flatten)]
    pub crop: super::crop::CropArgs,
    /// Completeness radius τ, m.
    #[arg(long, default_value_t = 0.25)]
    pub tau: f32,
    /// Spacing of the ground-truth samples, m.
    #[arg(long, default_value_t = 0.25)]
    pub gt_spacing: f32,
    /// Also write DIR/eval.json, DIR/eval.md and DIR/completeness.city.json.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the evaluation as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// The evaluation as Markdown: the summary table, then per building.
pub fn markdown(e: &Evaluation, title: &str) -> String {
    format!(
        "# {title}\n\n{}\n## Per building\n\n{}",
        e.summary_markdown(),
        e.buildings_markdown()
    )
}

/// Writes `value` as pretty JSON to `path`.
pub fn write_json(path: &Path, value: &serde_json::Value) -> Result<(), RuntimeError> {
    skyground_core::file::write(path, format!("{value:#}\n")).map_err(err)
}

/// Runs the evaluation.
pub fn run(a: &EvalArgs) -> Result<serde_json::Value, RuntimeError> {
    if !(a.tau > 0.0 && a.gt_spacing > 0.0) {
        return Err(err(format!(
            "--tau ({}) and --gt-spacing ({}) must be positive",
            a.tau, a.gt_spacing
        )));
    }
    let (full, model_crs) =
        load_scene_and_crs(&a.scene).map_err(|e| err(format!("scene {}: {e}", a.scene)))?;
    let crop = super::crop::apply(&full, &a.scene, &a.crop)?;
    if let Some(c) = &crop {
        eprintln!("  {}", super::crop::describe(c, model_crs.as_ref()));
    }
    let scene = crop.as_ref().map_or(&full, |c| &c.scene);
    let aerial = read_cloud(&a.aerial).map_err(err)?;
    let merged = read_cloud(&a.resampled).map_err(err)?;
    let gt = sample_building_surfaces(scene, a.gt_spacing);
    let e = evaluate(scene, &gt, &aerial, &merged, a.tau);
    let value = serde_json::json!({
        "scene": a.scene,
        "crop": crop.as_ref().map(|c| super::crop::to_json(c, model_crs.as_ref())),
        "aerial": a.aerial,
        "resampled": a.resampled,
        "coverage_before": e.before.completeness.overall.ratio,
        "coverage_after": e.after.completeness.overall.ratio,
        "mean_gt_dist_before": e.before.completeness.mean_gt_distance,
        "mean_gt_dist_after": e.after.completeness.mean_gt_distance,
        "mean_cloud_to_mesh_before": e.before.mean_cloud_to_mesh,
        "mean_cloud_to_mesh_after": e.after.mean_cloud_to_mesh,
        "evaluation": e,
    });
    if let Some(dir) = &a.out {
        std::fs::create_dir_all(dir).map_err(|e| err(format!("{}: {e}", dir.display())))?;
        write_json(&dir.join("eval.json"), &value)?;
        skyground_core::file::write(
            &dir.join("eval.md"),
            markdown(&e, &format!("skyground eval: {}", a.scene)),
        )
        .map_err(|e| err(format!("{}: {e}", dir.display())))?;
        super::city_model::write_completeness(
            dir,
            &a.scene,
            scene,
            crop.as_ref(),
            &e,
            gt.spacing,
            None,
        )?;
    }
    if !a.json {
        eprintln!("{}", markdown(&e, &format!("skyground eval: {}", a.scene)));
    }
    Ok(value)
}
