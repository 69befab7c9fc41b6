//! Choosing a scene by name: the built-in reference scene or a file.

use std::path::Path;

use crate::crs::Crs;

use super::SceneError;
use super::cityjson::{CityJsonOptions, city_files, is_city_file, read_city_files_and_crs};
use super::obj::scene::{ObjOptions, read_obj};
use super::ply_mesh::read_ply_mesh;
use crate::scene::Scene;
use crate::scene::reference::{REFERENCE_SEED, reference_scene};

/// Loads a scene from a spec:
/// - `reference` or `reference:SEED` (decimal u64): the built-in scene;
/// - otherwise a file path by extension (any case): `.obj`, `.ply`, `.json`
///   (incl. `.city.json`, CityJSON) or `.jsonl` (CityJSONSeq), read with
///   default options;
/// - several city model files (tiles) as one scene: a comma-separated list
///   or a directory of `.json` / `.jsonl` files.
pub fn load_scene(spec: &str) -> Result<Scene, SceneError> {
    load_scene_and_crs(spec).map(|(scene, _)| scene)
}

/// Loads a scene as [`load_scene`] does, with its city model's CRS (`None`
/// for the reference scene, OBJ, PLY, and a model naming none we resolve):
/// the model is read once.
pub fn load_scene_and_crs(spec: &str) -> Result<(Scene, Option<Crs>), SceneError> {
    let no_crs = |scene: Result<Scene, SceneError>| scene.map(|s| (s, None));
    if spec == "reference" {
        return Ok((reference_scene(REFERENCE_SEED), None));
    }
    if let Some(seed) = spec.strip_prefix("reference:") {
        let seed = seed
            .trim()
            .parse::<u64>()
            .map_err(|_| SceneError::BadSeed {
                spec: spec.to_string(),
            })?;
        return Ok((reference_scene(seed), None));
    }
    if spec.contains(',') || Path::new(spec).is_dir() {
        let files = city_files(spec)?;
        if let Some(p) = files.iter().find(|p| !is_city_file(p) && p.exists()) {
            return Err(SceneError::NotTile { path: p.clone() });
        }
        return read_city_files_and_crs(&files, &CityJsonOptions::default());
    }
    let path = Path::new(spec);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "obj" => no_crs(read_obj(path, &ObjOptions::default())),
        "ply" => no_crs(read_ply_mesh(path)),
        "json" | "jsonl" => {
            read_city_files_and_crs(&[path.to_path_buf()], &CityJsonOptions::default())
        }
        _ => Err(SceneError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}
