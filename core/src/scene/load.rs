//! Choosing a scene by name: the built-in reference scene or a file.

use std::path::Path;

use super::cityjson::{CityJsonOptions, read_cityjson};
use super::obj::{ObjOptions, read_obj};
use super::ply_mesh::read_ply_mesh;
use super::reference::{REFERENCE_SEED, reference_scene};
use super::{Scene, SceneError};

/// Loads a scene from a spec:
/// - `reference` or `reference:SEED` (decimal u64): the built-in scene;
/// - otherwise a file path by extension (any case): `.obj`, `.ply`, `.json`
///   (incl. `.city.json`, CityJSON), read with default options.
pub fn load_scene(spec: &str) -> Result<Scene, SceneError> {
    if spec == "reference" {
        return Ok(reference_scene(REFERENCE_SEED));
    }
    if let Some(seed) = spec.strip_prefix("reference:") {
        let seed = seed
            .trim()
            .parse::<u64>()
            .map_err(|_| SceneError::BadSeed {
                spec: spec.to_string(),
            })?;
        return Ok(reference_scene(seed));
    }
    let path = Path::new(spec);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "obj" => read_obj(path, &ObjOptions::default()),
        "ply" => read_ply_mesh(path),
        "json" => read_cityjson(path, &CityJsonOptions::default()),
        _ => Err(SceneError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}
