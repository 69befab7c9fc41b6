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
