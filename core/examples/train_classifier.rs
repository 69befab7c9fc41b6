//! Trains the shipped classifier on simulated scenes and writes it:
//! `cargo run -p skyground-core --release --example train_classifier -- config/classifier_model.json`

use std::path::PathBuf;
use std::time::Instant;

use skyground_core::classify::{TrainParams, default_training_set, train};
use skyground_core::features::FEATURE_NAMES;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "config/classifier_model.json".into()),
    );
    let t0 = Instant::now();
    let clouds = default_training_set()?;
    let simulated = t0.elapsed().as_secs_f64();
    for c in &clouds {
        println!("{}: {} points", c.name, c.xyz.len());
    }
    let t1 = Instant::now();
    let model = train(&clouds, &TrainParams::default())?;
    let trained = t1.elapsed().as_secs_f64();
    model.save(&out)?;
    let size = std::fs::metadata(&out)?.len();
    println!(
        "simulation {simulated:.1} s, features + forest {trained:.1} s; {} trees, {} nodes; {} ({:.2} MB)",
        model.forest.tree_count(),
        model.forest.node_count(),
        out.display(),
        size as f64 / 1e6
    );
    println!("trained on {}", model.trained_on);
    let mut imp: Vec<(f32, &str)> = model
        .forest
        .importances()
        .iter()
        .copied()
        .zip(FEATURE_NAMES)
        .collect();
    imp.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (v, n) in imp {
        println!("  {n:<16} {v:.3}");
    }
    Ok(())
}
