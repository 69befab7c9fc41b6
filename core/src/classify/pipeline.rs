//! The classification of one cloud: ground flags in, LAS codes out.

use super::blocks::{BLOCK_POINTS, votes};
use super::error::ClassifyError;
use super::grade::{AtGrade, join_terrain};
use super::model::Model;
use super::roofs::check_roofs;
use super::smooth::{argmax_rows, smooth_votes};
use crate::cloud::ColumnLength;
use crate::cloud::class::{GROUND, UNCLASSIFIED};
use crate::density::Density;
use crate::features::Echoes;

/// LAS class of every point: 2 where `is_ground`, else the forest's
/// vegetation (5) or building (6). A non-ground point the forest calls
/// ground is ground too (2: terrain the cloth missed, see
/// [`classify_at`]), and a building surface that continues the terrain 2
/// or 17 ([`join_terrain`]).
/// `hag`: height above the ground model, metres; `echoes`: the cloud's
/// return numbers, when it has them.
pub fn classify(
    xyz: &[[f32; 3]],
    hag: &[f32],
    is_ground: &[bool],
    echoes: Option<Echoes<'_>>,
    model: &Model,
) -> Result<Vec<u8>, ClassifyError> {
    let spacing = Density::measure(xyz).map_or(0.0, |d| d.spacing_m);
    classify_at(xyz, hag, is_ground, echoes, model, spacing).map(|(labels, _)| labels)
}

/// [`classify`] of a cloud whose point spacing (m) is already measured
/// (the ground filter measures it): the roof check's cells and links
/// follow it below 4 pts/m². Also says which points the ground filter
/// left standing are ground after all: building surfaces that continue the
/// terrain ([`join_terrain`]: ground (2) or bridge deck (17)), and points
/// the forest calls ground. The forest learned its ground class on exactly
/// the points the filter leaves to it (producer ground the cloth missed,
/// [`super::training::labelled_cloud`]): terrain on slopes and banks, where
/// a stiff cloth hangs more than its threshold off the ground.
pub fn classify_at(
    xyz: &[[f32; 3]],
    hag: &[f32],
    is_ground: &[bool],
    echoes: Option<Echoes<'_>>,
    model: &Model,
    spacing_m: f32,
) -> Result<(Vec<u8>, AtGrade), ClassifyError> {
    if xyz.is_empty() {
        return Err(ClassifyError::Empty);
    }
    for (what, got) in [("hag", hag.len()), ("is_ground", is_ground.len())] {
        ColumnLength::check(what, xyz.len(), got)?;
    }
    model.check()?;
    let rows: Vec<usize> = (0..xyz.len()).filter(|&i| !is_ground[i]).collect();
    let mut forest_ground: Vec<usize> = Vec::new();
    let mut out = vec![GROUND; xyz.len()];
    if rows.is_empty() {
        return Ok((out, AtGrade::default()));
    }
    let proba = votes(xyz, hag, echoes, &rows, model, BLOCK_POINTS)?;
    let classes = model.forest.classes();
    let sub: Vec<[f32; 3]> = rows.iter().map(|&i| xyz[i]).collect();
    let s = &model.smoothing;
    let proba = smooth_votes(&sub, &proba, classes.len(), s.k, s.radius_m);
    for (&i, k) in rows.iter().zip(argmax_rows(&proba, classes.len())) {
        let c = classes.get(k).copied().unwrap_or(UNCLASSIFIED);
        // Held out of the roof check and the growing at grade (their
        // settings were chosen without these points), ground after them.
        if c == GROUND {
            forest_ground.push(i);
        }
        out[i] = if c == GROUND { UNCLASSIFIED } else { c };
    }
    check_roofs(
        xyz,
        hag,
        &mut out,
        echoes,
        &model.roof_check.for_spacing(spacing_m),
    );
    let mut at_grade = join_terrain(xyz, &mut out, spacing_m);
    for i in forest_ground {
        if out[i] == UNCLASSIFIED {
            out[i] = GROUND;
            at_grade.forest_ground += 1;
        }
    }
    Ok((out, at_grade))
}
