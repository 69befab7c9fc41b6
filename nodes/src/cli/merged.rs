//! The demo's merged cloud (the prior plus every resampled scan point): its
//! LAS and its LoD2 models.

use std::path::Path;

use skyground_core::cloud::{Cloud, class, write_cloud};
use skyground_core::reconstruct::ModelEvaluation;
use skyground_core::scene::Scene;

use crate::runtime::RuntimeError;

/// The prior with the resampled points appended (each a building point,
/// the one return of its beam).
pub fn merged_cloud(prior: &Cloud, resampled: Option<&Cloud>) -> Cloud {
    let mut merged = prior.clone();
    let Some(r) = resampled else {
        return merged;
    };
    merged.xyz.extend_from_slice(&r.xyz);
    if let Some(l) = merged.label.as_mut() {
        l.extend(std::iter::repeat_n(class::BUILDING, r.len()));
    }
    if let Some(b) = merged.building.as_mut() {
        b.extend(std::iter::repeat_n(0, r.len()));
    }
    if let Some(i) = merged.intensity.as_mut() {
        i.extend(std::iter::repeat_n(0.0, r.len()));
    }
    for col in [&mut merged.return_number, &mut merged.number_of_returns] {
        if let Some(c) = col.as_mut() {
            c.extend(std::iter::repeat_n(1, r.len()));
        }
    }
    merged
}

/// What [`after`] gives: the LAS written (or why not) and the models.
pub type AfterResult = (Result<(), String>, Result<ModelEvaluation, RuntimeError>);

/// The merged cloud written to `file` (LAS or LAZ by its extension) while
/// `models_after.*` are made beside it (per footprint when given, in the cloud's frame).
pub fn after(
    file: &Path,
    scene: &Scene,
    merged: &Cloud,
    spacing: f32,
    footprints: Option<&super::reconstruct::ModelFootprints>,
) -> AfterResult {
    let out = file.parent().unwrap_or(Path::new("."));
    std::thread::scope(|s| {
        let las = s.spawn(|| write_cloud(file, merged));
        let models =
            super::reconstruct::models_of(out, "models_after", scene, merged, spacing, footprints);
        let las = las
            .join()
            .map_err(|_| format!("writing {} panicked", file.display()))
            .and_then(|r| r.map_err(|e| e.to_string()));
        (las, models)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merged_points_are_building_single_returns_and_every_column_keeps_its_length() {
        let mut prior = Cloud::from_xyz(vec![[0.0; 3], [1.0, 0.0, 0.0]]);
        prior.label = Some(vec![class::GROUND, class::VEGETATION]);
        prior.building = Some(vec![0, 0]);
        prior.return_number = Some(vec![1, 2]);
        prior.number_of_returns = Some(vec![2, 2]);
        let scans = Cloud::from_xyz(vec![[5.0, 5.0, 5.0]; 3]);
        let m = merged_cloud(&prior, Some(&scans));
        assert_eq!(m.len(), 5);
        assert_eq!(m.label.as_deref(), Some(&[2, 5, 6, 6, 6][..]));
        assert_eq!(m.return_number.as_deref(), Some(&[1, 2, 1, 1, 1][..]));
        assert_eq!(m.number_of_returns.as_deref(), Some(&[2, 2, 1, 1, 1][..]));
        assert_eq!(m.building.as_ref().map(Vec::len), Some(5));
        assert!(
            m.intensity.is_none(),
            "a column the prior lacks stays absent"
        );
        assert_eq!(merged_cloud(&prior, None).len(), 2);
    }
}
