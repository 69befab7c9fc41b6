//! Model accuracy against the ground-truth mesh (docs/design.md "Metrics"):
//! per building, the model's roof and wall faces are sampled (above the
//! terrain, like the truth's samples) and the truth's samples are measured
//! to the model and the model's samples to the truth's building mesh; the
//! mean symmetric distance pools both directions.

use geo::{Area, BooleanOps, MultiPolygon};
use rayon::prelude::*;
use serde::Serialize;

use super::Reconstruction;
use super::solid::SurfaceType;
use crate::footprint::{footprints_of_scene, iou};
use crate::metrics::mesh_distance::building_triangles;
use crate::metrics::triangle_grid::TriangleGrid;
use crate::metrics::{GroundHeight, GtSamples, SurfaceKind};
use crate::metrics::{MeshBackend, MeshDistance};
use crate::scene::Scene;
use crate::scene::vec3::{cross, norm, sub};

/// Distances farther than this (m) count as this far (a model far off).
pub(crate) const FAR: f64 = 50.0;

/// Mean, root mean square and 95th percentile of one set of surface
/// distances, m (`None` without distances).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct DistanceStats {
    /// Mean, m.
    pub mean: Option<f64>,
    /// Root mean square, m.
    pub rmse: Option<f64>,
    /// 95th percentile, m.
    pub p95: Option<f64>,
}

impl DistanceStats {
    /// The statistics of `d` (reordered in place for the percentile).
    pub fn of(d: &mut [f64]) -> Self {
        if d.is_empty() {
            return Self::default();
        }
        let n = d.len() as f64;
        let mean = d.iter().sum::<f64>() / n;
        let rmse = (d.iter().map(|v| v * v).sum::<f64>() / n).sqrt();
        let k = ((n * 0.95).ceil() as usize).clamp(1, d.len()) - 1;
        d.select_nth_unstable_by(k, f64::total_cmp);
        Self {
            mean: Some(mean),
            rmse: Some(rmse),
            p95: Some(d[k]),
        }
    }
}

/// One ground-truth building against the models matched to it.
#[derive(Debug, Clone, Serialize)]
pub struct ModelScore {
    /// Ground-truth building id.
    pub building: u32,
    /// Ids of the models whose footprint overlaps this building most.
    pub models: Vec<u32>,
    /// The symmetric surface distances (both directions pooled).
    #[serde(flatten)]
    pub distance: DistanceStats,
    /// Mean distance of the truth's samples to the model, m.
    pub gt_to_model: Option<f64>,
    /// Mean distance of the model's samples to the truth, m.
    pub model_to_gt: Option<f64>,
    /// Mean distance of the truth's roof samples to the model's roof faces, m.
    pub roof_error: Option<f64>,
    /// Intersection over union of the model's and the true footprint.
    pub footprint_iou: Option<f64>,
    /// Every matched model is closed (each edge used twice, opposite ways).
    pub watertight: bool,
    /// ... and has no degenerate face.
    pub valid: bool,
    /// The model's samples (scene frame xy) and their distance to the truth, m
    /// (for pictures; not serialised).
    #[serde(skip)]
    pub samples: Vec<([f64; 2], f64)>,
}

/// All buildings of a scene against one reconstruction.
#[derive(Debug, Clone, Serialize)]
pub struct ModelEvaluation {
    /// Per ground-truth building, ascending id.
    pub buildings: Vec<ModelScore>,
    /// The symmetric distances of every matched building's samples, pooled.
    #[serde(flatten)]
    pub distance: DistanceStats,
    /// Mean roof error over all matched buildings' roof samples, m.
    pub roof_error: Option<f64>,
    /// Models made.
    pub models: usize,
    /// Every model is watertight.
    pub all_watertight: bool,
    /// Every model is valid.
    pub all_valid: bool,
    /// Ground-truth buildings no model overlaps.
    pub without_model: Vec<u32>,
    /// Models that overlap no ground-truth building.
    pub unmatched_models: Vec<u32>,
}

/// Points on triangle `t` at about one per `spacing`² (a deterministic
/// low-discrepancy sequence folded into the triangle).
fn sample_triangle(t: &[[f64; 3]; 3], spacing: f64, out: &mut Vec<[f64; 3]>) {
    let (e1, e2) = (sub(t[1], t[0]), sub(t[2], t[0]));
    let area = 0.5 * norm(cross(e1, e2));
    let n = (area / (spacing * spacing)).round().max(1.0) as usize;
    // R2 sequence (plastic number).
    let (a1, a2) = (0.754_877_666_246_692_8, 0.569_840_290_998_053_3);
    for k in 0..n {
        let (mut u, mut v) = ((0.5 + a1 * k as f64).fract(), (0.5 + a2 * k as f64).fract());
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        out.push([0, 1, 2].map(|i| t[0][i] + u * e1[i] + v * e2[i]));
    }
}

fn mean(d: &[f64]) -> Option<f64> {
    (!d.is_empty()).then(|| d.iter().sum::<f64>() / d.len() as f64)
}

/// Measures `rec` against the buildings of `scene` (its samples `gt`),
/// sampling the models at `spacing` m.
pub fn evaluate_models(
    scene: &Scene,
    gt: &GtSamples,
    rec: &Reconstruction,
    spacing: f64,
) -> ModelEvaluation {
    let shift = [0, 1, 2].map(|k| rec.origin[k] - scene.origin[k]);
    let move_xy = |mp: &MultiPolygon<f64>| {
        use geo::Translate;
        mp.translate(shift[0], shift[1])
    };
    let truth = footprints_of_scene(scene);
    // Each model goes to the true footprint it overlaps most.
    let mut matched: Vec<Vec<usize>> = vec![Vec::new(); truth.len()];
    let mut unmatched_models = Vec::new();
    for (m, model) in rec.models.iter().enumerate() {
        let o = move_xy(&model.outline);
        let best = truth
            .iter()
            .enumerate()
            .map(|(k, f)| (k, o.intersection(&f.polygon).unsigned_area()))
            .filter(|(_, a)| *a > 0.0)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match best {
            Some((k, _)) => matched[k].push(m),
            None => unmatched_models.push(model.id),
        }
    }
    // Model triangles (scene frame), tagged model index × 2 + roof flag.
    let mut tris = Vec::new();
    let mut tags = Vec::new();
    for (m, model) in rec.models.iter().enumerate() {
        for (t, kind) in model.shell.triangles() {
            tris.push(t.map(|p| [0, 1, 2].map(|k| p[k] + shift[k])));
            tags.push(m as u32 * 2 + u32::from(kind == SurfaceType::RoofSurface));
        }
    }
    let model_tris: Vec<([[f64; 3]; 3], u32)> =
        tris.iter().copied().zip(tags.iter().copied()).collect();
    let model_grid = TriangleGrid::new(tris, tags);
    let gt_mesh = MeshDistance::new(building_triangles(scene), MeshBackend::default());
    let terrain = GroundHeight::new(scene);
    let mut pooled: Vec<f64> = Vec::new();
    let mut pooled_roof: Vec<f64> = Vec::new();
    let mut buildings = Vec::new();
    let mut without_model = Vec::new();
    for (k, f) in truth.iter().enumerate() {
        let ms = &matched[k];
        let checks: Vec<_> = ms.iter().map(|&m| rec.models[m].shell.check()).collect();
        let mut score = ModelScore {
            building: f.id,
            models: ms.iter().map(|&m| rec.models[m].id).collect(),
            distance: DistanceStats::default(),
            gt_to_model: None,
            model_to_gt: None,
            roof_error: None,
            footprint_iou: None,
            watertight: !ms.is_empty() && checks.iter().all(|c| c.watertight()),
            valid: !ms.is_empty() && checks.iter().all(|c| c.valid()),
            samples: Vec::new(),
        };
        if ms.is_empty() {
            without_model.push(f.id);
            buildings.push(score);
            continue;
        }
        let in_model = |tag: u32| ms.contains(&((tag / 2) as usize));
        let samples: Vec<([f64; 3], bool)> = (0..gt.len())
            .filter(|&i| gt.building[i] == f.id)
            .map(|i| (gt.xyz[i].map(f64::from), gt.kind[i] == SurfaceKind::Roof))
            .collect();
        let to_model: Vec<(f64, f64)> = samples
            .par_iter()
            .map(|(p, roof)| {
                let d = model_grid
                    .nearest(*p, FAR, in_model)
                    .map_or(FAR, |(d2, _)| d2.sqrt());
                let r = if *roof {
                    model_grid
                        .nearest(*p, FAR, |t| t % 2 == 1 && in_model(t))
                        .map_or(FAR, |(d2, _)| d2.sqrt())
                } else {
                    f64::NAN
                };
                (d, r)
            })
            .collect();
        let mut model_pts = Vec::new();
        for (t, tag) in &model_tris {
            if in_model(*tag) {
                sample_triangle(t, spacing, &mut model_pts);
            }
        }
        let model_pts: Vec<[f64; 3]> = model_pts
            .into_iter()
            .filter(|p| terrain.at(p[0], p[1]).is_none_or(|g| p[2] > g + 0.05))
            .collect();
        let to_gt: Vec<f64> = model_pts
            .par_iter()
            .map(|p| gt_mesh.distance(*p, FAR).unwrap_or(FAR))
            .collect();
        score.samples = model_pts
            .iter()
            .zip(&to_gt)
            .map(|(p, d)| ([p[0], p[1]], *d))
            .collect();
        let a: Vec<f64> = to_model.iter().map(|d| d.0).collect();
        let roof: Vec<f64> = to_model
            .iter()
            .map(|d| d.1)
            .filter(|v| !v.is_nan())
            .collect();
        score.gt_to_model = mean(&a);
        score.model_to_gt = mean(&to_gt);
        score.roof_error = mean(&roof);
        let mut all: Vec<f64> = a.iter().chain(&to_gt).copied().collect();
        pooled.extend_from_slice(&all);
        pooled_roof.extend_from_slice(&roof);
        score.distance = DistanceStats::of(&mut all);
        let union = ms
            .iter()
            .map(|&m| move_xy(&rec.models[m].outline))
            .fold(MultiPolygon::new(Vec::new()), |acc, o| acc.union(&o));
        score.footprint_iou = Some(iou(&union, &f.polygon));
        buildings.push(score);
    }
    let checks: Vec<_> = rec.models.iter().map(|m| m.shell.check()).collect();
    ModelEvaluation {
        buildings,
        distance: DistanceStats::of(&mut pooled),
        roof_error: mean(&pooled_roof),
        models: rec.models.len(),
        all_watertight: checks.iter().all(|c| c.watertight()),
        all_valid: checks.iter().all(|c| c.valid()),
        without_model,
        unmatched_models,
    }
}

/// Mean distance from the points of `points` (local frame of `rec`) that
/// lie on a model's footprint (within 0.5 m of it) to the nearest model
/// face: City3D's measure of fit. Also returns how many points that was.
pub fn points_to_models(rec: &Reconstruction, points: &[[f32; 3]]) -> Option<(f64, usize)> {
    let fps: Vec<crate::footprint::Footprint> = rec
        .models
        .iter()
        .enumerate()
        .map(|(k, m)| crate::footprint::Footprint {
            id: k as u32 + 1,
            polygon: m.outline.clone(),
            name: m.name.clone(),
        })
        .collect();
    let ids =
        crate::footprint::split(points, &fps, &crate::footprint::SplitParams::default()).ok()?;
    let mine: Vec<[f32; 3]> = points
        .iter()
        .zip(&ids)
        .filter(|(_, id)| **id != 0)
        .map(|(p, _)| *p)
        .collect();
    let tris: Vec<[[f64; 3]; 3]> = rec
        .models
        .iter()
        .flat_map(|m| m.shell.triangles().into_iter().map(|(t, _)| t))
        .collect();
    let mesh = MeshDistance::new(tris, MeshBackend::default());
    let d: Vec<f64> = mine
        .par_iter()
        .map(|p| mesh.distance(p.map(f64::from), FAR).unwrap_or(FAR))
        .collect();
    mean(&d).map(|m| (m, d.len()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_cover_a_triangle_evenly() {
        let t = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
        let mut out = Vec::new();
        sample_triangle(&t, 0.25, &mut out);
        assert_eq!(out.len(), 128);
        assert!(
            out.iter()
                .all(|p| p[0] >= 0.0 && p[1] >= 0.0 && p[0] + p[1] <= 4.0)
        );
        let near_origin = out.iter().filter(|p| p[0] + p[1] < 2.0).count();
        // A quarter of the area lies within x + y < 2.
        assert!(
            (near_origin as f64 / 128.0 - 0.25).abs() < 0.05,
            "{near_origin}"
        );
        let mut d = vec![1.0, 2.0, 3.0, 4.0];
        let s = DistanceStats::of(&mut d);
        assert_eq!((s.mean, s.p95), (Some(2.5), Some(4.0)));
        assert!((s.rmse.unwrap() - 7.5f64.sqrt()).abs() < 1e-12);
    }
}
