//! `skyground aerial`: simulate the airborne survey of a scene and measure how
//! complete its buildings are in it (docs/design.md "Scenes", "Metrics").

use std::path::PathBuf;
use std::time::Instant;

use serde::Deserialize;
use serde_json::json;
use skyground_core::cloud::{Cloud, CloudIoError, write_cloud};
use skyground_core::io::load_scene_and_crs;
use skyground_core::lidar::airborne::survey_areas;
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::metrics::{
    CompletenessReport, GtSamples, SurfaceKind, completeness_of_cloud, nearest_distances,
    sample_building_surfaces,
};
use skyground_core::scene::Scene;

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

/// A simulated survey of a scene with its ground truth and completeness.
pub struct Survey {
    /// The scene.
    pub scene: Scene,
    /// The airborne cloud (labels 2/5/6, building ids).
    pub cloud: skyground_core::cloud::Cloud,
    /// Ground-truth samples of building surfaces.
    pub gt: GtSamples,
    /// Completeness radius, m.
    pub tau: f32,
    /// The JSON summary.
    pub summary: serde_json::Value,
}

/// Loads the scene, flies the survey (config/aerial.yaml, then `params_file`)
/// and measures the cloud against ground truth.
pub fn survey(
    scene_spec: &str,
    params_file: Option<&std::path::Path>,
) -> Result<Survey, RuntimeError> {
    let t0 = Instant::now();
    let (scene, crs) = load_scene_and_crs(scene_spec)
        .map_err(|e| RuntimeError::Node(format!("scene {scene_spec}: {e}")))?;
    let load_s = t0.elapsed().as_secs_f64();
    let mut s = survey_of(scene, scene_spec, params_file)?;
    s.summary["seconds"]["load"] = json!(load_s);
    // The scene is in metres inside; a writer gives the model's unit back.
    s.cloud.crs = crs;
    Ok(s)
}

/// [`survey`] of a scene already loaded (`scene_spec` names it in messages).
pub fn survey_of(
    scene: Scene,
    scene_spec: &str,
    params_file: Option<&std::path::Path>,
) -> Result<Survey, RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let p = params(params_file)?;
    let caster = Caster::new(&scene).map_err(|e| err(format!("scene {scene_spec}: {e}")))?;
    check_survey_size(&scene, &caster, &p, scene_spec)?;
    let t1 = Instant::now();
    let cloud = airborne_scan(&caster, &p.survey).map_err(|e| err(format!("survey: {e}")))?;
    let scan_s = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    let (mut s, report) = measured(scene, cloud, &p);
    let metric_s = t2.elapsed().as_secs_f64();
    let area = upward_area(&s.scene);
    let more = json!({
        "scene": scene_spec,
        "triangles": s.scene.triangles.len(),
        // Over the xy area of the surfaces an airborne scanner faces (ground,
        // roofs), not the bounding box: city models can be sparse patches.
        "density_pts_per_m2": if area > 0.0 { s.cloud.len() as f64 / area } else { 0.0 },
        "nominal_density_pts_per_m2": p.survey.nominal_density(),
        "per_building": report.buildings,
        "seconds": {"survey": scan_s, "metrics": metric_s},
    });
    if let (Some(shared), serde_json::Value::Object(m)) = (s.summary.as_object_mut(), more) {
        shared.extend(m);
    }
    Ok(s)
}

/// The survey of `scene` that gave `cloud`: its ground truth, the summary's
/// shared part (scene size, GT, completeness, where the gaps are), and the
/// completeness report.
fn measured(scene: Scene, cloud: Cloud, p: &Params) -> (Survey, CompletenessReport) {
    let gt = sample_building_surfaces(&scene, p.gt_spacing_m);
    let report = completeness_of_cloud(&gt, &cloud, p.tau_m);
    let gaps = gap_profile(&scene, &gt, &cloud.xyz, p.tau_m);
    let summary = json!({
        "origin": scene.origin,
        "buildings": scene.building_count(),
        "points": cloud.len(),
        "gt_samples": gt.xyz.len(),
        "tau_m": p.tau_m,
        "completeness": report.overall.ratio,
        "completeness_walls": report.walls.ratio,
        "completeness_roofs": report.roofs.ratio,
        "mean_gt_distance_m": report.mean_gt_distance,
        "where_the_gaps_are": gaps,
    });
    let s = Survey {
        scene,
        cloud,
        gt,
        tau: p.tau_m,
        summary,
    };
    (s, report)
}

/// config/aerial.yaml, then `params_file`.
fn params(params_file: Option<&std::path::Path>) -> Result<Params, RuntimeError> {
    let mut params = ParamSet::default();
    params.merge_yaml(DEFAULTS, "aerial", "config/aerial.yaml")?;
    if let Some(f) = params_file {
        params.merge_file(f, "aerial")?;
    }
    Ok(params.parse("aerial")?)
}

/// A real survey (`cloud`, already in the scene's local frame) as the prior
/// of `scene`: ground truth and completeness measured exactly as for the
/// simulated survey (same GT spacing and τ, config/aerial.yaml).
pub fn survey_of_real(
    scene: Scene,
    cloud: skyground_core::cloud::Cloud,
    prior_name: &str,
) -> Result<Survey, RuntimeError> {
    let (mut s, _) = measured(scene, cloud, &params(None)?);
    s.summary["prior"] = json!(prior_name);
    Ok(s)
}

/// Runs the survey simulation and writes its outputs.
pub fn run(a: &AerialArgs) -> Result<serde_json::Value, RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let mut s = survey(&a.scene, a.params_file.as_deref())?;
    std::fs::create_dir_all(&a.out).map_err(|e| err(format!("{}: {e}", a.out.display())))?;
    for name in ["aerial.las", "aerial.ply"] {
        write_cloud(&a.out.join(name), &s.cloud).map_err(|e| err(e.to_string()))?;
    }
    let gt_path = a.out.join("gt_samples.ply");
    skyground_core::file::write_with(&gt_path, |file| {
        s.gt.write_ply(std::io::BufWriter::new(file))
            .map_err(|source| CloudIoError::Ply {
                path: gt_path.clone(),
                source,
            })
    })
    .map_err(|e| err(e.to_string()))?;
    s.summary["outputs"] = json!({
        "las": a.out.join("aerial.las"),
        "ply": a.out.join("aerial.ply"),
        "gt": gt_path,
    });
    skyground_core::file::write(&a.out.join("summary.json"), format!("{:#}", s.summary))
        .map_err(|e| err(e.to_string()))?;
    Ok(s.summary)
}

/// Most points a simulated survey, and apart from it the ground-truth
/// samples of the buildings, may hold in one run (~1.2 GB each).
const MAX_SURVEY_POINTS: f64 = 5e7;

/// `Err`, before anything is allocated, when the survey of `scene` (its
/// parts' plan areas at the survey's nominal density) or the samples of its
/// building surfaces would hold more than [`MAX_SURVEY_POINTS`]: a
/// kilometre-wide terrain mesh, or a model whose integer vertices lack the
/// scale that makes them metres.
fn check_survey_size(
    scene: &Scene,
    caster: &Caster,
    p: &Params,
    spec: &str,
) -> Result<(), RuntimeError> {
    let Some((lo, hi)) = scene.bounds() else {
        return Ok(());
    };
    let size = [0, 1].map(|k| f64::from(hi[k] - lo[k]));
    let density = f64::from(p.survey.nominal_density());
    // Parts far apart are flown over one by one: only their own areas count.
    let patches = survey_areas(caster, &p.survey);
    let points = patches.iter().map(|q| q.area()).sum::<f64>() * density;
    let building_area: f64 = (0..scene.triangles.len())
        .filter(|&t| {
            let o = scene.triangle_object.get(t).map(|&o| o as usize);
            o.and_then(|o| scene.objects.get(o))
                .is_some_and(|o| o.kind == skyground_core::scene::ObjectKind::Building)
        })
        .filter_map(|t| scene.triangle_corners(t))
        .map(|[a, b, c]| {
            let (u, v) = (
                [0, 1, 2].map(|k| b[k] - a[k]),
                [0, 1, 2].map(|k| c[k] - a[k]),
            );
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            f64::from((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()) / 2.0
        })
        .sum();
    let samples = building_area / f64::from(p.gt_spacing_m).powi(2);
    let limit = MAX_SURVEY_POINTS;
    if points.is_finite() && samples.is_finite() && points <= limit && samples <= limit {
        return Ok(());
    }
    Err(RuntimeError::Node(format!(
        "scene {spec}: {:.0} m × {:.0} m in plan ({} part(s) far apart), {:.0} m² of building surface: its survey at {density:.1} pts/m² would hold ~{:.2e} points and its ground truth at {} m spacing ~{:.2e} samples, more than the {limit:.0e} one run holds in memory: crop the scene (skyground crop), lower the survey's density in a params file, or check the model's units",
        size[0],
        size[1],
        patches.len(),
        building_area,
        points,
        p.gt_spacing_m,
        samples
    )))
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

/// Completeness of the parts of buildings airborne scans are known to miss:
/// the lowest 3 m of walls, walls within 6 m of a tree, undersides (e.g. the
/// floor over a hollow base), against the rest of the walls and the roofs.
fn gap_profile(
    scene: &skyground_core::scene::Scene,
    gt: &GtSamples,
    observed: &[[f32; 3]],
    tau: f32,
) -> serde_json::Value {
    use skyground_core::scene::ObjectKind;
    let covered: Vec<bool> = nearest_distances(&gt.xyz, observed)
        .into_iter()
        .map(|d| d <= tau)
        .collect();
    let mut base = std::collections::HashMap::<u32, f32>::new();
    for (p, b) in gt.xyz.iter().zip(&gt.building) {
        let e = base.entry(*b).or_insert(f32::INFINITY);
        *e = e.min(p[2]);
    }
    let trees: Vec<[f32; 3]> = scene
        .triangles
        .iter()
        .zip(&scene.triangle_object)
        .filter(|(_, o)| {
            scene
                .objects
                .get(**o as usize)
                .is_some_and(|o| o.kind == ObjectKind::Vegetation)
        })
        .filter_map(|(t, _)| scene.vertices.get(t[0] as usize).copied())
        .collect();
    let near_tree: Vec<bool> = if trees.is_empty() {
        vec![false; gt.len()]
    } else {
        nearest_distances(&gt.xyz, &trees)
            .into_iter()
            .map(|d| d <= 6.0)
            .collect()
    };
    let mut groups = [(0usize, 0usize); 5];
    for i in 0..gt.len() {
        let (Some(p), Some(n), Some(k), Some(b)) = (
            gt.xyz.get(i),
            gt.normal.get(i),
            gt.kind.get(i),
            gt.building.get(i),
        ) else {
            continue;
        };
        let g = if *k == SurfaceKind::Roof {
            4
        } else if n[2] < -0.5 {
            2
        } else if near_tree.get(i) == Some(&true) {
            1
        } else if p[2] - base.get(b).copied().unwrap_or(p[2]) < 3.0 {
            0
        } else {
            3
        };
        if let (Some(slot), Some(c)) = (groups.get_mut(g), covered.get(i)) {
            slot.0 += 1;
            slot.1 += usize::from(*c);
        }
    }
    let ratio = |(n, c): (usize, usize)| json!({"samples": n, "completeness": if n > 0 { Some(c as f64 / n as f64) } else { None }});
    json!({
        "walls_lowest_3m": ratio(groups[0]),
        "walls_near_trees": ratio(groups[1]),
        "undersides": ratio(groups[2]),
        "other_walls": ratio(groups[3]),
        "roofs": ratio(groups[4]),
    })
}
