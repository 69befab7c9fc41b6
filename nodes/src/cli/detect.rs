//! `skyground detect`: steps 2–4 of the method offline — buildings, where
//! their walls are missing, and the targets that would fill the gaps — with
//! a top-down PNG, and recall/precision against ground truth with `--gt`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Deserialize;
use serde_json::json;
use skyground_core::classify::SceneClassifier;
use skyground_core::cloud::extent::check_plan_extent;
use skyground_core::cloud::{Cloud, class, write_cloud};
use skyground_core::file;
use skyground_core::io::load_scene;
use skyground_core::metrics::{
    TARGET_REACH_M, building_points, producer_check, sample_building_surfaces,
};
use skyground_core::missing::{SceneParams, detect_scene, evaluate_explained, shift_missing};
use skyground_core::plot::detection_picture;
use skyground_core::targets::{Site, TargetParams, consolidate, generate};

use super::err;
use crate::convert::detection::strategy_name;
use crate::runtime::RuntimeError;
use crate::runtime::model::load_model_file;
use crate::runtime::params::section;

/// Options of `skyground detect`.
#[derive(Debug, Clone, clap::Args)]
pub struct DetectArgs {
    /// A classified cloud (LAS/LAZ/PLY with labels); unlabelled clouds are classified first.
    /// Several files (tiles of one survey, one CRS) are one survey: a building
    /// the tiles' seam cuts is whole.
    #[arg(long = "in", num_args = 1.., required = true)]
    pub inputs: Vec<PathBuf>,
    #[command(flatten)]
    pub footprints: super::footprints::FootprintsArg,
    /// Output directory: classified.laz (classified.las unless every input is LAZ),
    /// missing.las, targets.json, detection.json, detection.png.
    #[arg(long, default_value = "out/detect")]
    pub out: PathBuf,
    /// Ground truth for recall/precision: a scene (reference, reference:SEED, file) or a
    /// `skyground aerial` output directory (its summary.json names the scene).
    #[arg(long)]
    pub gt: Option<String>,
    /// Classify even when the cloud has labels.
    #[arg(long)]
    pub classify: bool,
    /// The classifier model when classifying (default: the shipped one), e.g.
    /// one trained without this file, to check detection on held-out classes.
    #[arg(long, requires = "classify")]
    pub model: Option<PathBuf>,
    /// A params file (sections completeness_detector and target_generator).
    #[arg(long)]
    pub params_file: Option<PathBuf>,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub units: super::units::UnitsArg,
}

#[derive(Debug, Deserialize, Default)]
struct GeneratorParams {
    #[serde(default)]
    targets: TargetParams,
}

/// The scene named by `--gt`.
fn gt_scene(spec: &str) -> Result<String, RuntimeError> {
    let summary = Path::new(spec).join("summary.json");
    if summary.is_file() {
        let text = std::fs::read_to_string(&summary)
            .map_err(|e| err(format!("{}: {e}", summary.display())))?;
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| err(format!("{}: {e}", summary.display())))?;
        return v
            .get("scene")
            .and_then(|s| s.as_str())
            .map(str::to_string)
            .ok_or_else(|| err(format!("{} names no scene", summary.display())));
    }
    Ok(spec.to_string())
}

/// Runs detection (and targets) on a file; an error names the file.
pub fn run(a: &DetectArgs) -> Result<serde_json::Value, RuntimeError> {
    detect_files(a).map_err(|e| super::about(&a.inputs, e))
}

fn detect_files(a: &DetectArgs) -> Result<serde_json::Value, RuntimeError> {
    use crate::runtime::specs::{COMPLETENESS_DETECTOR, TARGET_GENERATOR};
    let pd: SceneParams = section(
        "completeness_detector",
        COMPLETENESS_DETECTOR.default_params,
        a.params_file.as_deref(),
        &["detect", "split", "derive"],
    )?;
    let pg: GeneratorParams = section(
        "target_generator",
        TARGET_GENERATOR.default_params,
        a.params_file.as_deref(),
        &["targets"],
    )?;
    // Footprints are read first: a file that cannot be used stops here.
    let scene = a.gt.as_deref().map(gt_scene).transpose()?;
    let given = a.footprints.read(scene.as_deref())?;
    let t0 = Instant::now();
    let mut cloud: Cloud = a.units.read_tiles(&a.inputs)?;
    check_plan_extent(&cloud).map_err(err)?;
    let footprints = given
        .as_ref()
        .map(|r| super::footprints::in_frame(r, &cloud.frame()))
        .transpose()?;
    let labelled = cloud
        .label
        .as_ref()
        .is_some_and(|l| l.contains(&class::BUILDING));
    // The producer's classes, to check the result against (also with --classify).
    let producer = cloud.label.clone().filter(|_| labelled);
    let mut classify_s = 0.0;
    if a.classify || !labelled {
        let t = Instant::now();
        let c = SceneClassifier::new(Default::default(), load_model_file(a.model.as_deref())?)
            .map_err(err)?;
        cloud.label = Some(c.classify_cloud(&cloud).map_err(err)?.labels);
        classify_s = t.elapsed().as_secs_f64();
    }
    let t1 = Instant::now();
    let (detection, used) = detect_scene(&cloud, None, footprints.as_deref(), &pd).map_err(err)?;
    let detect_s = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    let labels = cloud.label.as_deref().unwrap_or_default();
    let site =
        Site::from_cloud(&cloud.xyz, labels, pg.targets.cell, pg.targets.clearance).map_err(err)?;
    let (mut targets, dropped) = generate(&detection, &site, &pg.targets).map_err(err)?;
    // One stop for every gap it sees, shared between buildings (as target_generator does).
    let (kept, consolidation) = consolidate(
        &targets.points,
        &detection.missing_points(),
        &site,
        &pg.targets,
    );
    targets.points = kept;
    let targets_s = t2.elapsed().as_secs_f64();

    let bpts = cloud.xyz_of_class(class::BUILDING);
    let mut missing = Cloud::from_xyz(detection.missing_xyz());
    missing.building = Some(
        detection
            .missing_points()
            .iter()
            .map(|m| m.building)
            .collect(),
    );
    missing.origin = cloud.origin;
    missing.crs = cloud.crs.clone();
    let png = a.out.join("detection.png");
    let unit = cloud.frame().unit();
    // A tile without buildings still gets its picture, of the whole tile
    // (a cloud of one point, of the metre around it). Drawn before anything
    // is written: a failure leaves the directory as it was.
    let survey = cloud.bounds().map(|(lo, hi)| {
        let (lo, hi) = ([lo[0], lo[1]].map(f64::from), [hi[0], hi[1]].map(f64::from));
        let pad = |k: usize| if hi[k] - lo[k] < 1.0 { 0.5 } else { 0.0 };
        (
            [lo[0] - pad(0), lo[1] - pad(1)],
            [hi[0] + pad(0), hi[1] + pad(1)],
        )
    });
    let picture =
        detection_picture(&bpts, &detection, Some(&targets), survey, 2400, &unit).map_err(err)?;
    std::fs::create_dir_all(&a.out).map_err(|e| err(format!("{}: {e}", a.out.display())))?;
    // The producer's points with the classes used: every other field stays.
    let classified = classified_path(&a.out, &a.inputs)?;
    super::classify::write_classified(&a.inputs, &classified, &cloud)?;
    write_cloud(&a.out.join("missing.las"), &missing).map_err(err)?;
    // The gaps with their normals ride along, so `skyground plan` can tell
    // which stops the route sees anyway (as the planner does from /missing_points).
    let targets_json = json!({
        "origin": cloud.origin,
        "targets": targets,
        "missing": detection.missing_points(),
    });
    // Compact: on a 10 M-point tile the gaps alone are 350 k entries.
    let targets_path = a.out.join("targets.json");
    file::write(&targets_path, format!("{targets_json}\n")).map_err(err)?;
    let field = super::field::write_detection(&a.out, &cloud, &detection, &targets)?;
    picture.save(&png).map_err(err)?;

    let per_building: Vec<serde_json::Value> = detection
        .buildings
        .iter()
        .map(|b| {
            json!({
                "building": b.building,
                "footprint_id": b.footprint_id,
                "points": b.points,
                "skipped": b.skipped.as_ref().map(ToString::to_string),
                "slices": b.slices.len(),
                "structures": b.structures.len(),
                "boundary_points": b.boundary.len(),
                "missing_points": b.missing.len(),
                "r_missing": b.r_missing,
                "strategy": strategy_name(b.strategy),
            })
        })
        .collect();
    file::write(
        &a.out.join("detection.json"),
        format!("{:#}\n", json!(per_building)),
    )
    .map_err(err)?;
    let analysed = detection
        .buildings
        .iter()
        .filter(|b| b.skipped.is_none())
        .count();
    let mut out = json!({
        "input": super::units::describe(&a.inputs),
        "inputs": a.inputs,
        "points": cloud.len(),
        "building_points": bpts.len(),
        "footprints": if footprints.is_some() { "given" } else { "derived" },
        "buildings": detection.buildings.len(),
        "analysed": analysed,
        "skipped": detection.buildings.len() - analysed,
        "slices": detection.buildings.iter().map(|b| b.slices.len()).sum::<usize>(),
        "boundary_points": detection.buildings.iter().map(|b| b.boundary.len()).sum::<usize>(),
        "missing_points": missing.len(),
        "r_missing": detection.r_missing(),
        "point_based": detection.buildings.iter().filter(|b| b.skipped.is_none() && b.strategy == skyground_core::missing::Strategy::PointBased).count(),
        "region_based": detection.buildings.iter().filter(|b| b.skipped.is_none() && b.strategy == skyground_core::missing::Strategy::RegionBased).count(),
        "target_points": targets.points.len(),
        "target_regions": targets.regions.len(),
        "dropped": dropped,
        "consolidation": consolidation,
        "footprints_used": used.len(),
        "density": detection.density,
        "detect_params": detection.params,
        "seconds": {"read": t1.duration_since(t0).as_secs_f64() - classify_s, "classify": classify_s, "detect": detect_s, "targets": targets_s},
        "outputs": {"dir": a.out, "classified": classified, "png": png, "field": field},
        "crs": super::info::crs_json(cloud.crs.as_ref()),
        "per_building": per_building,
    });
    if !a.json {
        eprintln!(
            "{} buildings ({analysed} analysed), {} missing points (R_missing {:.3}), {} target points and {} regions to explore; written to {} (detection.png, targets.geojson, completeness.geojson / .csv, missing.las, {})",
            detection.buildings.len(),
            missing.len(),
            detection.r_missing(),
            targets.points.len(),
            targets.regions.len(),
            a.out.display(),
            classified
                .file_name()
                .map_or_else(Default::default, |n| n.to_string_lossy()),
        );
    }
    if let Some(truth) = &producer {
        let check = producer_check(
            &cloud.xyz,
            truth,
            &detection.missing_xyz(),
            &targets.positions(),
            detection.outline_cell_m() as f32,
        );
        if !a.json && check.missing_points == 0 {
            eprintln!("against the producer's classes: no missing points to check");
        } else if !a.json {
            eprintln!(
                "against the producer's classes: {:.3} of {} missing points within {:.2} m in plan of a building point ({:.3} have one nearest in 3D); targets at most {:.1} m from one ({} beyond {TARGET_REACH_M} m)",
                check.missing_on_outline_share,
                check.missing_points,
                check.outline_reach_m,
                check.missing_on_building_share,
                check.target_building_max_m,
                check.targets_beyond_reach
            );
        }
        out["producer_check"] = json!(check);
    }
    if let Some(spec) = &a.gt {
        let scene_spec = gt_scene(spec)?;
        let scene = load_scene(&scene_spec).map_err(|e| err(format!("scene {scene_spec}: {e}")))?;
        let gt = sample_building_surfaces(&scene, 0.25);
        let aerial = building_points(&cloud, gt.origin);
        let moved = shift_missing(&detection.missing_points(), cloud.origin, gt.origin);
        let vegetation = vegetation_points(&cloud, gt.origin);
        let (score, breakdown) = evaluate_explained(&gt, &aerial, &moved, &vegetation);
        if !a.json {
            eprintln!(
                "detection vs ground truth ({scene_spec}): recall {:.3} ({} of {} truly missing 1 m wall cells), precision {:.3} ({} of {} missing points)",
                score.walls.recall,
                score.walls.found,
                score.walls.truly_missing,
                score.walls.precision,
                score.walls.correct_points,
                score.walls.missing_points
            );
        }
        out["gt"] = json!({"scene": scene_spec, "recall": score.walls.recall, "precision": score.walls.precision, "score": score, "breakdown": breakdown});
    }
    Ok(out)
}

/// The cloud's vegetation points (classes 3–5) in the frame at `origin`:
/// what the breakdown of `--gt` tells points near trees by.
fn vegetation_points(cloud: &Cloud, origin: [f64; 3]) -> Vec<[f32; 3]> {
    let shift = [0, 1, 2].map(|k| cloud.origin[k] - origin[k]);
    let Some(labels) = &cloud.label else {
        return Vec::new();
    };
    cloud
        .xyz
        .iter()
        .zip(labels)
        .filter(|(_, l)| matches!(**l, class::LOW_VEGETATION..=class::VEGETATION))
        .map(|(p, _)| [0, 1, 2].map(|k| (f64::from(p[k]) + shift[k]) as f32))
        .collect()
}

/// The two names `detect` gives the classified cloud.
const CLASSIFIED: [&str; 2] = ["classified.laz", "classified.las"];

/// Where `detect` writes the classified cloud in `dir`: compressed when every
/// input is LAZ, as the producer delivered it (a 10 M-point tile is 57 MB
/// instead of 307 MB). A file of the other name left by an earlier run is
/// removed, so `plan` never reads a stale cloud.
fn classified_path(dir: &Path, inputs: &[PathBuf]) -> Result<PathBuf, RuntimeError> {
    let laz = inputs
        .iter()
        .all(|f| f.extension().is_some_and(|e| e.eq_ignore_ascii_case("laz")));
    let (name, other) = if laz {
        (CLASSIFIED[0], CLASSIFIED[1])
    } else {
        (CLASSIFIED[1], CLASSIFIED[0])
    };
    let stale = dir.join(other);
    if stale.exists() {
        std::fs::remove_file(&stale).map_err(|e| err(format!("{}: {e}", stale.display())))?;
    }
    Ok(dir.join(name))
}

/// The classified cloud of a `detect` output directory (classified.laz or
/// classified.las).
pub fn find_classified(dir: &Path) -> Result<PathBuf, RuntimeError> {
    CLASSIFIED
        .iter()
        .map(|n| dir.join(n))
        .find(|p| p.is_file())
        .ok_or_else(|| {
            err(format!(
                "{}: no classified.laz or classified.las (a `skyground detect` output directory?)",
                dir.display()
            ))
        })
}
