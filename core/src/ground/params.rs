//! Parameters of the Cloth Simulation Filter, filled from a params file.

use serde::{Deserialize, Serialize};

use crate::density::{Auto, Density};
use crate::params::{Checks, ParamError};

/// Cloth resolution over point spacing in sparse clouds.
const CLOTH_SPACINGS: f32 = 4.0;
/// Finest automatic cloth, metres: bridges 60 m roofs.
const MIN_CLOTH: f32 = 4.0;
/// The paper's class threshold, metres.
const MIN_THRESHOLD: f32 = 0.5;
/// Largest automatic class threshold, metres (a low wall or a car is taller).
const MAX_THRESHOLD: f32 = 1.0;

/// Cloth Simulation Filter parameters (Zhang et al. 2016); every field has
/// a default, so a params file names only what differs.
///
/// The defaults (`auto`) follow the cloud's measured density; they suit
/// city surveys from ~1 to ~50 pts/m² with roofs up to 60 m across
/// (sample_c.las, the reference city, IGN LiDAR HD, AHN3); see
/// `core/tests/ground.rs`, `core/tests/real_density.rs` and
/// `config/scene_classifier.yaml` for the figures they give.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct CsfParams {
    /// Spacing of the cloth's particles, metres; `auto`: [`CsfParams::cloth_rule`].
    pub cloth_resolution: Auto<f32>,
    /// Cloth stiffness, 1 (steep slopes) to 3 (flat terrain): how many
    /// times each spring is relaxed per step.
    pub rigidness: u8,
    /// Time step of the Verlet integration (the paper's 0.65).
    pub time_step: f32,
    /// Points closer than this to the cloth (vertically) are ground, metres;
    /// `auto`: [`CsfParams::threshold_rule`].
    pub class_threshold: Auto<f32>,
    /// Most simulation steps.
    pub iterations: u32,
    /// The simulation stops when no particle moved more than this in a step, metres.
    pub tolerance: f32,
    /// Post-processing: pull cloth that hangs just above steep terrain onto it.
    pub slope_smoothing: bool,
    /// Slope smoothing pulls a free particle down onto the surface when it
    /// hangs less than this above it, metres.
    pub slope_threshold: f32,
    /// Post-processing: a piece of ground higher than all the ground near
    /// it by more than this, metres (plus the survey's slope times the
    /// gap), is a roof the cloth rested on where the survey ends, not
    /// ground; 0: off. See `ground::raised`.
    pub raised_step_m: f32,
    /// Pieces of ground covering more than this, m², are never raised.
    pub raised_max_m2: f32,
}

impl Default for CsfParams {
    fn default() -> Self {
        Self {
            cloth_resolution: Auto::Auto,
            rigidness: 3,
            time_step: 0.65,
            class_threshold: Auto::Auto,
            iterations: 500,
            tolerance: 0.005,
            slope_smoothing: true,
            slope_threshold: 0.3,
            raised_step_m: 2.0,
            raised_max_m2: 10_000.0,
        }
    }
}

impl CsfParams {
    /// The cloth resolution for a cloud of density `d`: the given number, or
    /// the rule (see [`CsfParams::cloth_rule`]).
    pub fn cloth_resolution_for(&self, d: &Density) -> f32 {
        self.cloth_resolution.or_rule(|| Self::cloth_rule(d))
    }

    /// The class threshold for a cloud of density `d`: the given number, or
    /// the rule (see [`CsfParams::threshold_rule`]).
    pub fn class_threshold_for(&self, d: &Density) -> f32 {
        self.class_threshold.or_rule(|| Self::threshold_rule(d))
    }

    /// These parameters with every `auto` replaced by its value at `d`.
    pub fn resolved(&self, d: &Density) -> Self {
        Self {
            cloth_resolution: Auto::Value(self.cloth_resolution_for(d)),
            class_threshold: Auto::Value(self.class_threshold_for(d)),
            ..self.clone()
        }
    }

    /// `cloth_resolution: auto`: four point spacings (a particle's cell
    /// then holds ~16 points, enough to find the lowest surface under it),
    /// never finer than 4 m: the cloth must bridge the widest roof, and
    /// 2–3 m cloths sagged onto sample_c.las's 60 m roof (total error 46 %
    /// at 2 m, 21 % at 3 m, 3–4 % at 4 m). So 4 m from 1 pt/m² up (every
    /// survey here), coarser below.
    pub fn cloth_rule(d: &Density) -> f32 {
        (CLOTH_SPACINGS * d.spacing_m).max(MIN_CLOTH)
    }

    /// `class_threshold: auto`: the paper's 0.5 m, raised to one point
    /// spacing (at most 1 m) in clouds sparser than 4 pts/m², where the
    /// cloth rests on fewer points and ground between them departs further
    /// from it.
    pub fn threshold_rule(d: &Density) -> f32 {
        d.spacing_m.clamp(MIN_THRESHOLD, MAX_THRESHOLD)
    }

    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("ground filter");
        if let Some(v) = self.cloth_resolution.value() {
            c.positive("cloth_resolution", v)?;
        }
        c.positive("time_step", self.time_step)?;
        if let Some(v) = self.class_threshold.value() {
            c.positive("class_threshold", v)?;
        }
        c.positive("tolerance", self.tolerance)?;
        c.positive("slope_threshold", self.slope_threshold)?;
        c.non_negative("raised_step_m", self.raised_step_m)?;
        c.non_negative("raised_max_m2", self.raised_max_m2)?;
        let rigid = (1..=3).contains(&self.rigidness);
        c.that(
            rigid,
            "rigidness",
            self.rigidness,
            "1 (steep), 2 or 3 (flat)",
        )?;
        c.that(
            self.iterations > 0,
            "iterations",
            self.iterations,
            "at least 1",
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_validate_and_bad_fields_are_named() {
        assert!(CsfParams::default().validate().is_ok());
        let p = CsfParams {
            rigidness: 4,
            ..CsfParams::default()
        };
        assert!(matches!(
            p.validate(),
            Err(ParamError {
                field: "rigidness",
                ..
            })
        ));
        let p = CsfParams {
            cloth_resolution: Auto::Value(f32::NAN),
            ..CsfParams::default()
        };
        assert!(p.validate().is_err());
    }

    #[test]
    fn params_file_names_only_what_differs() {
        let p: CsfParams = serde_json::from_str(r#"{"rigidness": 1}"#).unwrap();
        assert_eq!(p.rigidness, 1);
        assert_eq!(p.iterations, CsfParams::default().iterations);
        assert!(serde_json::from_str::<CsfParams>(r#"{"rigid": 1}"#).is_err());
    }
}
