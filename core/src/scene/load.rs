//! Choosing a scene by name: the built-in reference scene or a file.

use std::path::Path;

use super::cityjson::{CityJsonOptions, city_files, is_city_file, read_city_files};
use super::obj::{ObjOptions, read_obj};
use super::ply_mesh::read_ply_mesh;
use super::reference::{REFERENCE_SEED, reference_scene};
use super::{Scene, SceneError};

/// Loads a scene from a spec:
/// - `reference` or `reference:SEED` (decimal u64): the built-in scene;
/// - otherwise a file path by extension (any case): `.obj`, `.ply`, `.json`
///   (incl. `.city.json`, CityJSON) or `.jsonl` (CityJSONSeq), read with
///   default options;
/// - several city model files (tiles) as one scene: a comma-separated list
///   or a directory of `.json` / `.jsonl` files.
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
    if spec.contains(',') || Path::new(spec).is_dir() {
        let files = city_files(spec)?;
        if let Some(p) = files.iter().find(|p| !is_city_file(p) && p.exists()) {
            return Err(SceneError::NotTile { path: p.clone() });
        }
        return read_city_files(&files, &CityJsonOptions::default());
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
        "json" | "jsonl" => read_city_files(&[path.to_path_buf()], &CityJsonOptions::default()),
        _ => Err(SceneError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}
