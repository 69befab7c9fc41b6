//! The classifier model scene_classifier and the CLI's commands load: a
//! file named, or the one shipped with skyground.

use std::path::Path;

use skyground_core::classify::Model;

use super::RuntimeError;

/// The model shipped with skyground (`skyground train` makes it).
pub const DEFAULT_MODEL: &[u8] = include_bytes!("../../../config/classifier_model.json.gz");

/// The model at `path`, or the shipped one for an empty path (a node's `model_path`).
pub fn load_model(path: &str) -> Result<Model, RuntimeError> {
    load_model_file((!path.is_empty()).then(|| Path::new(path)))
}

/// The model file `path` (a command's `--model`), or the shipped one.
pub fn load_model_file(path: Option<&Path>) -> Result<Model, RuntimeError> {
    let model = match path {
        None => Model::from_slice(DEFAULT_MODEL),
        Some(p) => Model::load(p),
    };
    let name = path.map(|p| p.display().to_string()).unwrap_or_default();
    model.map_err(|e| RuntimeError::Node(format!("classifier model {name:?}: {e}")))
}
