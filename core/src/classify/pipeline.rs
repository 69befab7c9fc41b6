//! The classification of one cloud: ground flags in, LAS codes out.

use super::error::ClassifyError;
use super::model::Model;
use crate::cloud::class::{GROUND, UNCLASSIFIED};
use crate::features::compute_subset;

/// LAS class of every point: 2 where `is_ground`, else the forest's
/// vegetation (5) or building (6). A non-ground point the forest calls
/// ground (a low object the ground filter left standing) gets 1.
/// `hag`: height above the ground model, metres.
pub fn classify(
    xyz: &[[f32; 3]],
    hag: &[f32],
    is_ground: &[bool],
    model: &Model,
) -> Result<Vec<u8>, ClassifyError> {
    if xyz.is_empty() {
        return Err(ClassifyError::Empty);
    }
    for (what, got) in [("hag", hag.len()), ("is_ground", is_ground.len())] {
        if got != xyz.len() {
            return Err(ClassifyError::LengthMismatch {
                what,
                expected: xyz.len(),
                got,
            });
        }
    }
    model.check()?;
    let rows: Vec<usize> = (0..xyz.len()).filter(|&i| !is_ground[i]).collect();
    let mut out = vec![GROUND; xyz.len()];
    if rows.is_empty() {
        return Ok(out);
    }
    let features = compute_subset(xyz, hag, &rows, &model.feature_params)?;
    let predicted = model.forest.predict(&features.data)?;
    for (&i, &c) in rows.iter().zip(&predicted) {
        out[i] = if c == GROUND { UNCLASSIFIED } else { c };
    }
    Ok(out)
}
