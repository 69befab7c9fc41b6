//! Parameters of the Cloth Simulation Filter, filled from a params file.

use serde::{Deserialize, Serialize};

use super::error::CsfError;

/// Cloth Simulation Filter parameters (Zhang et al. 2016); every field has
/// a default, so a params file names only what differs.
///
/// The defaults suit city surveys from ~2 to ~46 pts/m² with roofs up to
/// 60 m across (sample_c.las, the reference city); see `core/tests/ground.rs`
/// and `config/scene_classifier.yaml` for the figures they give.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct CsfParams {
    /// Spacing of the cloth's particles, metres.
    pub cloth_resolution: f32,
    /// Cloth stiffness, 1 (steep slopes) to 3 (flat terrain): how many
    /// times each spring is relaxed per step.
    pub rigidness: u8,
    /// Time step of the Verlet integration (the paper's 0.65).
    pub time_step: f32,
    /// Points closer than this to the cloth (vertically) are ground, metres.
    pub class_threshold: f32,
    /// Most simulation steps.
    pub iterations: u32,
    /// The simulation stops when no particle moved more than this in a step, metres.
    pub tolerance: f32,
    /// Post-processing: pull cloth that hangs just above steep terrain onto it.
    pub slope_smoothing: bool,
    /// Slope smoothing pulls a free particle down onto the surface when it
    /// hangs less than this above it, metres.
    pub slope_threshold: f32,
}

impl Default for CsfParams {
    fn default() -> Self {
        Self {
            cloth_resolution: 4.0,
            rigidness: 3,
            time_step: 0.65,
            class_threshold: 0.5,
            iterations: 500,
            tolerance: 0.005,
            slope_smoothing: true,
            slope_threshold: 0.3,
        }
    }
}

impl CsfParams {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), CsfError> {
        positive("cloth_resolution", self.cloth_resolution)?;
        positive("time_step", self.time_step)?;
        positive("class_threshold", self.class_threshold)?;
        positive("tolerance", self.tolerance)?;
        positive("slope_threshold", self.slope_threshold)?;
        if !(1..=3).contains(&self.rigidness) {
            return Err(CsfError::BadParam {
                name: "rigidness",
                value: f64::from(self.rigidness),
                expected: "1 (steep), 2 or 3 (flat)",
            });
        }
        if self.iterations == 0 {
            return Err(CsfError::BadParam {
                name: "iterations",
                value: 0.0,
                expected: "at least 1",
            });
        }
        Ok(())
    }
}

fn positive(name: &'static str, value: f32) -> Result<(), CsfError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CsfError::BadParam {
            name,
            value: f64::from(value),
            expected: "a finite number > 0",
        })
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
            Err(CsfError::BadParam {
                name: "rigidness",
                ..
            })
        ));
        let p = CsfParams {
            cloth_resolution: f32::NAN,
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
