//! Training data from simulated airborne scans, and training itself.
//!
//! Every simulated point knows its class (the scene object it hit), so the
//! reference scene's other seeds, scanned at several densities, angles and
//! noise levels, make a labelled training set without any real data; the
//! reference seed itself is left out for evaluation.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::error::ClassifyError;
use super::hag::hag_from_ground_points;
use super::model::Model;
use crate::cloud::class::{BUILDING, GROUND, VEGETATION, fold};
use crate::cloud::{Cloud, ColumnLength};
use crate::features::{Echoes, FEATURE_NAMES, FeatureParams, compute_subset};
use crate::forest::{ForestParams, RandomForest};
use crate::ground::{CsfParams, csf};
use crate::lidar::{AirborneConfig, Caster, FlightPattern, airborne_scan};
use crate::params::Checks;
use crate::scene::reference_scene;

/// One labelled cloud to learn from.
#[derive(Debug, Clone)]
pub struct TrainingCloud {
    /// Where it came from (goes into `Model::trained_on`).
    pub name: String,
    /// Points.
    pub xyz: Vec<[f32; 3]>,
    /// Height above ground per point, metres.
    pub hag: Vec<f32>,
    /// Reference LAS class per point (folded by `train`).
    pub label: Vec<u8>,
    /// Return number and number of returns per point, when known.
    pub echoes: Option<(Vec<u8>, Vec<u8>)>,
    /// Points that may be sampled (the ones the ground filter leaves to
    /// the forest); `None`: all.
    pub candidates: Option<Vec<bool>>,
}

impl TrainingCloud {
    /// The echo columns as feature input.
    fn echo_input(&self) -> Option<Echoes<'_>> {
        self.echoes.as_ref().map(|(rn, nr)| Echoes {
            return_number: rn,
            number_of_returns: nr,
        })
    }
}

/// How to sample and train.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrainParams {
    /// Neighbourhood sizes.
    pub features: FeatureParams,
    /// Forest hyper-parameters.
    pub forest: ForestParams,
    /// Samples drawn per class from each cloud (fewer if it has fewer), so
    /// every class and every density weighs alike.
    pub per_class: usize,
    /// Seed of the sampling.
    pub seed: u64,
    /// Also train the forest for clouds without echoes, on every cloud's
    /// samples with their echoes hidden.
    pub without_echoes: bool,
}

impl Default for TrainParams {
    fn default() -> Self {
        Self {
            features: FeatureParams::default(),
            forest: ForestParams::default(),
            per_class: 10_000,
            seed: 11,
            without_echoes: true,
        }
    }
}

impl TrainParams {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ClassifyError> {
        self.features.validate()?;
        self.forest.validate()?;
        Checks("training").that(self.per_class > 0, "per_class", 0, "must be ≥ 1")?;
        Ok(())
    }
}

/// The shares of its pulses each labelled file is also learned at, by
/// default (`skyground train --densities`).
pub const DEFAULT_DENSITIES: [f64; 3] = [1.0, 0.35, 0.12];

/// Classes the forest learns.
const CLASSES: [u8; 3] = [GROUND, VEGETATION, BUILDING];

/// Trains a model on balanced samples of `clouds`.
pub fn train(clouds: &[TrainingCloud], params: &TrainParams) -> Result<Model, ClassifyError> {
    params.validate()?;
    let mut x = Vec::new();
    let mut y = Vec::new();
    // The same rows with the echo columns hidden, for the echo-free forest.
    let mut x_bare = Vec::new();
    for (ci, c) in clouds.iter().enumerate() {
        ColumnLength::check("training labels", c.xyz.len(), c.label.len())?;
        let rows = balanced_rows(
            &c.label,
            c.candidates.as_deref(),
            params.per_class,
            params.seed ^ ci as u64,
        );
        let f = compute_subset(&c.xyz, &c.hag, c.echo_input(), &rows, &params.features)?;
        x.extend_from_slice(&f.data);
        y.extend(rows.iter().map(|&r| fold(c.label[r])));
        if params.without_echoes {
            let bare = match c.echo_input() {
                Some(_) => compute_subset(&c.xyz, &c.hag, None, &rows, &params.features)?.data,
                None => f.data,
            };
            x_bare.extend_from_slice(&bare);
        }
    }
    for class in CLASSES {
        if !y.contains(&class) {
            return Err(ClassifyError::MissingClass { class });
        }
    }
    let forest = RandomForest::fit(&x, FEATURE_NAMES.len(), &y, &params.forest)?;
    let forest_without_echoes = params
        .without_echoes
        .then(|| RandomForest::fit(&x_bare, FEATURE_NAMES.len(), &y, &params.forest))
        .transpose()?;
    let names: Vec<&str> = clouds.iter().map(|c| c.name.as_str()).collect();
    Ok(Model {
        feature_params: params.features.clone(),
        feature_names: FEATURE_NAMES.iter().map(|s| s.to_string()).collect(),
        classes: forest.classes().to_vec(),
        forest,
        forest_without_echoes,
        trained_on: format!("{} samples from {}", y.len(), names.join(", ")),
        training_files: names.iter().map(|s| s.to_string()).collect(),
        smoothing: Default::default(),
        roof_check: Default::default(),
    })
}

/// Up to `per_class` rows of each learned class among the `candidates`,
/// drawn without replacement.
fn balanced_rows(
    label: &[u8],
    candidates: Option<&[bool]>,
    per_class: usize,
    seed: u64,
) -> Vec<usize> {
    let mut out = Vec::new();
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let allowed = |i: usize| candidates.is_none_or(|c| c.get(i).copied().unwrap_or(false));
    for class in CLASSES {
        let mut rows: Vec<usize> = (0..label.len())
            .filter(|&i| fold(label[i]) == class && allowed(i))
            .collect();
        let take = per_class.min(rows.len());
        for t in 0..take {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let pick = t + (state % (rows.len() - t) as u64) as usize;
            rows.swap(t, pick);
        }
        rows.truncate(take);
        out.extend(rows);
    }
    out.sort_unstable();
    out
}

/// The simulated surveys of the default training set: (scene seed, survey),
/// from ~1.5 to ~46 pts/m², nadir and oblique, range noise 3–8 cm. None
/// uses `REFERENCE_SEED`.
pub fn training_surveys() -> Vec<(u64, AirborneConfig)> {
    let d = AirborneConfig::default();
    vec![
        (1, d.clone()),
        (
            2,
            AirborneConfig {
                pulse_rate_hz: 60_000.0,
                pattern: FlightPattern::AlongX,
                seed: 2,
                ..d.clone()
            },
        ),
        (
            3,
            AirborneConfig {
                pulse_rate_hz: 20_000.0,
                oblique_deg: None,
                range_noise_sigma: 0.05,
                seed: 3,
                ..d.clone()
            },
        ),
        (
            4,
            AirborneConfig {
                pulse_rate_hz: 15_000.0,
                altitude_m: 400.0,
                pattern: FlightPattern::AlongY,
                oblique_deg: Some(15.0),
                seed: 4,
                ..d.clone()
            },
        ),
        (
            5,
            AirborneConfig {
                pulse_rate_hz: 100_000.0,
                oblique_deg: Some(35.0),
                range_noise_sigma: 0.08,
                seed: 5,
                ..d.clone()
            },
        ),
        (
            6,
            AirborneConfig {
                pulse_rate_hz: 30_000.0,
                altitude_m: 250.0,
                pattern: FlightPattern::AlongX,
                oblique_deg: None,
                seed: 6,
                ..d
            },
        ),
    ]
}

/// One simulated airborne scan of the reference city `seed`, with heights
/// above ground from its ground-labelled points (the stand-in for CSF).
pub fn simulated_cloud(seed: u64, survey: &AirborneConfig) -> Result<TrainingCloud, ClassifyError> {
    let scene = reference_scene(seed);
    let caster = Caster::new(&scene).map_err(|e| ClassifyError::Simulation(e.to_string()))?;
    let cloud =
        airborne_scan(&caster, survey).map_err(|e| ClassifyError::Simulation(e.to_string()))?;
    let label = cloud
        .label
        .ok_or_else(|| ClassifyError::Simulation("scan has no labels".into()))?;
    let is_ground: Vec<bool> = label.iter().map(|&c| c == GROUND).collect();
    let hag = hag_from_ground_points(&cloud.xyz, &is_ground)?;
    let echoes = cloud.return_number.zip(cloud.number_of_returns);
    Ok(TrainingCloud {
        name: format!("reference:{seed} @ {:.0} pts/m²", survey.nominal_density()),
        xyz: cloud.xyz,
        hag,
        label,
        echoes,
        candidates: None,
    })
}

/// A cloud labelled by its producer (LAS classes 2–6 are learned, the rest
/// ignored), with heights above the ground that `csf` finds in it, exactly
/// as [`super::SceneClassifier`] will see such a cloud. Only the points the
/// filter leaves to the forest are sampled.
pub fn labelled_cloud(
    name: &str,
    cloud: Cloud,
    csf_params: &CsfParams,
) -> Result<TrainingCloud, ClassifyError> {
    let label = cloud.label.clone().ok_or_else(|| ClassifyError::File {
        path: name.to_owned(),
        message: "has no classification to learn from".into(),
    })?;
    if !label
        .iter()
        .any(|&c| fold(c) == BUILDING || fold(c) == VEGETATION)
    {
        return Err(ClassifyError::File {
            path: name.to_owned(),
            message: "has no building or vegetation points (classes 3–6) to learn from".into(),
        });
    }
    let split = csf(&cloud.xyz, csf_params)?;
    let echoes = cloud.echoes().map(|(rn, nr)| (rn.to_vec(), nr.to_vec()));
    Ok(TrainingCloud {
        name: name.to_owned(),
        candidates: Some(split.is_ground.iter().map(|g| !g).collect()),
        xyz: cloud.xyz,
        hag: split.hag,
        label,
        echoes,
    })
}

/// How a labelled file is learned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileRole {
    /// The producer's classes 2–6 are learned.
    Labelled,
    /// A survey whose producer left the trees unclassified (a forest, or
    /// AHN3, whose class 1 is everything neither ground nor building): its
    /// class 1 is learned as vegetation, its classes 2–6 as given.
    Forest,
}

/// The training clouds of one labelled file: the file itself and a thinned
/// copy at every share in `densities` (pulses kept at random, so the model
/// sees sparser surveys of the same place), named after `name`.
pub fn file_training_clouds(
    name: &str,
    mut cloud: Cloud,
    role: FileRole,
    densities: &[f64],
    csf_params: &CsfParams,
) -> Result<Vec<TrainingCloud>, ClassifyError> {
    if role == FileRole::Forest
        && let Some(l) = cloud.label.as_mut()
    {
        l.iter_mut()
            .filter(|c| **c == 1)
            .for_each(|c| *c = VEGETATION);
    }
    // Refused before any ground filtering is spent on the good ones.
    if let Some(keep) = densities.iter().find(|k| !(**k > 0.0 && **k <= 1.0)) {
        return Err(ClassifyError::File {
            path: name.to_owned(),
            message: format!("density share {keep} is not in (0, 1]"),
        });
    }
    densities
        .iter()
        .enumerate()
        .map(|(k, &keep)| {
            let rows = pulse_sample(&cloud, keep, k as u64);
            let tag = if keep < 1.0 {
                format!("{name} (thinned to {:.0} %)", keep * 100.0)
            } else {
                name.to_owned()
            };
            labelled_cloud(&tag, cloud.subset(&rows), csf_params)
        })
        .collect()
}

/// Rows of a random share `keep` of the cloud's pulses: a point goes with
/// the others of its pulse (consecutive points whose return numbers count
/// up), as a sparser survey would have recorded them.
pub fn pulse_sample(cloud: &Cloud, keep: f64, seed: u64) -> Vec<usize> {
    if keep >= 1.0 {
        return (0..cloud.len()).collect();
    }
    let rn = cloud.return_number.as_deref().unwrap_or_default();
    let mut state = (seed + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let mut take = false;
    (0..cloud.len())
        .filter(|&i| {
            if rn.get(i).copied().unwrap_or(1) <= 1 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                take = (state >> 11) as f64 / (1u64 << 53) as f64 <= keep;
            }
            take
        })
        .collect()
}

/// The default training set: [`simulated_cloud`] of every [`training_surveys`] entry.
pub fn default_training_set() -> Result<Vec<TrainingCloud>, ClassifyError> {
    training_surveys()
        .par_iter()
        .map(|(seed, survey)| simulated_cloud(*seed, survey))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::class::GROUND;

    /// Flat ground with a 6 m tall column of unclassified points (a trunk
    /// and crown as a forest's producer leaves them).
    fn forest_file() -> Cloud {
        let mut xyz = crate::geom::fixtures::lattice(40, 40, 0.5, |_, _| 0.0);
        let ground = xyz.len();
        xyz.extend((0..200).map(|i| [10.0 + (i % 5) as f32 * 0.3, 10.0, 2.0 + i as f32 * 0.03]));
        let mut c = Cloud::from_xyz(xyz);
        c.label = Some(
            (0..c.xyz.len())
                .map(|i| if i < ground { GROUND } else { 1 })
                .collect(),
        );
        c
    }

    #[test]
    fn a_forest_is_learned_as_vegetation_only_when_named_one() {
        let csf = CsfParams::default();
        let as_labelled =
            file_training_clouds("f", forest_file(), FileRole::Labelled, &[1.0], &csf);
        assert!(
            matches!(as_labelled, Err(ClassifyError::File { .. })),
            "class 1 alone is nothing to learn: {:?}",
            as_labelled.map(|v| v.len())
        );
        let clouds = file_training_clouds("f", forest_file(), FileRole::Forest, &[1.0, 0.5], &csf)
            .unwrap_or_else(|e| panic!("{e}"));
        let names: Vec<&str> = clouds.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["f", "f (thinned to 50 %)"]);
        let veg = clouds[0].label.iter().filter(|&&l| l == VEGETATION).count();
        assert_eq!(veg, 200);
        assert!(clouds[1].xyz.len() < clouds[0].xyz.len());
    }

    #[test]
    fn a_density_share_outside_0_1_is_refused() {
        for bad in [0.0, 1.5, f64::NAN] {
            let r = file_training_clouds(
                "f",
                forest_file(),
                FileRole::Forest,
                &[bad],
                &CsfParams::default(),
            );
            assert!(matches!(r, Err(ClassifyError::File { .. })), "{bad}");
        }
    }
}
