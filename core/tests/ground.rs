//! Cloth Simulation Filter against ground truth: the producer's ground
//! class of Autzen, the simulated reference city (every point's class and
//! the true terrain are known), the CSF authors' sample, and small
//! hand-built clouds. Real files come from `../shared/data/real`
//! (`SKYGROUND_REAL_DATA` overrides; absent → `SKIPPED: ...`, test passes).

use std::path::PathBuf;

use skyground_core::cloud::{Cloud, class, read_cloud};
use skyground_core::ground::{CsfError, CsfParams, GroundSplit, csf};
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::metrics::GroundHeight;
use skyground_core::scene::{REFERENCE_SEED, reference_scene};

fn real(name: &str) -> Option<Cloud> {
    let dir = std::env::var_os("SKYGROUND_REAL_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/real"),
        PathBuf::from,
    );
    if !dir.is_dir() {
        eprintln!("SKIPPED: {} not found", dir.display());
        return None;
    }
    Some(read_cloud(&dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}")))
}

/// Agreement of `split` with the truth (`true` = ground), ISPRS style.
struct Errors {
    total: f64,
    type1: f64,
    type2: f64,
    kappa: f64,
}

fn errors(split: &GroundSplit, truth: &[bool]) -> Errors {
    let (mut gg, mut gn, mut ng, mut nn) = (0.0, 0.0, 0.0, 0.0);
    for (&t, &p) in truth.iter().zip(&split.is_ground) {
        match (t, p) {
            (true, true) => gg += 1.0,
            (true, false) => gn += 1.0,
            (false, true) => ng += 1.0,
            (false, false) => nn += 1.0,
        }
    }
    let n: f64 = gg + gn + ng + nn;
    let observed = (gg + nn) / n;
    let chance = ((gg + gn) * (gg + ng) + (ng + nn) * (gn + nn)) / (n * n);
    Errors {
        total: (gn + ng) / n,
        type1: gn / (gg + gn),
        type2: ng / (ng + nn),
        kappa: (observed - chance) / (1.0 - chance),
    }
}

fn print_errors(name: &str, e: &Errors, split: &GroundSplit) {
    println!(
        "{name}: total error {:.2} %, type I {:.2} %, type II {:.2} %, kappa {:.3}, {} steps",
        100.0 * e.total,
        100.0 * e.type1,
        100.0 * e.type2,
        e.kappa,
        split.iterations_run
    );
}

#[test]
fn autzen_matches_producer_ground_class() {
    let Some(cloud) = real("autzen_trim.las") else {
        return;
    };
    let labels = cloud.label.as_ref().unwrap();
    let truth: Vec<bool> = labels.iter().map(|&c| c == class::GROUND).collect();
    let split = csf(&cloud.xyz, &CsfParams::default()).unwrap();
    let e = errors(&split, &truth);
    print_errors("autzen_trim.las", &e, &split);
    assert!(e.total <= 0.05, "total error {:.2} %", 100.0 * e.total);
    assert!(e.kappa > 0.85, "kappa {:.3}", e.kappa);
}
