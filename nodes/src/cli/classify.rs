//! `skyground classify` and `skyground train`: step 1 of the method offline.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Deserialize;
use skyground_core::classify::{
    ClassReport, DEFAULT_DENSITIES, FileRole, GroundReport, SceneClassifier, TrainParams,
    default_training_set, disputes, echoes_of, file_training_clouds, is_scored, label_coherence,
    shapes_by_pairing, train,
};
use skyground_core::cloud::class::{self, BUILDING, GROUND, VEGETATION};
use skyground_core::cloud::las::LasError;
use skyground_core::cloud::{Cloud, CloudIoError, read_cloud, relabel_files, write_cloud};
use skyground_core::ground::CsfParams;
use skyground_core::prior::{same_crs, with_buffer};

use super::err;

use crate::runtime::model::load_model_file;
use crate::runtime::{RuntimeError, params::ParamSet};

/// Neighbours whose majority the producer's labels are checked against.
const COHERENCE_K: [usize; 2] = [4, 16];

/// Options of `skyground classify`.
#[derive(Debug, Clone, clap::Args)]
pub struct ClassifyArgs {
    /// The cloud to classify (LAS/LAZ/PLY); several files (tiles of one
    /// survey, one CRS) are classified as one cloud, each tile seeing its
    /// neighbours across the seam. Its own labels, if any, are the reference
    /// (scored on points whose label is 2–6).
    #[arg(long = "in", num_args = 1.., required = true)]
    pub inputs: Vec<PathBuf>,
    /// Where to write the classified cloud (.las/.laz/.ply).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Classify each --in file as a tile of its own, with the points of its
    /// neighbours within `--buffer` around it, and write it to this
    /// directory under its own name (as tiled surveys are processed: one
    /// tile in memory with its neighbours' edges, not the whole survey).
    #[arg(long, conflicts_with = "out")]
    pub out_dir: Option<PathBuf>,
    /// With --out-dir: how far (metres, in plan) beyond a tile's edge its
    /// neighbours' points are classified with it (not written with it).
    #[arg(long, default_value_t = 30.0)]
    pub buffer: f32,
    /// A model file (default: the shipped config/classifier_model.json.gz).
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// A params file overriding config/scene_classifier.yaml (its `csf` section).
    #[arg(long)]
    pub params_file: Option<PathBuf>,
    /// Print the result as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub units: super::units::UnitsArg,
}

/// Options of `skyground train`.
#[derive(Debug, Clone, clap::Args)]
pub struct TrainArgs {
    /// Where to write the model.
    #[arg(long, default_value = "config/classifier_model.json.gz")]
    pub out: PathBuf,
    /// Labelled clouds to learn from (LAS/LAZ/PLY with the producer's
    /// classes: 2 ground, 3/4/5 vegetation, 6 building; others ignored).
    /// The model records their names: never report accuracy on them.
    #[arg(long = "in", num_args = 1..)]
    pub inputs: Vec<PathBuf>,
    /// Clouds whose unclassified points (LAS 1) are learned as vegetation
    /// (with their classes 2–6 as --in files do): forests without
    /// buildings, or surveys such as AHN3 whose class 1 holds the trees with
    /// everything else that is neither ground nor building. Named in the
    /// model like --in files.
    #[arg(long = "vegetation-in", num_args = 1..)]
    pub vegetation_inputs: Vec<PathBuf>,
    /// Leave out the simulated reference-city surveys.
    #[arg(long)]
    pub no_sim: bool,
    /// Each --in file is also learned thinned to these shares of its points
    /// (pulses kept at random), so the model sees sparser surveys too.
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULT_DENSITIES)]
    pub densities: Vec<f64>,
    /// Samples drawn per class from each cloud.
    #[arg(long, default_value_t = 10_000)]
    pub per_class: usize,
    /// A params file overriding config/scene_classifier.yaml (its `csf`
    /// section: the ground filter that gives real clouds their heights).
    #[arg(long)]
    pub params_file: Option<PathBuf>,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Deserialize)]
struct NodeParams {
    csf: CsfParams,
}

fn csf_params(file: Option<&std::path::Path>) -> Result<CsfParams, RuntimeError> {
    let mut params = ParamSet::default();
    params.merge_yaml(
        crate::runtime::specs::SCENE_CLASSIFIER.default_params,
        "scene_classifier",
        "config/scene_classifier.yaml",
    )?;
    if let Some(f) = file {
        params.merge_file(f, "scene_classifier")?;
    }
    // Only the CSF section matters offline; the node's other keys are ignored.
    let v: serde_json::Value = params.parse("scene_classifier")?;
    let p: NodeParams = serde_json::from_value(serde_json::json!({ "csf": v.get("csf") }))
        .map_err(|e| err(format!("csf params: {e}")))?;
    Ok(p.csf)
}

/// Classifies a file (or tiles as one cloud, or tile by tile with
/// `--out-dir`); compares with its own labels when it has any.
pub fn run(a: &ClassifyArgs) -> Result<serde_json::Value, RuntimeError> {
    classify_files(a).map_err(|e| super::about(&a.inputs, e))
}

fn classify_files(a: &ClassifyArgs) -> Result<serde_json::Value, RuntimeError> {
    let csf = csf_params(a.params_file.as_deref())?;
    let model = load_model_file(a.model.as_deref())?;
    let classifier = SceneClassifier::new(csf, model).map_err(err)?;
    if let Some(dir) = &a.out_dir {
        return by_tile(a, &classifier, dir);
    }
    let t0 = Instant::now();
    let cloud = a.units.read_tiles(&a.inputs)?;
    let read_s = t0.elapsed().as_secs_f64();
    let job = Job {
        files: &a.inputs,
        own: cloud.len(),
        out: a.out.as_deref(),
        read_s,
    };
    classify_one(&classifier, cloud, &job, a.json)
}

/// One cloud to classify: the files it came from, how many of its points
/// are its own (the rest a buffer from neighbouring tiles), where it goes.
struct Job<'a> {
    files: &'a [PathBuf],
    own: usize,
    out: Option<&'a Path>,
    read_s: f64,
}

/// Classifies `cloud`, scores and writes its first `job.own` points.
fn classify_one(
    classifier: &SceneClassifier,
    cloud: Cloud,
    job: &Job,
    json: bool,
) -> Result<serde_json::Value, RuntimeError> {
    let input = super::units::describe(job.files);
    let mut classified = classifier
        .classify_cloud(&cloud)
        .map_err(|e| err(format!("{input}: {e}")))?;
    let buffer_points = cloud.len() - job.own;
    let mut cloud = match buffer_points {
        0 => cloud,
        _ => {
            let own: Vec<usize> = (0..job.own).collect();
            classified.labels.truncate(job.own);
            classified.ground.is_ground.truncate(job.own);
            classified.ground.hag.truncate(job.own);
            cloud.subset(&own)
        }
    };
    let truth = cloud.label.take().filter(|l| l.iter().any(|&c| c > 1));
    let counts = classified.counts();
    let building = counts.get("building").copied().unwrap_or(0);
    let names: Vec<String> = job
        .files
        .iter()
        .filter_map(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .filter(|n| classifier.model().training_files.contains(n))
        .collect();
    let seen = !names.is_empty();
    let mut out = serde_json::json!({
        "input": input,
        "inputs": job.files,
        "points": cloud.len(),
        "buffer_points": buffer_points,
        "classes": counts,
        "building_share": building as f64 / cloud.len().max(1) as f64,
        "echoes": cloud.echoes().is_some(),
        "echo_note": classifier.echo_note(&cloud),
        "seconds": {"read": job.read_s, "csf": classified.seconds_csf, "features_and_forest": classified.seconds_classify},
        "model": classifier.model().trained_on,
        "trained_on_this_file": seen,
        "density": classified.ground.density,
        "csf": classified.ground.params,
        // The check as applied: its cell and link follow the spacing.
        "roof_check": classifier.model().roof_check.for_spacing(classified.ground.density.spacing_m),
        "raised_ground": classified.ground.raised,
        "at_grade": classified.at_grade,
    });
    // Water, bridges, wires, noise and producers' own codes stay theirs
    // (noise also stays out of the ground filter and the features).
    let mut kept = std::collections::BTreeMap::<u8, usize>::new();
    for &c in truth.iter().flatten() {
        if !class::replaced_by_classifier(c) {
            *kept.entry(c).or_default() += 1;
        }
    }
    if !kept.is_empty() && !json {
        let list: Vec<String> = kept.iter().map(|(c, n)| format!("{c}: {n}")).collect();
        eprintln!(
            "kept the producer's classes (water, bridges, wires, noise, its own codes; noise left out of the ground filter and features): {}",
            list.join(", ")
        );
    }
    out["producer_classes_kept"] = serde_json::json!(kept);
    for m in classified.messages().filter(|_| !json) {
        eprintln!("{m}");
    }
    if let Some(m) = classifier.echo_note(&cloud).filter(|_| !json) {
        eprintln!("{m}");
    }
    if seen {
        eprintln!(
            "note: the model was trained on {}: the figures below are not an accuracy claim",
            names.join(", ")
        );
    }
    if let Some(truth) = &truth {
        // Producers' classes outside 2–6 (unclassified, water, wires, noise)
        // say nothing about ground, vegetation or building: left out.
        let scored: Vec<usize> = (0..truth.len()).filter(|&i| is_scored(truth[i])).collect();
        let pick = |v: &[u8]| scored.iter().map(|&i| v[i]).collect::<Vec<u8>>();
        let t = pick(truth);
        let report = ClassReport::new(&t, &pick(&classified.labels)).map_err(err)?;
        // Over every point: the report picks its own scope (classes 2–6, or
        // the producer's ground alone when it names no vegetation or building).
        // None when the producer names no ground among its classes.
        let ground = GroundReport::new(truth, &classified.ground.is_ground).ok();
        if !json {
            eprintln!("{input}:\n{}", report.table());
            if let Some(g) = &ground {
                eprintln!("{}", g.line());
            }
        }
        // The producer's labels against their own neighbours': where they
        // change from point to point, no classifier that looks at
        // neighbourhoods can follow them (k = 4, and 16 as our smoothing).
        let started = Instant::now();
        let coherence = label_coherence(&cloud.xyz, truth, &COHERENCE_K).map_err(err)?;
        out["seconds"]["label_coherence"] = serde_json::json!(started.elapsed().as_secs_f64());
        if !json {
            for c in &coherence {
                let f1s: Vec<String> = [
                    (BUILDING, "building"),
                    (VEGETATION, "vegetation"),
                    (GROUND, "ground"),
                ]
                .iter()
                .filter_map(|&(class, name)| {
                    let m = c.report.class(class).filter(|m| m.support > 0)?;
                    Some(format!("{name} {:.3}", m.f1))
                })
                .collect();
                eprintln!(
                    "the producer's labels against the majority of their {} nearest scored neighbours' (over {} points), F1: {}",
                    c.k,
                    c.sampled,
                    f1s.join(", ")
                );
            }
        }
        out["label_coherence"] = serde_json::to_value(&coherence).map_err(err)?;
        // Where the producer and we part, which side the points resemble.
        let started = Instant::now();
        let shapes = shapes_by_pairing(
            &cloud.xyz,
            &classified.ground.hag,
            echoes_of(&cloud),
            truth,
            &classified.labels,
            &classifier.model().feature_params,
        )
        .map_err(err)?;
        out["seconds"]["shapes_by_pairing"] = serde_json::json!(started.elapsed().as_secs_f64());
        if !json && !shapes.is_empty() {
            eprintln!(
                "what the points look like, by the producer's class and ours (median planarity over 1.5 m, share from pulses with several returns, median height over the ground, share standing over 2 m above a roof both call building within 1 m):\n{}",
                disputes::table(&shapes)
            );
        }
        out["shapes_by_pairing"] = serde_json::to_value(&shapes).map_err(err)?;
        out["scored_points"] = serde_json::json!(scored.len());
        out["report"] = serde_json::to_value(&report).map_err(err)?;
        out["ground"] = serde_json::to_value(&ground).map_err(err)?;
    }
    if let Some(path) = job.out {
        cloud.label = Some(classified.labels);
        let kept = write_classified(job.files, path, &cloud)?;
        out["output"] = serde_json::json!(path);
        out["fields_kept"] = serde_json::json!(kept);
    }
    Ok(out)
}

/// Writes `cloud` (read from `files`, labelled) to `path`: the producer's
/// points with its classes, GPS time, colour, flight line and the rest kept,
/// as after a PDAL or LAStools classifier; through the cloud alone
/// (positions, intensity, returns, classes) for PLY or for tiles of
/// different point formats. True when every field was kept.
pub fn write_classified(
    files: &[PathBuf],
    path: &Path,
    cloud: &Cloud,
) -> Result<bool, RuntimeError> {
    let kept = match relabel_files(files, path, cloud) {
        Ok(kept) => kept,
        Err(CloudIoError::Las {
            source: e @ LasError::SourceFormat { .. },
            ..
        }) => {
            eprintln!(
                "note: {e}; {} gets positions, intensity, returns and classes only",
                path.display()
            );
            false
        }
        Err(e) => return Err(err(e)),
    };
    if !kept {
        write_cloud(path, cloud).map_err(err)?;
    }
    Ok(kept)
}

/// `--out-dir`: each tile classified with its neighbours' points within
/// `--buffer` of its edge, and written under its own name.
fn by_tile(
    a: &ClassifyArgs,
    classifier: &SceneClassifier,
    dir: &Path,
) -> Result<serde_json::Value, RuntimeError> {
    std::fs::create_dir_all(dir).map_err(|e| err(format!("{}: {e}", dir.display())))?;
    let here = |p: &Path| std::fs::canonicalize(p).ok();
    for p in &a.inputs {
        let parent = p.parent().map(|d| {
            if d.as_os_str().is_empty() {
                Path::new(".")
            } else {
                d
            }
        });
        if parent.and_then(here).is_some_and(|d| Some(d) == here(dir)) {
            return Err(err(format!(
                "--out-dir {} holds the input {}: writing there would overwrite it",
                dir.display(),
                p.display()
            )));
        }
    }
    // First pass, headers only: every tile's extent (metres, absolute) and
    // one CRS for all.
    let mut extents = Vec::with_capacity(a.inputs.len());
    let mut first: Option<(String, Cloud)> = None;
    for p in &a.inputs {
        let c = a.units.read_bounds(p)?;
        let name = p.display().to_string();
        let (lo, hi) = c
            .bounds()
            .ok_or_else(|| err(format!("{name}: holds no points")))?;
        let abs = |v: [f32; 3]| [0, 1].map(|k| c.origin[k] + f64::from(v[k]));
        extents.push((abs(lo), abs(hi)));
        match &first {
            None => first = Some((name, c)),
            Some((f, fc)) => same_crs((f, fc), (&name, &c)).map_err(err)?,
        }
    }
    let b = f64::from(a.buffer.max(0.0));
    let near = |i: usize, j: usize| {
        let ((lo, hi), (olo, ohi)) = (extents[i], extents[j]);
        (0..2).all(|k| olo[k] <= hi[k] + b && ohi[k] >= lo[k] - b)
    };
    let mut tiles = Vec::with_capacity(a.inputs.len());
    for (i, p) in a.inputs.iter().enumerate() {
        let t0 = Instant::now();
        let tile = (p.display().to_string(), a.units.read(p)?);
        let mut neighbours = Vec::new();
        for (j, q) in a.inputs.iter().enumerate() {
            if j != i && near(i, j) {
                neighbours.push((q.display().to_string(), a.units.read(q)?));
            }
        }
        let cloud = with_buffer(&tile, &neighbours, a.buffer.max(0.0)).map_err(err)?;
        drop(neighbours);
        let name = p
            .file_name()
            .ok_or_else(|| err(format!("{}: not a file name", p.display())))?;
        let out = dir.join(name);
        let job = Job {
            files: std::slice::from_ref(p),
            own: tile.1.len(),
            out: Some(&out),
            read_s: t0.elapsed().as_secs_f64(),
        };
        drop(tile);
        tiles.push(classify_one(classifier, cloud, &job, a.json)?);
    }
    Ok(serde_json::json!({
        "out_dir": dir,
        "buffer_m": a.buffer,
        "tiles": tiles,
    }))
}

/// Trains a model on labelled files and/or simulated scenes and writes it.
pub fn run_train(a: &TrainArgs) -> Result<serde_json::Value, RuntimeError> {
    let t0 = Instant::now();
    let mut set = if a.no_sim {
        Vec::new()
    } else {
        default_training_set().map_err(err)?
    };
    let sim_s = t0.elapsed().as_secs_f64();
    let csf = csf_params(a.params_file.as_deref())?;
    let inputs = a.inputs.iter().map(|p| (p, FileRole::Labelled));
    for (path, role) in inputs.chain(a.vegetation_inputs.iter().map(|p| (p, FileRole::Forest))) {
        let cloud = read_cloud(path).map_err(err)?;
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        set.extend(file_training_clouds(&name, cloud, role, &a.densities, &csf).map_err(err)?);
    }
    if set.is_empty() {
        return Err(err("nothing to train on: give --in FILE or drop --no-sim"));
    }
    let t1 = Instant::now();
    let params = TrainParams {
        per_class: a.per_class,
        ..TrainParams::default()
    };
    let model = train(&set, &params).map_err(err)?;
    let train_s = t1.elapsed().as_secs_f64();
    model.save(&a.out).map_err(err)?;
    let bytes = std::fs::metadata(&a.out).map(|m| m.len()).unwrap_or(0);
    Ok(serde_json::json!({
        "out": a.out,
        "clouds": set.iter().map(|c| c.name.clone()).collect::<Vec<_>>(),
        "trained_on": model.trained_on,
        "points": set.iter().map(|c| c.xyz.len()).sum::<usize>(),
        "seconds": {"simulate": sim_s, "train": train_s},
        "bytes": bytes,
    }))
}
