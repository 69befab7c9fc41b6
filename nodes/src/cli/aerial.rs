//! `skyground aerial`: simulate the airborne survey of a scene and measure how
//! complete its buildings are in it (DESIGN.md "Scenes", "Metrics").

use std::path::PathBuf;
use std::time::Instant;

use serde::Deserialize;
use serde_json::json;
use skyground_core::cloud::write_cloud;
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::metrics::{completeness_of_cloud, sample_building_surfaces};
use skyground_core::scene::load_scene;

use crate::runtime::{RuntimeError, params::ParamSet};

/// Options of `skyground aerial`.
#[derive(Debug, Clone, clap::Args)]
pub struct AerialArgs {
    /// reference, reference:SEED, or a scene file (.obj, .ply, CityJSON .json).
    #[arg(long, default_value = "reference")]
    pub scene: String,
    /// Output directory: aerial.las, aerial.ply, gt_samples.ply, summary.json.
    #[arg(long, default_value = "out/aerial")]
    pub out: PathBuf,
    /// A params file overriding config/aerial.yaml (node name `aerial`).
    #[arg(long)]
    pub params_file: Option<PathBuf>,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(default)]
    survey: AirborneConfig,
    gt_spacing_m: f32,
    tau_m: f32,
}

const DEFAULTS: &str = include_str!("../../../config/aerial.yaml");

/// Runs the survey simulation and writes its outputs.
pub fn run(a: &AerialArgs) -> Result<serde_json::Value, RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let mut params = ParamSet::default();
    params.merge_yaml(DEFAULTS, "aerial", "config/aerial.yaml")?;
    if let Some(f) = &a.params_file {
        params.merge_file(f, "aerial")?;
    }
    let p: Params = params.parse("aerial")?;
    let t0 = Instant::now();
    let scene = load_scene(&a.scene).map_err(|e| err(format!("scene {}: {e}", a.scene)))?;
    let load_s = t0.elapsed().as_secs_f64();
    let caster = Caster::new(&scene).map_err(|e| err(format!("scene {}: {e}", a.scene)))?;
    let t1 = Instant::now();
    let cloud = airborne_scan(&caster, &p.survey).map_err(|e| err(format!("survey: {e}")))?;
    let scan_s = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    let gt = sample_building_surfaces(&scene, p.gt_spacing_m);
    let report = completeness_of_cloud(&gt, &cloud, p.tau_m);
    let metric_s = t2.elapsed().as_secs_f64();
    std::fs::create_dir_all(&a.out).map_err(|e| err(format!("{}: {e}", a.out.display())))?;
    for name in ["aerial.las", "aerial.ply"] {
        write_cloud(&a.out.join(name), &cloud).map_err(|e| err(e.to_string()))?;
    }
    let gt_path = a.out.join("gt_samples.ply");
    let file =
        std::fs::File::create(&gt_path).map_err(|e| err(format!("{}: {e}", gt_path.display())))?;
    gt.write_ply(std::io::BufWriter::new(file))
        .map_err(|e| err(format!("{}: {e}", gt_path.display())))?;
    let area = upward_area(&scene);
    let buildings = scene.building_count();
    let summary = json!({
        "scene": a.scene,
        "origin": scene.origin,
        "triangles": scene.triangles.len(),
        "buildings": buildings,
        "points": cloud.len(),
        // Over the xy area of the surfaces an airborne scanner faces (ground,
        // roofs), not the bounding box: city models can be sparse patches.
        "density_pts_per_m2": if area > 0.0 { cloud.len() as f64 / area } else { 0.0 },
        "nominal_density_pts_per_m2": p.survey.nominal_density(),
        "gt_samples": gt.xyz.len(),
        "tau_m": p.tau_m,
        "completeness": report.overall.ratio,
        "completeness_walls": report.walls.ratio,
        "completeness_roofs": report.roofs.ratio,
        "mean_gt_distance_m": report.mean_gt_distance,
        "per_building": report.buildings,
        "seconds": {"load": load_s, "survey": scan_s, "metrics": metric_s},
        "outputs": {
            "las": a.out.join("aerial.las"),
            "ply": a.out.join("aerial.ply"),
            "gt": a.out.join("gt_samples.ply"),
        },
    });
    std::fs::write(a.out.join("summary.json"), format!("{summary:#}"))
        .map_err(|e| err(format!("{}: {e}", a.out.display())))?;
    Ok(summary)
}

/// The xy-projected area of the upward-facing triangles, m².
fn upward_area(scene: &skyground_core::scene::Scene) -> f64 {
    (0..scene.triangles.len())
        .filter_map(|t| scene.triangle_corners(t))
        .map(|[a, b, c]| {
            let z = f64::from((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2.0;
            z.max(0.0)
        })
        .sum()
}
