//! Before/after evaluation of a mission (docs/design.md step 9, the paper's
//! Table 2): completeness and both distance terms for the aerial prior and
//! for the merged cloud, overall and per building.

use serde::Serialize;

use super::accuracy::mean_cloud_to_mesh;
use super::completeness::{CompletenessReport, completeness};
use super::gt::GtSamples;
use crate::cloud::{Cloud, class};
use crate::scene::Scene;

/// One cloud measured against ground truth.
#[derive(Debug, Clone, Serialize)]
pub struct Measured {
    /// Points of the cloud.
    pub points: usize,
    /// Points used as building points (label 6, or all when unlabelled).
    pub building_points: usize,
    /// Completeness, overall / per building / walls vs roofs, and the gap term.
    pub completeness: CompletenessReport,
    /// The accuracy term: mean distance of building points to the mesh, m.
    pub mean_cloud_to_mesh: Option<f64>,
}

/// One building before and after.
#[derive(Debug, Clone, Serialize)]
pub struct BuildingRow {
    /// Building id.
    pub building: u32,
    /// Completeness before (walls + roofs).
    pub coverage_before: Option<f64>,
    /// Completeness after.
    pub coverage_after: Option<f64>,
    /// Wall completeness before.
    pub walls_before: Option<f64>,
    /// Wall completeness after.
    pub walls_after: Option<f64>,
    /// Roof completeness before.
    pub roofs_before: Option<f64>,
    /// Roof completeness after.
    pub roofs_after: Option<f64>,
    /// Gap term before, m.
    pub mean_gt_dist_before: Option<f64>,
    /// Gap term after, m.
    pub mean_gt_dist_after: Option<f64>,
}

/// The aerial prior and the merged cloud against the same ground truth.
#[derive(Debug, Clone, Serialize)]
pub struct Evaluation {
    /// Coverage radius, m.
    pub tau: f32,
    /// GT samples.
    pub gt_samples: usize,
    /// The aerial prior.
    pub before: Measured,
    /// Aerial + ground scans.
    pub after: Measured,
    /// Per building, ascending id.
    pub buildings: Vec<BuildingRow>,
}

/// The building points of a cloud moved into the frame of `origin`: label
/// 6 when the cloud has labels, every point otherwise.
pub fn building_points(cloud: &Cloud, origin: [f64; 3]) -> Vec<[f32; 3]> {
    let shift = [0, 1, 2].map(|k| cloud.origin[k] - origin[k]);
    let keep = |i: usize| {
        cloud
            .label
            .as_ref()
            .is_none_or(|l| l.get(i) == Some(&class::BUILDING))
    };
    cloud
        .xyz
        .iter()
        .enumerate()
        .filter(|(i, _)| keep(*i))
        .map(|(_, p)| [0, 1, 2].map(|k| (f64::from(p[k]) + shift[k]) as f32))
        .collect()
}

fn measure(scene: &Scene, gt: &GtSamples, cloud: &Cloud, tau: f32) -> Measured {
    let pts = building_points(cloud, gt.origin);
    Measured {
        points: cloud.len(),
        building_points: pts.len(),
        completeness: completeness(gt, &pts, tau),
        mean_cloud_to_mesh: mean_cloud_to_mesh(scene, &pts),
    }
}

/// Measures `before` (the aerial prior) and `after` (prior + scans) against
/// the scene's building ground truth `gt` (same frame as the scene).
pub fn evaluate(
    scene: &Scene,
    gt: &GtSamples,
    before: &Cloud,
    after: &Cloud,
    tau: f32,
) -> Evaluation {
    let before = measure(scene, gt, before, tau);
    let after = measure(scene, gt, after, tau);
    let buildings = before
        .completeness
        .buildings
        .iter()
        .map(|b| {
            let a = after
                .completeness
                .buildings
                .iter()
                .find(|a| a.building == b.building);
            BuildingRow {
                building: b.building,
                coverage_before: b.all.ratio,
                coverage_after: a.and_then(|a| a.all.ratio),
                walls_before: b.walls.ratio,
                walls_after: a.and_then(|a| a.walls.ratio),
                roofs_before: b.roofs.ratio,
                roofs_after: a.and_then(|a| a.roofs.ratio),
                mean_gt_dist_before: b.mean_gt_distance,
                mean_gt_dist_after: a.and_then(|a| a.mean_gt_distance),
            }
        })
        .collect();
    Evaluation {
        tau,
        gt_samples: gt.len(),
        before,
        after,
        buildings,
    }
}

fn pct(v: Option<f64>) -> String {
    v.map_or_else(|| "–".into(), |v| format!("{:.2} %", v * 100.0))
}

fn metres(v: Option<f64>) -> String {
    v.map_or_else(|| "–".into(), |v| format!("{v:.3} m"))
}

impl Evaluation {
    /// The summary table (the paper's Table 2 rows) as Markdown.
    pub fn summary_markdown(&self) -> String {
        let (b, a) = (&self.before.completeness, &self.after.completeness);
        let mut s = format!(
            "| metric (τ = {} m, {} GT samples) | aerial prior | after ground scans |\n|---|---|---|\n",
            self.tau, self.gt_samples
        );
        let (before, after) = (&self.before, &self.after);
        let rows = [
            (
                "completeness, walls + roofs",
                pct(b.overall.ratio),
                pct(a.overall.ratio),
            ),
            (
                "completeness, walls",
                pct(b.walls.ratio),
                pct(a.walls.ratio),
            ),
            (
                "completeness, roofs",
                pct(b.roofs.ratio),
                pct(a.roofs.ratio),
            ),
            (
                "mean GT → cloud distance (gap term)",
                metres(b.mean_gt_distance),
                metres(a.mean_gt_distance),
            ),
            (
                "mean cloud → mesh distance (accuracy term)",
                metres(before.mean_cloud_to_mesh),
                metres(after.mean_cloud_to_mesh),
            ),
            (
                "building points",
                before.building_points.to_string(),
                after.building_points.to_string(),
            ),
        ];
        for (name, x, y) in rows {
            s.push_str(&format!("| {name} | {x} | {y} |\n"));
        }
        s
    }

    /// The per-building table as Markdown.
    pub fn buildings_markdown(&self) -> String {
        let mut s = String::from(
            "| building | completeness before | after | walls before | walls after | GT → cloud before | after |\n|---|---|---|---|---|---|---|\n",
        );
        for r in &self.buildings {
            s.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} | {} |\n",
                r.building,
                pct(r.coverage_before),
                pct(r.coverage_after),
                pct(r.walls_before),
                pct(r.walls_after),
                metres(r.mean_gt_dist_before),
                metres(r.mean_gt_dist_after)
            ));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::sample_building_surfaces;
    use crate::scene::reference_scene;

    #[test]
    fn adding_the_truth_completes_every_building() {
        let scene = reference_scene(7);
        let gt = sample_building_surfaces(&scene, 1.0);
        // Before: only the roofs' samples; after: every sample.
        let roofs: Vec<[f32; 3]> = gt
            .xyz
            .iter()
            .zip(&gt.kind)
            .filter(|(_, k)| **k == crate::metrics::SurfaceKind::Roof)
            .map(|(p, _)| *p)
            .collect();
        let before = Cloud::from_xyz(roofs);
        let after = Cloud::from_xyz(gt.xyz.clone());
        let e = evaluate(&scene, &gt, &before, &after, 0.25);
        assert!(e.before.completeness.walls.ratio.unwrap() < 0.05);
        assert_eq!(e.after.completeness.overall.ratio, Some(1.0));
        assert!(e.after.mean_cloud_to_mesh.unwrap() < 0.01);
        assert_eq!(e.buildings.len(), scene.building_count());
        assert!(e.buildings.iter().all(|r| r.coverage_after == Some(1.0)));
        let md = e.summary_markdown();
        assert!(md.contains("100.00 %"), "{md}");
    }

    #[test]
    fn labelled_clouds_count_only_building_points() {
        let mut c = Cloud::from_xyz(vec![[0.0; 3], [1.0; 3], [2.0; 3]]);
        c.label = Some(vec![class::BUILDING, class::GROUND, class::BUILDING]);
        c.origin = [10.0, 0.0, 0.0];
        let pts = building_points(&c, [0.0; 3]);
        assert_eq!(pts, vec![[10.0, 0.0, 0.0], [12.0, 2.0, 2.0]]);
    }
}
