//! `completeness.city.json`: the mission's per-building figures written back
//! into the city model (a CityJSON 2.0 copy of the input's buildings with
//! `skyground_*` attributes), or the scene's buildings as LoD 2 surfaces
//! when the scene is no city model.

use std::collections::BTreeMap;
use std::path::Path;

use skyground_core::io::cityjson::{
    Attributes, annotated_model, city_files, is_city_file, read_city_model, scene_model,
};
use skyground_core::metrics::Evaluation;
use skyground_core::mission::{Mission, building_attributes};
use skyground_core::scene::{Cropped, ObjectKind, Scene};

use crate::runtime::RuntimeError;

/// The file name written into the output directory.
pub const FILE_NAME: &str = "completeness.city.json";

/// Writes `dir/completeness.city.json` for the evaluation `e` of `scene`
/// (loaded from `spec`, or cropped from it as `crop`); returns its path.
pub fn write_completeness(
    dir: &Path,
    spec: &str,
    scene: &Scene,
    crop: Option<&Cropped>,
    e: &Evaluation,
    spacing: f32,
    mission: Option<Mission<'_>>,
) -> Result<std::path::PathBuf, RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let by_id = building_attributes(e, spacing, mission);
    let files = city_files(spec).unwrap_or_default();
    let is_city = !files.is_empty() && files.iter().all(|p| is_city_file(p));
    let doc = if is_city {
        let model = read_city_model(&files).map_err(|e| err(format!("scene {spec}: {e}")))?;
        let roots = model.roots();
        // A building id of the evaluated scene → the name of its first
        // object (a CityJSON id) → its root Building.
        let names: BTreeMap<u32, String> = match crop {
            Some(c) => c.buildings.iter().map(|b| (b.id, b.name.clone())).collect(),
            None => {
                let mut m = BTreeMap::new();
                for o in scene
                    .objects
                    .iter()
                    .filter(|o| o.kind == ObjectKind::Building)
                {
                    m.entry(o.building).or_insert_with(|| o.name.clone());
                }
                m
            }
        };
        let mut by_root: BTreeMap<String, Attributes> = BTreeMap::new();
        for (id, attrs) in by_id {
            let root = names.get(&id).and_then(|n| roots.get(n.as_str()));
            if let Some(root) = root {
                by_root.insert((*root).to_string(), attrs);
            }
        }
        annotated_model(&model, &by_root, crop.is_some())
    } else {
        scene_model(scene, &by_id, None)
    };
    let path = dir.join(FILE_NAME);
    skyground_core::file::write(
        &path,
        serde_json::to_vec(&doc).map_err(|e| err(e.to_string()))?,
    )
    .map_err(|e| err(format!("{}: {e}", path.display())))?;
    Ok(path)
}
