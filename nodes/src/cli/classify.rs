//! `skyground classify` and `skyground train`: step 1 of the method offline.

use std::path::PathBuf;
use std::time::Instant;

use serde::Deserialize;
use skyground_core::classify::{
    ClassReport, GroundReport, SceneClassifier, TrainParams, default_training_set, train,
};
use skyground_core::cloud::{read_cloud, write_cloud};
use skyground_core::ground::CsfParams;

use crate::node::scene_classifier::load_model;
use crate::runtime::{RuntimeError, params::ParamSet};

/// Options of `skyground classify`.
#[derive(Debug, Clone, clap::Args)]
pub struct ClassifyArgs {
    /// The cloud to classify (LAS/LAZ/PLY). Its own labels, if any, are the reference.
    #[arg(long = "in")]
    pub input: PathBuf,
    /// Where to write the classified cloud (.las/.laz/.ply).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// A model file (default: the shipped config/classifier_model.json).
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// A params file overriding config/scene_classifier.yaml (its `csf` section).
    #[arg(long)]
    pub params_file: Option<PathBuf>,
    /// Print the result as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Options of `skyground train`.
#[derive(Debug, Clone, clap::Args)]
pub struct TrainArgs {
    /// Where to write the model.
    #[arg(long, default_value = "config/classifier_model.json")]
    pub out: PathBuf,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Deserialize)]
struct NodeParams {
    csf: CsfParams,
}

fn err(e: impl std::fmt::Display) -> RuntimeError {
    RuntimeError::Node(e.to_string())
}

fn csf_params(file: Option<&std::path::Path>) -> Result<CsfParams, RuntimeError> {
    let mut params = ParamSet::default();
    params.merge_yaml(
        crate::node::scene_classifier::SPEC.default_params,
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

/// Classifies a file; compares with its own labels when it has any.
pub fn run(a: &ClassifyArgs) -> Result<serde_json::Value, RuntimeError> {
    let csf = csf_params(a.params_file.as_deref())?;
    let model = load_model(
        &a.model
            .as_ref()
            .map(|m| m.display().to_string())
            .unwrap_or_default(),
    )?;
    let classifier = SceneClassifier::new(csf, model).map_err(err)?;
    let t0 = Instant::now();
    let mut cloud = read_cloud(&a.input).map_err(err)?;
    let read_s = t0.elapsed().as_secs_f64();
    let classified = classifier
        .classify(&cloud.xyz)
        .map_err(|e| err(format!("{}: {e}", a.input.display())))?;
    let truth = cloud.label.take().filter(|l| l.iter().any(|&c| c > 1));
    let mut out = serde_json::json!({
        "input": a.input,
        "points": cloud.len(),
        "classes": classified.counts(),
        "seconds": {"read": read_s, "csf": classified.seconds_csf, "features_and_forest": classified.seconds_classify},
        "model": classifier.model().trained_on,
        "density": classified.density,
        "csf": classified.csf,
    });
    if let Some(truth) = &truth {
        let report = ClassReport::new(truth, &classified.labels).map_err(err)?;
        let ground = GroundReport::new(truth, &classified.is_ground).map_err(err)?;
        if !a.json {
            eprintln!("{}", report.table());
            eprintln!(
                "ground vs non-ground: total error {:.2} %, type I {:.2} %, type II {:.2} %, kappa {:.3}",
                ground.total_error * 100.0,
                ground.type_i * 100.0,
                ground.type_ii * 100.0,
                ground.kappa
            );
        }
        out["report"] = serde_json::to_value(&report).map_err(err)?;
        out["ground"] = serde_json::to_value(&ground).map_err(err)?;
    }
    cloud.label = Some(classified.labels);
    if let Some(path) = &a.out {
        write_cloud(path, &cloud).map_err(err)?;
        out["output"] = serde_json::json!(path);
    }
    Ok(out)
}

/// Trains the default model on simulated scenes and writes it.
pub fn run_train(a: &TrainArgs) -> Result<serde_json::Value, RuntimeError> {
    let t0 = Instant::now();
    let set = default_training_set().map_err(err)?;
    let sim_s = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let model = train(&set, &TrainParams::default()).map_err(err)?;
    let train_s = t1.elapsed().as_secs_f64();
    model.save(&a.out).map_err(err)?;
    let bytes = std::fs::metadata(&a.out).map(|m| m.len()).unwrap_or(0);
    Ok(serde_json::json!({
        "out": a.out,
        "clouds": set.iter().map(|c| c.name.clone()).collect::<Vec<_>>(),
        "points": set.iter().map(|c| c.xyz.len()).sum::<usize>(),
        "seconds": {"simulate": sim_s, "train": train_s},
        "bytes": bytes,
    }))
}
