//! Before against after: which buildings the prior's models got wrong, and
//! whether the merged cloud's models come closer to the truth there.

use serde::Serialize;

use super::evaluate::ModelEvaluation;

/// A prior model whose mean symmetric distance to the truth exceeds this
/// (m) is "off": the walls the prior missed changed its shape. Below it the
/// difference is the scanners' noise (the reference's boxes, whose roof
/// edges stand exactly over their walls, score 0.000–0.001 m from the
/// prior alone).
pub const PRIOR_OFF_M: f64 = 0.01;

/// The verdict of [`compare`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BeforeAfter {
    /// The threshold used, m.
    pub prior_off_m: f64,
    /// Buildings whose prior model was off.
    pub prior_off: Vec<u32>,
    /// Of those, the ones whose model after is not closer (or missing).
    pub not_improved: Vec<u32>,
    /// On the other buildings, the largest rise of the mean distance, m.
    pub largest_rise_elsewhere: Option<f64>,
}

/// Compares two evaluations of the same scene building by building.
pub fn compare(before: &ModelEvaluation, after: &ModelEvaluation, off_m: f64) -> BeforeAfter {
    let mut out = BeforeAfter {
        prior_off_m: off_m,
        prior_off: Vec::new(),
        not_improved: Vec::new(),
        largest_rise_elsewhere: None,
    };
    for b in &before.buildings {
        let a = after
            .buildings
            .iter()
            .find(|a| a.building == b.building)
            .and_then(|a| a.distance.mean);
        match (b.distance.mean, a) {
            (Some(mb), a) if mb > off_m => {
                out.prior_off.push(b.building);
                if a.is_none_or(|ma| ma >= mb) {
                    out.not_improved.push(b.building);
                }
            }
            (Some(mb), Some(ma)) => {
                let rise = ma - mb;
                if out.largest_rise_elsewhere.is_none_or(|r| rise > r) {
                    out.largest_rise_elsewhere = Some(rise);
                }
            }
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reconstruct::{DistanceStats, ModelScore};

    fn eval(means: &[(u32, Option<f64>)]) -> ModelEvaluation {
        ModelEvaluation {
            buildings: means
                .iter()
                .map(|&(building, mean)| ModelScore {
                    building,
                    models: vec![building],
                    distance: DistanceStats {
                        mean,
                        rmse: mean,
                        p95: mean,
                    },
                    gt_to_model: mean,
                    model_to_gt: mean,
                    roof_error: None,
                    footprint_iou: None,
                    watertight: true,
                    valid: true,
                    samples: Vec::new(),
                })
                .collect(),
            distance: DistanceStats::default(),
            roof_error: None,
            models: means.len(),
            all_watertight: true,
            all_valid: true,
            without_model: Vec::new(),
            unmatched_models: Vec::new(),
        }
    }

    #[test]
    fn off_buildings_must_come_closer_and_the_rest_report_their_noise() {
        let before = eval(&[
            (1, Some(0.5)),
            (2, Some(0.0002)),
            (3, Some(0.08)),
            (4, Some(0.2)),
        ]);
        let after = eval(&[(1, Some(0.2)), (2, Some(0.003)), (3, Some(0.09)), (4, None)]);
        let c = compare(&before, &after, PRIOR_OFF_M);
        assert_eq!(c.prior_off, vec![1, 3, 4]);
        assert_eq!(c.not_improved, vec![3, 4], "3 got worse, 4 lost its model");
        let rise = c.largest_rise_elsewhere.unwrap();
        assert!((rise - 0.0028).abs() < 1e-12, "{rise}");
        let none_off = compare(&after, &after, 1.0);
        assert!(none_off.prior_off.is_empty() && none_off.not_improved.is_empty());
        assert_eq!(none_off.largest_rise_elsewhere, Some(0.0));
    }
}
