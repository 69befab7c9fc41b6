//! Before/after evaluation of a mission (docs/design.md step 9, the paper's
//! Table 2): completeness and both distance terms for the aerial prior and
//! for the merged cloud, overall and per building.

use serde::Serialize;

use super::accuracy::{cloud_to_mesh_distances, mean_cloud_to_mesh};
use super::completeness::{CompletenessReport, completeness, report_from_distances};
use super::gt::GtSamples;
use super::nearest::nearest_distances;
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

/// A cloud measured as its points arrive (the mission's merged cloud: the
/// prior, then each round's scans), so that the last measurement costs only
/// the last points: per GT sample the nearest distance so far, and the sum
/// of the points' distances to the mesh. Equal to [`Measured`] of the whole.
#[derive(Debug, Clone)]
pub struct MeasureSoFar {
    tau: f32,
    dist: Vec<f32>,
    points: usize,
    building_points: usize,
    finite_points: usize,
    mesh_sum: f64,
    mesh_n: usize,
}

impl MeasureSoFar {
    /// Nothing measured yet against `gt` with coverage radius `tau`.
    pub fn new(gt: &GtSamples, tau: f32) -> Self {
        Self {
            tau,
            dist: vec![f32::INFINITY; gt.len()],
            points: 0,
            building_points: 0,
            finite_points: 0,
            mesh_sum: 0.0,
            mesh_n: 0,
        }
    }

    /// Adds a cloud's points (its building points count, as in [`evaluate`]).
    pub fn add(&mut self, scene: &Scene, gt: &GtSamples, cloud: &Cloud) {
        let pts = building_points(cloud, gt.origin);
        self.points += cloud.len();
        self.building_points += pts.len();
        self.finite_points += pts
            .iter()
            .filter(|p| p.iter().all(|v| v.is_finite()))
            .count();
        if pts.is_empty() {
            return;
        }
        for (d, n) in self.dist.iter_mut().zip(nearest_distances(&gt.xyz, &pts)) {
            *d = d.min(n);
        }
        for d in cloud_to_mesh_distances(scene, &pts) {
            if d.is_finite() {
                self.mesh_sum += f64::from(d);
                self.mesh_n += 1;
            }
        }
    }

    /// The measurement of everything added so far.
    pub fn measured(&self, gt: &GtSamples) -> Measured {
        Measured {
            points: self.points,
            building_points: self.building_points,
            completeness: report_from_distances(gt, &self.dist, self.tau, self.finite_points),
            mean_cloud_to_mesh: (self.mesh_n > 0).then(|| self.mesh_sum / self.mesh_n as f64),
        }
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
    compare(
        tau,
        gt.len(),
        measure(scene, gt, before, tau),
        measure(scene, gt, after, tau),
    )
}

/// The evaluation of two measurements against the same `gt_samples` samples.
pub fn compare(tau: f32, gt_samples: usize, before: Measured, after: Measured) -> Evaluation {
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
        gt_samples,
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
    fn measured_in_parts_equals_measured_whole() {
        let scene = reference_scene(7);
        let gt = sample_building_surfaces(&scene, 1.0);
        // Three arrivals: the roofs, half the walls (offset 0.2 m, so the
        // distances are not all 0), the rest.
        let shifted: Vec<[f32; 3]> = gt.xyz.iter().map(|p| [p[0] + 0.2, p[1], p[2]]).collect();
        let n = shifted.len();
        let parts = [
            &shifted[..n / 3],
            &shifted[n / 3..2 * n / 3],
            &shifted[2 * n / 3..],
        ];
        let mut so_far = MeasureSoFar::new(&gt, 0.25);
        for part in parts {
            so_far.add(&scene, &gt, &Cloud::from_xyz(part.to_vec()));
        }
        let whole = measure(&scene, &gt, &Cloud::from_xyz(shifted.clone()), 0.25);
        let parts = so_far.measured(&gt);
        assert_eq!(parts.points, whole.points);
        assert_eq!(parts.building_points, whole.building_points);
        let (p, w) = (&parts.completeness, &whole.completeness);
        assert_eq!(p.overall.ratio, w.overall.ratio);
        assert_eq!(p.walls.ratio, w.walls.ratio);
        assert_eq!(p.observed_points, w.observed_points);
        let close = |a: Option<f64>, b: Option<f64>| (a.unwrap() - b.unwrap()).abs() < 1e-9;
        assert!(close(p.mean_gt_distance, w.mean_gt_distance));
        assert!(close(parts.mean_cloud_to_mesh, whole.mean_cloud_to_mesh));
        assert!(parts.mean_cloud_to_mesh.unwrap() > 0.01);
        assert!(
            p.buildings
                .iter()
                .zip(&w.buildings)
                .all(|(a, b)| a.all.ratio == b.all.ratio)
        );
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
