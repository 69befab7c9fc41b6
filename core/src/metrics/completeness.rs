//! Completeness (coverage of the ground truth by an observed cloud) and the
//! gap term of the mean distance.

use std::collections::BTreeMap;

use super::gt::{GtSamples, SurfaceKind};
use super::nearest::nearest_distances;
use crate::cloud::Cloud;

/// Default coverage radius τ, metres.
pub const DEFAULT_TAU: f32 = 0.25;

/// Covered share of a set of GT samples.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct Coverage {
    /// GT samples in the set.
    pub samples: usize,
    /// Of those, samples with an observed point within τ.
    pub covered: usize,
    /// `covered / samples`; `None` for an empty set.
    pub ratio: Option<f64>,
}

impl Coverage {
    fn add(&mut self, covered: bool) {
        self.samples += 1;
        self.covered += usize::from(covered);
    }

    fn finish(&mut self) {
        self.ratio = (self.samples > 0).then(|| self.covered as f64 / self.samples as f64);
    }
}

/// Completeness of one building.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct BuildingCompleteness {
    /// Building id.
    pub building: u32,
    /// Walls and roofs together.
    pub all: Coverage,
    /// Walls only.
    pub walls: Coverage,
    /// Roofs only.
    pub roofs: Coverage,
    /// Mean distance from its GT samples to the nearest observed point, m.
    pub mean_gt_distance: Option<f64>,
}

/// Completeness of an observed cloud against GT samples (see docs/design.md "Metrics").
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct CompletenessReport {
    /// Coverage radius τ, metres.
    pub tau: f32,
    /// Finite observed points used.
    pub observed_points: usize,
    /// All GT samples.
    pub overall: Coverage,
    /// Wall samples.
    pub walls: Coverage,
    /// Roof samples.
    pub roofs: Coverage,
    /// The gap term: plain mean over all GT samples of the distance to the
    /// nearest observed point (no cap: far gaps weigh in fully), metres;
    /// `None` without samples or observed points.
    pub mean_gt_distance: Option<f64>,
    /// Per building, ascending id.
    pub buildings: Vec<BuildingCompleteness>,
}

/// Share of `gt` samples with an observed point within `tau`, overall, per
/// building and walls vs roofs, plus the gap term.
///
/// `observed` must be in the same local frame as the samples (same origin).
pub fn completeness(gt: &GtSamples, observed: &[[f32; 3]], tau: f32) -> CompletenessReport {
    let dist = nearest_distances(&gt.xyz, observed);
    report_from_distances(gt, &dist, tau, count_finite(observed))
}

/// [`completeness`] of a [`Cloud`], first moved into the samples' frame
/// when its origin differs from theirs.
pub fn completeness_of_cloud(gt: &GtSamples, cloud: &Cloud, tau: f32) -> CompletenessReport {
    if cloud.origin == gt.origin {
        return completeness(gt, &cloud.xyz, tau);
    }
    let shift = [0, 1, 2].map(|k| cloud.origin[k] - gt.origin[k]);
    let moved: Vec<[f32; 3]> = cloud
        .xyz
        .iter()
        .map(|p| [0, 1, 2].map(|k| (f64::from(p[k]) + shift[k]) as f32))
        .collect();
    completeness(gt, &moved, tau)
}

/// The gap term alone: mean over GT samples of the distance to the nearest
/// observed point (plain mean, no cap); `None` without samples or points.
pub fn mean_gt_distance(gt: &GtSamples, observed: &[[f32; 3]]) -> Option<f64> {
    mean(&nearest_distances(&gt.xyz, observed))
}

/// Builds the report from per-sample nearest distances (`dist[i]` for sample `i`).
pub fn report_from_distances(
    gt: &GtSamples,
    dist: &[f32],
    tau: f32,
    observed_points: usize,
) -> CompletenessReport {
    let mut r = CompletenessReport {
        tau,
        observed_points,
        ..CompletenessReport::default()
    };
    let mut per: BTreeMap<u32, (BuildingCompleteness, f64)> = BTreeMap::new();
    for (i, &d) in dist.iter().enumerate().take(gt.len()) {
        let covered = d <= tau;
        let kind = gt.kind.get(i).copied().unwrap_or(SurfaceKind::Wall);
        let id = gt.building.get(i).copied().unwrap_or(0);
        let (b, sum) = per.entry(id).or_insert_with(|| {
            (
                BuildingCompleteness {
                    building: id,
                    ..BuildingCompleteness::default()
                },
                0.0,
            )
        });
        r.overall.add(covered);
        b.all.add(covered);
        *sum += f64::from(d);
        match kind {
            SurfaceKind::Wall => {
                r.walls.add(covered);
                b.walls.add(covered);
            }
            SurfaceKind::Roof => {
                r.roofs.add(covered);
                b.roofs.add(covered);
            }
        }
    }
    for c in [&mut r.overall, &mut r.walls, &mut r.roofs] {
        c.finish();
    }
    r.mean_gt_distance = mean(dist);
    r.buildings = per
        .into_values()
        .map(|(mut b, sum)| {
            b.all.finish();
            b.walls.finish();
            b.roofs.finish();
            let m = sum / b.all.samples.max(1) as f64;
            b.mean_gt_distance = m.is_finite().then_some(m);
            b
        })
        .collect();
    r
}

fn count_finite(points: &[[f32; 3]]) -> usize {
    points
        .iter()
        .filter(|p| p.iter().all(|v| v.is_finite()))
        .count()
}

fn mean(d: &[f32]) -> Option<f64> {
    if d.is_empty() {
        return None;
    }
    let m = d.iter().map(|&v| f64::from(v)).sum::<f64>() / d.len() as f64;
    m.is_finite().then_some(m)
}
