//! Classification speed: `cargo bench -p skyground-core --bench classify`.
//!
//! The reference scene's airborne prior, thinned to 1 M points; heights
//! above ground and ground flags from its labels (set up once, untimed).
//! Timed: features of every non-ground point plus the forest's votes
//! (`classify`), the features alone and the votes alone, with the shipped
//! model.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{Criterion, Throughput};
use skyground_core::classify::{
    Model, SceneClassifier, classify, hag_from_ground_points, simulated_cloud,
};
use skyground_core::cloud::class::GROUND;
use skyground_core::cloud::read_cloud;
use skyground_core::features::{Echoes, compute};
use skyground_core::ground::CsfParams;
use skyground_core::lidar::AirborneConfig;
use skyground_core::scene::REFERENCE_SEED;

const POINTS: usize = 1_000_000;

fn benches(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../config/classifier_model.json.gz");
    let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let full = simulated_cloud(REFERENCE_SEED, &AirborneConfig::default()).unwrap();
    let n = full.xyz.len();
    let keep: Vec<usize> = (0..POINTS.min(n)).map(|i| i * n / POINTS.min(n)).collect();
    let xyz: Vec<[f32; 3]> = keep.iter().map(|&i| full.xyz[i]).collect();
    let is_ground: Vec<bool> = keep.iter().map(|&i| full.label[i] == GROUND).collect();
    let hag = hag_from_ground_points(&xyz, &is_ground).unwrap();
    let (rn, nr) = full.echoes.clone().unwrap_or_default();
    let (rn, nr): (Vec<u8>, Vec<u8>) = keep
        .iter()
        .map(|&i| {
            (
                rn.get(i).copied().unwrap_or(0),
                nr.get(i).copied().unwrap_or(0),
            )
        })
        .unzip();
    let echoes = Some(Echoes {
        return_number: &rn,
        number_of_returns: &nr,
    });
    println!(
        "{} of {} points, {} not ground, {} threads",
        xyz.len(),
        n,
        is_ground.iter().filter(|g| !**g).count(),
        rayon::current_num_threads()
    );
    let mut g = c.benchmark_group("classify");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(30));
    g.throughput(Throughput::Elements(xyz.len() as u64));
    g.bench_function("classify_1M", |b| {
        b.iter(|| classify(black_box(&xyz), &hag, &is_ground, echoes, &model).map(|l| l.len()))
    });
    g.bench_function("features_all_1M", |b| {
        b.iter(|| compute(black_box(&xyz), &hag, echoes, &model.feature_params).map(|f| f.len()))
    });
    let features = compute(&xyz, &hag, echoes, &model.feature_params).unwrap();
    let forest = model.forest_for(echoes.is_some());
    g.bench_function("forest_votes_1M", |b| {
        b.iter(|| {
            forest
                .predict_proba(black_box(&features.data))
                .map(|v| v.len())
        })
    });
    g.finish();
    real_million(c);
}

/// 1 M real points: the two AHN3 Delft tiles (848,942 points, in one frame)
/// and IGN Montpellier's first points set beside them, through the whole
/// classifier (CSF, features, forest, smoothing) with the shipped model.
fn real_million(c: &mut Criterion) {
    let dir = std::env::var_os("SKYGROUND_REAL_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/real"),
        PathBuf::from,
    );
    let files = [
        "ahn3_delft_1.laz",
        "ahn3_delft_2.laz",
        "ign_montpellier_150x100m.laz",
    ];
    let mut clouds = Vec::new();
    for f in files {
        match read_cloud(&dir.join(f)) {
            Ok(cloud) => clouds.push(cloud),
            Err(e) => {
                println!("SKIPPED classify_real_1M: {f}: {e}");
                return;
            }
        }
    }
    let mut all = clouds[0].clone();
    for (k, cloud) in clouds.iter().enumerate().skip(1) {
        // AHN3 tiles share a CRS; Montpellier goes 500 m east of them.
        let shift: [f32; 3] = std::array::from_fn(|i| {
            let same_crs = (cloud.origin[i] - all.origin[i]) as f32;
            if k == 2 {
                [500.0, 0.0, 0.0][i]
            } else {
                same_crs
            }
        });
        let room = POINTS.saturating_sub(all.len());
        let rows: Vec<usize> = (0..cloud.len().min(room)).collect();
        let mut part = cloud.subset(&rows);
        part.xyz
            .iter_mut()
            .for_each(|p| (0..3).for_each(|i| p[i] += shift[i]));
        part.origin = all.origin;
        all.xyz.extend(part.xyz);
        for (a, b) in [
            (&mut all.return_number, part.return_number),
            (&mut all.number_of_returns, part.number_of_returns),
            (&mut all.label, part.label),
        ] {
            if let (Some(a), Some(b)) = (a.as_mut(), b) {
                a.extend(b);
            }
        }
    }
    all.intensity = None;
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../config/classifier_model.json.gz");
    let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let classifier =
        SceneClassifier::new(CsfParams::default(), model).unwrap_or_else(|e| panic!("{e}"));
    println!("{} real points", all.len());
    let mut g = c.benchmark_group("classify");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(60));
    g.throughput(Throughput::Elements(all.len() as u64));
    g.bench_function("classify_real_1M", |b| {
        b.iter(|| {
            classifier
                .classify_cloud(black_box(&all))
                .map(|c| c.labels.len())
        })
    });
    g.finish();
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    benches(&mut c);
    c.final_summary();
}
