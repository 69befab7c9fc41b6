//! A trained classifier as one file: the feature definition and the forest.

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

use flate2::Compression;
use flate2::read::GzDecoder;
use flate2::write::GzEncoder;

use serde::{Deserialize, Serialize};

use super::error::ClassifyError;
use super::roofs::RoofCheck;
use crate::features::{FEATURE_NAMES, FeatureParams};
use crate::forest::RandomForest;

/// What `classify` needs: how features are computed and the forest on them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Neighbourhood sizes the forest was trained with.
    pub feature_params: FeatureParams,
    /// Feature names in column order (checked on load).
    pub feature_names: Vec<String>,
    /// The forest; its classes are LAS codes (2, 5, 6).
    pub forest: RandomForest,
    /// The forest for clouds without echo information (no pulse with more
    /// than one return: photogrammetry, first-return products), trained on
    /// the same clouds with their echoes hidden; `None` in older models,
    /// which use `forest` for every cloud.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub forest_without_echoes: Option<RandomForest>,
    /// The LAS codes the forest tells apart.
    pub classes: Vec<u8>,
    /// What the model was trained on, for provenance.
    pub trained_on: String,
    /// The training clouds by name (files as given, simulated surveys by
    /// scene and density): no accuracy figure may be reported on these.
    #[serde(default)]
    pub training_files: Vec<String>,
    /// How the forest's votes are smoothed over neighbours.
    #[serde(default)]
    pub smoothing: Smoothing,
    /// The roof-plane check after the forest (`classify::roofs`).
    #[serde(default)]
    pub roof_check: RoofCheck,
}

/// Neighbourhood smoothing of the votes (see `classify::smooth`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Smoothing {
    /// Neighbours averaged, the point included (below 2: no smoothing).
    pub k: usize,
    /// Farthest neighbour counted, metres.
    pub radius_m: f32,
}

impl Default for Smoothing {
    fn default() -> Self {
        Self {
            k: 16,
            radius_m: 1.5,
        }
    }
}

impl Model {
    /// The forest for a cloud with (`true`) or without echo information.
    pub fn forest_for(&self, echoes: bool) -> &RandomForest {
        match &self.forest_without_echoes {
            Some(f) if !echoes => f,
            _ => &self.forest,
        }
    }

    /// Checks the forests against the current feature definition.
    pub fn check(&self) -> Result<(), ClassifyError> {
        self.feature_params.validate()?;
        self.forest.check()?;
        if let Some(f) = &self.forest_without_echoes {
            f.check()?;
            if f.dims() != self.forest.dims() || f.classes() != self.forest.classes() {
                return Err(ClassifyError::ForestsDisagree);
            }
        }
        let names_match = self
            .feature_names
            .iter()
            .map(String::as_str)
            .eq(FEATURE_NAMES);
        if self.forest.dims() != FEATURE_NAMES.len() || !names_match {
            return Err(ClassifyError::ModelMismatch {
                expected: self.forest.dims(),
                got: FEATURE_NAMES.len(),
            });
        }
        Ok(())
    }

    /// Writes the model as JSON, gzipped when `path` ends in `.gz`.
    pub fn save(&self, path: &Path) -> Result<(), ClassifyError> {
        let err = |m: String| ClassifyError::File {
            path: path.display().to_string(),
            message: m,
        };
        // Built in memory and written atomically: a failure leaves an earlier model whole.
        let mut bytes = Vec::new();
        if path.extension().is_some_and(|e| e == "gz") {
            let mut gz = GzEncoder::new(&mut bytes, Compression::best());
            serde_json::to_writer(&mut gz, self).map_err(|e| err(e.to_string()))?;
            gz.finish().map_err(|e| err(e.to_string()))?;
        } else {
            serde_json::to_writer(&mut bytes, self).map_err(|e| err(e.to_string()))?;
        }
        crate::file::write(path, bytes).map_err(|e| err(e.to_string()))
    }

    /// Reads and checks a model from the bytes of a file written by
    /// [`Self::save`] (plain or gzipped JSON).
    pub fn from_slice(bytes: &[u8]) -> Result<Self, ClassifyError> {
        Self::from_reader(bytes, "(built-in model)")
    }

    /// Reads and checks a model written by [`Self::save`] (plain or gzipped JSON).
    pub fn load(path: &Path) -> Result<Self, ClassifyError> {
        let f = File::open(path).map_err(|e| ClassifyError::File {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::from_reader(BufReader::new(f), &path.display().to_string())
    }

    /// Parses JSON, or gzipped JSON (told apart by gzip's magic bytes, so a
    /// renamed file still loads).
    fn from_reader(mut r: impl BufRead, name: &str) -> Result<Self, ClassifyError> {
        let err = |m: String| ClassifyError::File {
            path: name.to_string(),
            message: m,
        };
        let gz = r
            .fill_buf()
            .map_err(|e| err(e.to_string()))?
            .starts_with(&GZIP_MAGIC);
        let m: Self = if gz {
            serde_json::from_reader(GzDecoder::new(r))
        } else {
            serde_json::from_reader(r)
        }
        .map_err(|e| err(e.to_string()))?;
        m.check()?;
        Ok(m)
    }
}

/// The first two bytes of every gzip stream (RFC 1952).
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];
