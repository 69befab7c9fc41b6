//! How far a producer's labels agree with themselves in space: each scored
//! point (producer class 2–6) is given the label most of its nearest scored
//! neighbours carry in the same reference, and that guess is scored like a
//! classification. Unclassified, water or wire neighbours do not vote:
//! they are not scored, so they say nothing of what a scored point is. Labels
//! that change from point to point on one surface (a wall tagged building,
//! other and low vegetation in turn) score low here, and no classifier that
//! decides by a point's neighbourhood can reproduce them.

use std::num::NonZeroUsize;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::error::ClassifyError;
use super::report::{ClassReport, is_scored};
use crate::cloud::ColumnLength;
use crate::cloud::class::fold;

/// Most scored points the agreement is measured on; beyond, an evenly
/// spread sample (every n-th), so a 10 M-point tile costs seconds.
pub const MAX_SAMPLED: usize = 200_000;

/// The producer's labels scored against their own neighbours' majority.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LabelCoherence {
    /// Neighbours that vote (the point itself left out).
    pub k: usize,
    /// Scored points the agreement was measured on.
    pub sampled: u64,
    /// The neighbours' majority as a classification of the producer's labels.
    pub report: ClassReport,
}

/// Agreement of `truth` (producer codes, one per point of `xyz`, metres)
/// with the majority of each point's `k` nearest neighbours, for every
/// `k` in `ks`; judged and voting are the points whose class [`is_scored`].
///
/// Ties go to the label of the nearest neighbour among the tied. Points
/// with a non-finite position neither vote nor are judged; fewer than two
/// such points give guesses of unclassified.
pub fn label_coherence(
    xyz: &[[f32; 3]],
    truth: &[u8],
    ks: &[usize],
) -> Result<Vec<LabelCoherence>, ClassifyError> {
    ColumnLength::check("reference labels", xyz.len(), truth.len())?;
    let scored: Vec<usize> = (0..xyz.len())
        .filter(|&i| is_scored(truth[i]) && xyz[i].iter().all(|v| v.is_finite()))
        .collect();
    let stride = scored.len().div_ceil(MAX_SAMPLED).max(1);
    let sample: Vec<usize> = scored.iter().copied().step_by(stride).collect();
    let pts: Vec<[f32; 3]> = scored.iter().map(|&i| xyz[i]).collect();
    let k_max = ks.iter().copied().max().unwrap_or(0);
    let tree = (pts.len() >= 2 && k_max > 0)
        .then(|| ImmutableKdTree::<f32, 3>::new_from_slice(&pts).ok())
        .flatten();
    // Each sampled point's neighbours, nearest first, itself left out.
    let neighbours: Vec<Vec<u8>> = sample
        .par_iter()
        .map(|&i| {
            let Some(tree) = &tree else {
                return Vec::new();
            };
            let n = NonZeroUsize::new((k_max + 1).min(pts.len())).unwrap_or(NonZeroUsize::MIN);
            tree.query(&xyz[i])
                .nearest_n::<SquaredEuclidean<f32>>(n)
                .execute()
                .iter()
                .map(|nb| scored[nb.item as usize])
                .filter(|&j| j != i)
                .take(k_max)
                .map(|j| fold(truth[j]))
                .collect()
        })
        .collect();
    let t: Vec<u8> = sample.iter().map(|&i| truth[i]).collect();
    ks.iter()
        .map(|&k| {
            let guess: Vec<u8> = neighbours
                .iter()
                .map(|near| majority(&near[..k.min(near.len())]))
                .collect();
            Ok(LabelCoherence {
                k,
                sampled: sample.len() as u64,
                report: ClassReport::new(&t, &guess)?,
            })
        })
        .collect()
}

/// The most frequent label of `near` (nearest first); ties go to the one
/// met first. Unclassified (1) for no neighbour.
fn majority(near: &[u8]) -> u8 {
    let mut count = [0u32; 256];
    let mut best = (0u32, crate::cloud::class::UNCLASSIFIED);
    for &c in near {
        count[usize::from(c)] += 1;
        if count[usize::from(c)] > best.0 {
            best = (count[usize::from(c)], c);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::class::{BUILDING, GROUND, VEGETATION};

    /// A 40 × 40 lattice, 0.5 m apart, with the label `f(i, j)`.
    fn lattice(f: impl Fn(usize, usize) -> u8) -> (Vec<[f32; 3]>, Vec<u8>) {
        (0..40)
            .flat_map(|j| (0..40).map(move |i| (i, j)))
            .map(|(i, j)| ([i as f32 * 0.5, j as f32 * 0.5, 0.0], f(i, j)))
            .unzip()
    }

    fn f1(c: &LabelCoherence, class: u8) -> f64 {
        c.report.class(class).map_or(f64::NAN, |m| m.f1)
    }

    #[test]
    fn two_halves_agree_and_alternate_rows_do_not() {
        let (xyz, labels) = lattice(|i, _| if i < 20 { BUILDING } else { VEGETATION });
        let got = label_coherence(&xyz, &labels, &[4, 8]).unwrap();
        assert_eq!(got.len(), 2);
        assert_eq!(got[0].sampled, 1600);
        for c in &got {
            // Only the two columns at the seam can be outvoted.
            assert!(f1(c, BUILDING) > 0.94, "{}", f1(c, BUILDING));
            assert!(f1(c, VEGETATION) > 0.94, "{}", f1(c, VEGETATION));
        }
        // One row building, the next vegetation: a point's four nearest are
        // two of each kind above and below, two of its own beside it.
        let (xyz, labels) = lattice(|_, j| if j % 2 == 0 { BUILDING } else { VEGETATION });
        let got = label_coherence(&xyz, &labels, &[8]).unwrap();
        assert!(f1(&got[0], VEGETATION) < 0.6, "{}", f1(&got[0], VEGETATION));
    }

    #[test]
    fn only_scored_points_are_judged_and_vote() {
        // Two ground points in a ring of unclassified (1) points, which
        // neither vote nor are judged; the building point farther out
        // loses to the other ground point.
        let mut xyz = vec![[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [3.0, 0.0, 0.0]];
        let mut labels = vec![GROUND, GROUND, BUILDING];
        for a in 0..8 {
            let t = a as f32 * std::f32::consts::FRAC_PI_4;
            xyz.push([t.cos(), t.sin(), 0.0]);
            labels.push(1);
        }
        xyz.push([0.05, 0.0, 0.0]);
        labels.push(14);
        xyz.push([f32::NAN, 0.0, 0.0]);
        labels.push(BUILDING);
        let got = label_coherence(&xyz, &labels, &[1, 2]).unwrap();
        assert_eq!(got[0].sampled, 3);
        assert_eq!(got[0].report.points, 3);
        assert_eq!(got[0].report.class(GROUND).map(|m| m.recall), Some(1.0));
        assert_eq!(got[0].report.class(BUILDING).map(|m| m.recall), Some(0.0));
        // With two voters the building point's nearest ground breaks the tie.
        assert_eq!(got[1].report.class(GROUND).map(|m| m.recall), Some(1.0));
    }

    #[test]
    fn ties_go_to_the_nearest_and_bad_input_is_an_error() {
        assert_eq!(majority(&[BUILDING, VEGETATION]), BUILDING);
        assert_eq!(majority(&[VEGETATION, BUILDING, BUILDING]), BUILDING);
        assert_eq!(majority(&[]), 1);
        let (xyz, labels) = lattice(|_, _| GROUND);
        assert!(label_coherence(&xyz, &labels[1..], &[4]).is_err());
        let one = label_coherence(&xyz[..1], &labels[..1], &[4]).unwrap();
        assert_eq!(one[0].report.class(GROUND).map(|m| m.recall), Some(0.0));
    }

    #[test]
    fn large_clouds_are_sampled_evenly() {
        let n = 2 * MAX_SAMPLED + 10;
        let xyz: Vec<[f32; 3]> = (0..n)
            .map(|i| [(i % 1000) as f32 * 0.3, (i / 1000) as f32 * 0.3, 0.0])
            .collect();
        let labels = vec![GROUND; n];
        let got = label_coherence(&xyz, &labels, &[4]).unwrap();
        assert!(got[0].sampled as usize <= MAX_SAMPLED);
        assert!(got[0].sampled as usize > MAX_SAMPLED / 2);
        assert_eq!(got[0].report.class(GROUND).map(|m| m.f1), Some(1.0));
    }
}
