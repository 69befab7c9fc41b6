//! Comparing footprints: intersection over union, and matching derived
//! footprints to true ones.

use geo::{Area, BooleanOps, MultiPolygon};
use rayon::prelude::*;

use super::types::Footprint;

/// Intersection area over union area (0 when both are empty).
pub fn iou(a: &MultiPolygon<f64>, b: &MultiPolygon<f64>) -> f64 {
    let inter = a.intersection(b).unsigned_area();
    let union = a.unsigned_area() + b.unsigned_area() - inter;
    if union > 0.0 { inter / union } else { 0.0 }
}

/// One true footprint and the derived footprint that overlaps it most.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootprintMatch {
    /// True building id.
    pub truth: u32,
    /// Derived id overlapping it most; 0 when none overlaps.
    pub derived: u32,
    /// Their IoU (0 when unmatched).
    pub iou: f64,
}

/// For every true footprint (in order), the derived one with the largest
/// overlap area. A derived footprint may match several true ones (merged
/// buildings then show as low IoU).
pub fn match_footprints(derived: &[Footprint], truth: &[Footprint]) -> Vec<FootprintMatch> {
    truth
        .par_iter()
        .map(|t| {
            let tb = t.bounds();
            let best = derived
                .iter()
                .filter(|d| match (tb, d.bounds()) {
                    (Some(a), Some(b)) => {
                        a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3]
                    }
                    _ => false,
                })
                .map(|d| (t.polygon.intersection(&d.polygon).unsigned_area(), d))
                .filter(|(a, _)| *a > 0.0)
                .max_by(|a, b| a.0.total_cmp(&b.0));
            match best {
                Some((_, d)) => FootprintMatch {
                    truth: t.id,
                    derived: d.id,
                    iou: iou(&t.polygon, &d.polygon),
                },
                None => FootprintMatch {
                    truth: t.id,
                    derived: 0,
                    iou: 0.0,
                },
            }
        })
        .collect()
}

/// How derived footprints segment the true buildings.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Segmentation {
    /// True footprints scored.
    pub truth: usize,
    /// Derived footprints.
    pub derived: usize,
    /// True buildings whose best derived footprint has them as its best
    /// true one too, with IoU ≥ 0.5 (found one to one).
    pub one_to_one: usize,
    /// True buildings merged with a neighbour: their best derived footprint
    /// also holds half or more of another true building.
    pub under: usize,
    /// True buildings split: two or more derived footprints each lie
    /// mostly (half or more of their area) inside them.
    pub over: usize,
    /// True buildings no derived footprint overlaps.
    pub missed: usize,
    /// Per true building, the IoU with its best derived footprint (order of `truth`).
    pub iou: Vec<f64>,
}

impl Segmentation {
    /// The `q`-quantile (0–1) of the IoUs, nearest rank.
    pub fn iou_quantile(&self, q: f64) -> f64 {
        let mut v = self.iou.clone();
        v.sort_by(f64::total_cmp);
        if v.is_empty() {
            return 0.0;
        }
        let k = ((q.clamp(0.0, 1.0) * (v.len() - 1) as f64).round()) as usize;
        v[k]
    }

    /// Share of true buildings with IoU ≥ `t`.
    pub fn share_at_least(&self, t: f64) -> f64 {
        let n = self.iou.iter().filter(|&&v| v >= t).count();
        n as f64 / self.iou.len().max(1) as f64
    }
}

/// Scores `derived` against `truth`: one-to-one matches, under- and
/// over-segmentation, the IoU distribution.
pub fn segmentation(derived: &[Footprint], truth: &[Footprint]) -> Segmentation {
    let matches = match_footprints(derived, truth);
    let bounds: Vec<Option<[f64; 4]>> = derived.iter().map(Footprint::bounds).collect();
    // Overlap area of every (truth, derived) pair whose boxes touch.
    let overlaps: Vec<Vec<(usize, f64)>> = truth
        .par_iter()
        .map(|t| {
            let Some(a) = t.bounds() else {
                return Vec::new();
            };
            derived
                .iter()
                .zip(&bounds)
                .enumerate()
                .filter(|(_, (_, b))| {
                    b.is_some_and(|b| a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3])
                })
                .map(|(k, (d, _))| (k, t.polygon.intersection(&d.polygon).unsigned_area()))
                .filter(|(_, area)| *area > 0.0)
                .collect()
        })
        .collect();
    let index: std::collections::HashMap<u32, usize> =
        derived.iter().enumerate().map(|(k, d)| (d.id, k)).collect();
    // Per derived footprint, the true one it overlaps most.
    let mut best_truth = vec![(0.0f64, usize::MAX); derived.len()];
    for (t, row) in overlaps.iter().enumerate() {
        for &(k, a) in row {
            if a > best_truth[k].0 {
                best_truth[k] = (a, t);
            }
        }
    }
    let (mut one_to_one, mut under, mut over, mut missed) = (0, 0, 0, 0);
    for (t, m) in matches.iter().enumerate() {
        let Some(&k) = index.get(&m.derived).filter(|_| m.derived != 0) else {
            missed += 1;
            continue;
        };
        one_to_one += usize::from(best_truth[k].1 == t && m.iou >= 0.5);
        // Another true building with half or more of its area in `k`.
        let merged = overlaps.iter().enumerate().any(|(u, row)| {
            u != t
                && row
                    .iter()
                    .any(|&(j, a)| j == k && a >= 0.5 * truth[u].area())
        });
        under += usize::from(merged);
        let pieces = overlaps[t]
            .iter()
            .filter(|&&(j, a)| a >= 0.5 * derived[j].area())
            .count();
        over += usize::from(pieces >= 2);
    }
    Segmentation {
        truth: truth.len(),
        derived: derived.len(),
        one_to_one,
        under,
        over,
        missed,
        iou: matches.iter().map(|m| m.iou).collect(),
    }
}
