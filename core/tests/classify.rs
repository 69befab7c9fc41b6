//! Classification (DESIGN.md step 1) against ground truth: the shipped model
//! on the reference scene's airborne prior (a seed it was not trained on)
//! and on a real producer-classified file, a small training run, and typed
//! errors for bad input.
//!
//! Heights above ground come from the ground-labelled points
//! (`hag_from_ground_points`), standing in for the CSF ground model, and
//! `is_ground` is the reference ground label: these tests measure the
//! vegetation / building forest, not the ground filter.

use std::path::PathBuf;

use skyground_core::classify::{
    ClassReport, Classified, ClassifyError, Model, SceneClassifier, TrainParams, TrainingCloud,
    classify, echoes_of, hag_from_ground_points, simulated_cloud, train,
};
use skyground_core::cloud::class::{BUILDING, GROUND, VEGETATION};
use skyground_core::cloud::{Cloud, ColumnLength, read_cloud};
use skyground_core::features::{Echoes, FeatureError};
use skyground_core::forest::{ForestParams, RandomForest};
use skyground_core::ground::CsfParams;
use skyground_core::lidar::{AirborneConfig, FlightPattern};
use skyground_core::scene::REFERENCE_SEED;

mod common;
use common::real_file;

fn echo_input(c: &TrainingCloud) -> Option<Echoes<'_>> {
    c.echoes.as_ref().map(|(rn, nr)| Echoes {
        return_number: rn,
        number_of_returns: nr,
    })
}

fn shipped_model() -> Model {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../config/classifier_model.json.gz");
    Model::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn evaluate(
    xyz: &[[f32; 3]],
    label: &[u8],
    echoes: Option<Echoes<'_>>,
    model: &Model,
) -> ClassReport {
    let is_ground: Vec<bool> = label.iter().map(|&c| c == GROUND).collect();
    let hag = hag_from_ground_points(xyz, &is_ground).unwrap();
    let predicted = classify(xyz, &hag, &is_ground, echoes, model).unwrap();
    ClassReport::new(label, &predicted).unwrap()
}

#[test]
fn reference_prior_buildings_and_vegetation() {
    let model = shipped_model();
    assert!(
        !model
            .trained_on
            .contains(&format!("reference:{REFERENCE_SEED} "))
    );
    let cloud = simulated_cloud(REFERENCE_SEED, &AirborneConfig::default()).unwrap();
    let r = evaluate(&cloud.xyz, &cloud.label, echo_input(&cloud), &model);
    println!(
        "reference scene (seed {REFERENCE_SEED}), default survey, hag from ground truth:\n{}",
        r.table()
    );
    let b = r.class(BUILDING).unwrap().f1;
    let v = r.class(VEGETATION).unwrap().f1;
    assert!(b >= 0.97, "building F1 {b:.4}");
    assert!(v >= 0.90, "vegetation F1 {v:.4}");
}

#[test]
fn sample_c_buildings_with_the_shipped_model() {
    let Some(path) = real_file("sample_c.las") else {
        return;
    };
    let cloud = read_cloud(&path).unwrap();
    let label = cloud.label.clone().unwrap();
    assert_eq!(cloud.len(), 14_408);
    let r = evaluate(&cloud.xyz, &label, echoes_of(&cloud), &shipped_model());
    println!(
        "sample_c.las (producer ground labels as is_ground, hag from them):\n{}",
        r.table()
    );
    let b = r.class(BUILDING).unwrap().f1;
    assert!(b >= 0.90, "building F1 {b:.4}");
}

#[test]
fn a_small_training_run_generalises_to_another_city() {
    let sparse = AirborneConfig {
        pulse_rate_hz: 40_000.0,
        pattern: FlightPattern::AlongX,
        ..AirborneConfig::default()
    };
    let train_cloud = simulated_cloud(31, &sparse).unwrap();
    let params = TrainParams {
        per_class: 3_000,
        forest: ForestParams {
            trees: 12,
            ..ForestParams::default()
        },
        ..TrainParams::default()
    };
    let model = train(&[train_cloud], &params).unwrap();
    assert_eq!(model.classes, vec![GROUND, VEGETATION, BUILDING]);
    let test_cloud = simulated_cloud(32, &sparse).unwrap();
    let r = evaluate(
        &test_cloud.xyz,
        &test_cloud.label,
        echo_input(&test_cloud),
        &model,
    );
    println!(
        "trained on city 31, tested on city 32 at {:.0} pts/m²:\n{}",
        sparse.nominal_density(),
        r.table()
    );
    assert!(r.class(BUILDING).unwrap().f1 > 0.9);
    assert!(r.class(VEGETATION).unwrap().f1 > 0.75);
    // The same city without echoes (a photogrammetric or first-return
    // cloud) goes to the forest that learned without them; a model without
    // that forest (as older model files) falls back to the one that reads
    // echoes, which never saw a cloud without them.
    let bare = evaluate(&test_cloud.xyz, &test_cloud.label, None, &model);
    let echo_only = Model {
        forest_without_echoes: None,
        ..model.clone()
    };
    let fallback = evaluate(&test_cloud.xyz, &test_cloud.label, None, &echo_only);
    let f1 = |r: &ClassReport, c| r.class(c).map_or(0.0, |m| m.f1);
    println!(
        "city 32 without echoes: building F1 {:.4}, vegetation F1 {:.4}; \
         with the echo forest alone {:.4}, {:.4}",
        f1(&bare, BUILDING),
        f1(&bare, VEGETATION),
        f1(&fallback, BUILDING),
        f1(&fallback, VEGETATION)
    );
    assert!(model.forest_without_echoes.is_some());
    assert!(f1(&bare, BUILDING) > 0.9 && f1(&bare, VEGETATION) > 0.75);
    assert!(f1(&bare, VEGETATION) > f1(&fallback, VEGETATION));
    // A second forest that tells other classes apart is refused.
    let dims = skyground_core::features::FEATURE_NAMES.len();
    let odd = RandomForest::fit(
        &vec![0.5; 4 * dims],
        dims,
        &[GROUND, BUILDING, GROUND, BUILDING],
        &ForestParams {
            trees: 2,
            ..ForestParams::default()
        },
    )
    .unwrap();
    let mixed = Model {
        forest_without_echoes: Some(odd),
        ..model.clone()
    };
    assert!(matches!(mixed.check(), Err(ClassifyError::ForestsDisagree)));
    // Round trip through the model file, plain and gzipped.
    let dir = std::env::temp_dir();
    let id = std::process::id();
    let plain = dir.join(format!("skyground_model_{id}.json"));
    let gz = dir.join(format!("skyground_model_{id}.json.gz"));
    model.save(&plain).unwrap();
    model.save(&gz).unwrap();
    let (plain_bytes, gz_bytes) = (std::fs::read(&plain).unwrap(), std::fs::read(&gz).unwrap());
    assert_eq!(&gz_bytes[..2], &[0x1f, 0x8b], "a .gz model is gzip");
    assert!(
        gz_bytes.len() * 2 < plain_bytes.len(),
        "gzip shrinks the model"
    );
    assert_eq!(Model::load(&plain).unwrap(), model);
    assert_eq!(Model::load(&gz).unwrap(), model);
    // The format is read from the bytes, not the name.
    assert_eq!(Model::from_slice(&gz_bytes).unwrap(), model);
    assert_eq!(Model::from_slice(&plain_bytes).unwrap(), model);
    // A cut-off gzip file is a clear error.
    assert!(matches!(
        Model::from_slice(&gz_bytes[..gz_bytes.len() / 2]),
        Err(ClassifyError::File { .. })
    ));
    std::fs::remove_file(&plain).ok();
    std::fs::remove_file(&gz).ok();
}

#[test]
fn bad_input_gives_typed_errors() {
    let model = shipped_model();
    let xyz: Vec<[f32; 3]> = (0..50)
        .map(|i| [i as f32, (i * 7 % 11) as f32, 0.0])
        .collect();
    let hag = vec![0.0f32; 50];
    let ground = vec![false; 50];
    assert!(matches!(
        classify(&[], &[], &[], None, &model),
        Err(ClassifyError::Empty)
    ));
    assert!(matches!(
        classify(&xyz, &hag[..10], &ground, None, &model),
        Err(ClassifyError::LengthMismatch(ColumnLength {
            column: "hag",
            ..
        }))
    ));
    assert!(matches!(
        classify(&xyz, &hag, &ground[..49], None, &model),
        Err(ClassifyError::LengthMismatch(ColumnLength {
            column: "is_ground",
            ..
        }))
    ));
    let mut nan = xyz.clone();
    nan[5][2] = f32::NAN;
    assert!(matches!(
        classify(&nan, &hag, &ground, None, &model),
        Err(ClassifyError::Features(FeatureError::NonFinite {
            index: 5,
            ..
        }))
    ));
    let mut bad_hag = hag.clone();
    bad_hag[3] = f32::INFINITY;
    assert!(matches!(
        classify(&xyz, &bad_hag, &ground, None, &model),
        Err(ClassifyError::Features(FeatureError::NonFinite {
            what: "hag",
            index: 3
        }))
    ));
    assert!(matches!(
        hag_from_ground_points(&nan, &[true; 50]),
        Err(ClassifyError::NonFinite { index: 5 })
    ));
    // All ground: nothing for the forest to do.
    assert_eq!(
        classify(&xyz, &hag, &[true; 50], None, &model).unwrap(),
        vec![GROUND; 50]
    );
    assert!(matches!(
        ClassReport::new(&[1, 2], &[2]),
        Err(ClassifyError::LengthMismatch(_))
    ));
    let missing = PathBuf::from("/nonexistent/model.json");
    assert!(matches!(
        Model::load(&missing),
        Err(ClassifyError::File { .. })
    ));
}

/// Appends `points` of class `code` (single returns, no intensity) to `cloud`.
fn push_points(cloud: &mut Cloud, points: &[[f32; 3]], code: u8) {
    for &p in points {
        cloud.xyz.push(p);
        cloud.label.get_or_insert_with(Vec::new).push(code);
        for v in [&mut cloud.return_number, &mut cloud.number_of_returns]
            .into_iter()
            .flatten()
        {
            v.push(1);
        }
        if let Some(v) = &mut cloud.intensity {
            v.push(0.0);
        }
        if let Some(v) = &mut cloud.building {
            v.push(0);
        }
    }
}

/// A producer's noise stays out of the ground filter and the features: a
/// patch of returns 30 m under the street (multipath) would otherwise hold
/// the terrain down. Noise, water and civil structures keep their classes.
#[test]
fn the_producers_noise_water_and_bridges_stay_its_own() {
    let Some(path) = real_file("ahn3_delft_2.laz") else {
        return;
    };
    let clean = read_cloud(&path).unwrap();
    let n = clean.len();
    let classifier = SceneClassifier::new(CsfParams::default(), shipped_model()).unwrap();
    let before = classifier.classify_cloud(&clean).unwrap();
    let producer = clean.label.clone().unwrap();
    for code in [9, 26] {
        let kept = (0..n).filter(|&i| producer[i] == code);
        assert!(kept.clone().count() > 100, "class {code}");
        assert!(
            kept.into_iter().all(|i| before.labels[i] == code),
            "class {code}"
        );
    }

    // Six 8 × 8 m patches of low noise on producer ground, 30 m under it
    // and denser than the survey (the cloth rests on the point nearest each
    // particle, so sparse noise would rarely touch it),
    // and birds 150 m over the highest point.
    let ground: Vec<[f32; 3]> = (0..n)
        .filter(|&i| producer[i] == GROUND)
        .map(|i| clean.xyz[i])
        .collect();
    let centres: Vec<[f32; 3]> = (1..=6).map(|k| ground[k * ground.len() / 7]).collect();
    let patch = |c: [f32; 3]| -> Vec<[f32; 3]> {
        (0..16)
            .flat_map(|j| (0..16).map(move |i| (i, j)))
            .map(|(i, j)| {
                [
                    c[0] - 2.0 + 0.25 * i as f32,
                    c[1] - 2.0 + 0.25 * j as f32,
                    c[2] - 30.0,
                ]
            })
            .collect()
    };
    let low: Vec<[f32; 3]> = centres.iter().flat_map(|&c| patch(c)).collect();
    let top = clean.bounds().unwrap().1[2];
    let birds: Vec<[f32; 3]> = centres.iter().map(|c| [c[0], c[1], top + 150.0]).collect();
    let mut noisy = clean.clone();
    push_points(&mut noisy, &low, 7);
    push_points(&mut noisy, &birds, 18);
    let after = classifier.classify_cloud(&noisy).unwrap();
    assert_eq!(
        &after.labels[..n],
        &before.labels[..],
        "noise changed a class"
    );
    let added = noisy.label.as_ref().unwrap();
    assert_eq!(&after.labels[n..], &added[n..]);
    assert!(after.ground.is_ground[n..].iter().all(|&g| !g));
    assert!(
        after.ground.hag[n..n + low.len()]
            .iter()
            .all(|&h| h < -25.0)
    );
    assert!(after.ground.hag[n + low.len()..].iter().all(|&h| h > 100.0));

    // Unmarked, the same returns pull the terrain down under the patches.
    let mut unmarked = noisy.clone();
    if let Some(l) = &mut unmarked.label {
        l[n..].iter_mut().for_each(|c| *c = 1);
    }
    let pulled = classifier.classify_cloud(&unmarked).unwrap();
    let mut sunk = 0;
    for c in &centres {
        let z = |k: &Classified| k.ground.dtm.height_at(c[0], c[1]);
        assert!(
            (z(&after) - z(&before)).abs() < 1e-3,
            "{} vs {}",
            z(&after),
            z(&before)
        );
        sunk += usize::from(z(&pulled) < z(&before) - 20.0);
    }
    assert!(sunk >= 4, "{sunk} of 6 patches held the terrain down");
}
