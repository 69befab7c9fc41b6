//! What the points look like where a producer's classes and ours part.
//!
//! For each pairing of the producer's class and ours among vegetation and
//! building, the points' median planarity (a 1.5 m sphere, the forest's own
//! `r1_planarity`), the share from pulses that gave several returns and the
//! median height above the ground. Beside the points both call alike it
//! says which side a disputed point resembles: a crown a producer drew
//! into a building's footprint has a crown's shape and echoes; a roof we
//! missed has a roof's. And where both call a roof, whether the disputed
//! point stands well above it: a crown over the house, which a label taken
//! from a footprint polygon calls building.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use serde::{Deserialize, Serialize};

use super::error::ClassifyError;
use crate::cloud::ColumnLength;
use crate::cloud::class::{BUILDING, VEGETATION, fold};
use crate::features::{Echoes, FeatureParams, R1_PLANARITY, compute_subset};

/// Most points profiled per pairing; beyond, an evenly spread sample.
pub const MAX_PER_PAIR: usize = 5_000;

/// A point stands over an agreed roof when it is more than this (m) above
/// the highest point both call building within [`ROOF_REACH_M`] in plan:
/// higher than a chimney or a parapet (roof_check's `above_roof_m`).
pub const OVER_ROOF_M: f32 = 2.0;

/// Plan radius (m) in which the agreed roof under a point is looked for.
pub const ROOF_REACH_M: f32 = 1.0;

/// The shape of the points one pairing of classes holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairShape {
    /// The producer's class (3–5 folded to 5).
    pub producer: u8,
    /// Ours.
    pub ours: u8,
    /// Points of the pairing.
    pub points: u64,
    /// Points profiled (all, or an evenly spread sample).
    pub sampled: u64,
    /// Median planarity of the 1.5 m neighbourhood (0 scattered … 1 a plane).
    pub planarity_median: f32,
    /// Share of the points whose pulse gave several returns; `None`
    /// without echo information.
    pub multiple_returns_share: Option<f32>,
    /// Median height above the ground model, metres.
    pub hag_median_m: f32,
    /// Share of the points standing more than [`OVER_ROOF_M`] above the
    /// highest point both call building within [`ROOF_REACH_M`] in plan
    /// (a crown over a roof); `None` when no point is called building by
    /// both.
    pub over_agreed_roof_share: Option<f32>,
}

/// The four pairings of vegetation and building (the producer's class
/// first), each profiled on up to [`MAX_PER_PAIR`] points; pairings with
/// no point are left out. `hag`: height above the ground model per point
/// (metres); `params`: the model's feature parameters.
pub fn shapes_by_pairing(
    xyz: &[[f32; 3]],
    hag: &[f32],
    echoes: Option<Echoes<'_>>,
    truth: &[u8],
    ours: &[u8],
    params: &FeatureParams,
) -> Result<Vec<PairShape>, ClassifyError> {
    for (what, got) in [
        ("hag", hag.len()),
        ("reference labels", truth.len()),
        ("labels", ours.len()),
    ] {
        ColumnLength::check(what, xyz.len(), got)?;
    }
    let pairs = [
        (BUILDING, BUILDING),
        (BUILDING, VEGETATION),
        (VEGETATION, VEGETATION),
        (VEGETATION, BUILDING),
    ];
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); pairs.len()];
    for (i, (&t, &o)) in truth.iter().zip(ours).enumerate() {
        if let Some(k) = pairs.iter().position(|&p| p == (fold(t), fold(o))) {
            members[k].push(i);
        }
    }
    let samples: Vec<Vec<usize>> = members
        .iter()
        .map(|m| {
            let stride = m.len().div_ceil(MAX_PER_PAIR).max(1);
            m.iter().copied().step_by(stride).collect()
        })
        .collect();
    let rows: Vec<usize> = samples.iter().flatten().copied().collect();
    if rows.is_empty() {
        return Ok(Vec::new());
    }
    let features = compute_subset(xyz, hag, echoes, &rows, params)?;
    let roofs = AgreedRoofs::new(xyz, truth, ours);
    let mut out = Vec::new();
    let mut at = 0;
    for ((&(producer, ours), all), sample) in pairs.iter().zip(&members).zip(&samples) {
        if sample.is_empty() {
            continue;
        }
        let plan: Vec<f32> = (at..at + sample.len())
            .map(|r| features.row(r)[R1_PLANARITY])
            .collect();
        at += sample.len();
        let heights: Vec<f32> = sample.iter().map(|&i| hag[i]).collect();
        let multiple = echoes.as_ref().map(|e| {
            sample.iter().filter(|&&i| e.is_multiple(i)).count() as f32 / sample.len() as f32
        });
        out.push(PairShape {
            producer,
            ours,
            points: all.len() as u64,
            sampled: sample.len() as u64,
            planarity_median: median(plan),
            multiple_returns_share: multiple,
            hag_median_m: median(heights),
            over_agreed_roof_share: roofs.as_ref().map(|r| {
                sample.iter().filter(|&&i| r.is_over(xyz[i])).count() as f32 / sample.len() as f32
            }),
        });
    }
    Ok(out)
}

/// The points both call building, in plan, with their heights.
struct AgreedRoofs {
    tree: ImmutableKdTree<f32, 2>,
    z: Vec<f32>,
}

impl AgreedRoofs {
    /// `None` when no finite point is building in both labellings.
    fn new(xyz: &[[f32; 3]], truth: &[u8], ours: &[u8]) -> Option<Self> {
        let (plan, z): (Vec<[f32; 2]>, Vec<f32>) = xyz
            .iter()
            .zip(truth.iter().zip(ours))
            .filter(|(p, (t, o))| {
                fold(**t) == BUILDING && **o == BUILDING && p.iter().all(|v| v.is_finite())
            })
            .map(|(p, _)| ([p[0], p[1]], p[2]))
            .unzip();
        if plan.is_empty() {
            return None;
        }
        let tree = ImmutableKdTree::<f32, 2>::new_from_slice(&plan).ok()?;
        Some(Self { tree, z })
    }

    /// Whether `p` stands more than [`OVER_ROOF_M`] above the highest
    /// agreed building point within [`ROOF_REACH_M`] in plan.
    fn is_over(&self, p: [f32; 3]) -> bool {
        let top = self
            .tree
            .query(&[p[0], p[1]])
            .within::<SquaredEuclidean<f32>>(ROOF_REACH_M * ROOF_REACH_M)
            .unsorted()
            .execute()
            .iter()
            .filter_map(|nb| self.z.get(nb.item as usize))
            .fold(f32::NEG_INFINITY, |a, &b| a.max(b));
        top.is_finite() && p[2] > top + OVER_ROOF_M
    }
}

/// The profiles as a table, one pairing a line, for a terminal.
pub fn table(shapes: &[PairShape]) -> String {
    let name = |c: u8| {
        if c == BUILDING {
            "building"
        } else {
            "vegetation"
        }
    };
    let mut s = format!(
        "{:<24} {:>9} {:>10} {:>16} {:>14} {:>15}\n",
        "producer -> ours", "points", "planarity", "several returns", "height", "over a roof"
    );
    let share = |v: Option<f32>| v.map_or_else(|| "-".to_string(), |v| format!("{v:.2}"));
    for p in shapes {
        s += &format!(
            "{:<24} {:>9} {:>10.2} {:>16} {:>12.1} m {:>15}\n",
            format!("{} -> {}", name(p.producer), name(p.ours)),
            p.points,
            p.planarity_median,
            share(p.multiple_returns_share),
            p.hag_median_m,
            share(p.over_agreed_roof_share)
        );
    }
    s
}

/// Median of finite values; NaN when there are none.
fn median(mut v: Vec<f32>) -> f32 {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return f32::NAN;
    }
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f32::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat roof 10 m × 10 m at 6 m and a crown of scattered points
    /// beside it, both 0.25 m apart; the crown's pulses give two returns.
    fn roof_and_crown() -> (Vec<[f32; 3]>, Vec<f32>, Vec<u8>) {
        let mut xyz = Vec::new();
        let mut multi = Vec::new();
        for i in 0..40 {
            for j in 0..40 {
                xyz.push([i as f32 * 0.25, j as f32 * 0.25, 6.0]);
                multi.push(1);
                // A hash, not a pattern: the crown's heights scatter.
                let h = ((i * 7919 + j * 104_729) % 97) as f32 / 97.0;
                xyz.push([20.0 + i as f32 * 0.25, j as f32 * 0.25, 4.0 + 4.0 * h]);
                multi.push(2);
            }
        }
        let hag = xyz.iter().map(|p| p[2]).collect();
        (xyz, hag, multi)
    }

    #[test]
    fn a_disputed_crown_reads_as_a_crown() {
        let (xyz, hag, multi) = roof_and_crown();
        let n = xyz.len();
        let returns = vec![1u8; n];
        let echoes = Echoes {
            return_number: &returns,
            number_of_returns: &multi,
        };
        // The producer calls the roof and a strip of the crown building;
        // we call the crown vegetation throughout.
        let truth: Vec<u8> = xyz
            .iter()
            .map(|p| if p[0] < 12.0 { BUILDING } else { 4 })
            .collect();
        let truth: Vec<u8> = truth
            .iter()
            .zip(&xyz)
            .map(|(&t, p)| {
                if p[0] >= 20.0 && p[0] < 22.0 {
                    BUILDING
                } else {
                    t
                }
            })
            .collect();
        let ours: Vec<u8> = xyz
            .iter()
            .map(|p| if p[0] < 12.0 { BUILDING } else { VEGETATION })
            .collect();
        let s = shapes_by_pairing(
            &xyz,
            &hag,
            Some(echoes),
            &truth,
            &ours,
            &FeatureParams::default(),
        )
        .unwrap();
        let get = |p: u8, o: u8| s.iter().find(|x| x.producer == p && x.ours == o).unwrap();
        let (agreed_roof, disputed, agreed_crown) = (
            get(BUILDING, BUILDING),
            get(BUILDING, VEGETATION),
            get(VEGETATION, VEGETATION),
        );
        assert_eq!(
            agreed_roof.points + disputed.points + agreed_crown.points,
            n as u64
        );
        assert!(
            s.iter()
                .all(|x| !(x.producer == VEGETATION && x.ours == BUILDING))
        );
        assert!(agreed_roof.planarity_median > 0.9, "{agreed_roof:?}");
        assert!(disputed.planarity_median < 0.6, "{disputed:?}");
        assert_eq!(disputed.multiple_returns_share, Some(1.0));
        assert_eq!(agreed_roof.multiple_returns_share, Some(0.0));
        assert!((agreed_roof.hag_median_m - 6.0).abs() < 1e-6);
        let t = table(&s);
        assert!(t.contains("building -> vegetation"), "{t}");
        // Without echoes the share is unknown, not 0.
        let s =
            shapes_by_pairing(&xyz, &hag, None, &truth, &ours, &FeatureParams::default()).unwrap();
        assert!(s.iter().all(|x| x.multiple_returns_share.is_none()));
    }

    #[test]
    fn a_crown_over_a_roof_both_call_building_is_told_apart_from_the_roof() {
        // A roof at 6 m both call building; over its east half, a crown 3–7 m
        // above it that the producer's footprint calls building and we call
        // vegetation; and a crown with no roof beneath, beside the house.
        let mut xyz = Vec::new();
        let (mut truth, mut ours) = (Vec::new(), Vec::new());
        for i in 0..40 {
            for j in 0..40 {
                let (x, y) = (i as f32 * 0.25, j as f32 * 0.25);
                xyz.push([x, y, 6.0]);
                truth.push(BUILDING);
                ours.push(BUILDING);
                let h = ((i * 7919 + j * 104_729) % 97) as f32 / 97.0;
                if x >= 5.0 {
                    xyz.push([x, y, 9.0 + 4.0 * h]);
                    truth.push(BUILDING);
                    ours.push(VEGETATION);
                }
                xyz.push([30.0 + x, y, 4.0 + 4.0 * h]);
                truth.push(BUILDING);
                ours.push(VEGETATION);
            }
        }
        let hag: Vec<f32> = xyz.iter().map(|p| p[2]).collect();
        let s =
            shapes_by_pairing(&xyz, &hag, None, &truth, &ours, &FeatureParams::default()).unwrap();
        let get = |p: u8, o: u8| s.iter().find(|x| x.producer == p && x.ours == o).unwrap();
        assert_eq!(get(BUILDING, BUILDING).over_agreed_roof_share, Some(0.0));
        // 800 points over the roof of 2,400 disputed.
        let disputed = get(BUILDING, VEGETATION);
        let share = disputed.over_agreed_roof_share.unwrap();
        assert!((share - 1.0 / 3.0).abs() < 0.01, "{disputed:?}");
        assert!(table(&s).contains("0.33"), "{}", table(&s));
        // Nothing both call building: the share is unknown.
        let s = shapes_by_pairing(
            &xyz,
            &hag,
            None,
            &truth,
            &vec![VEGETATION; xyz.len()],
            &FeatureParams::default(),
        )
        .unwrap();
        assert!(s.iter().all(|x| x.over_agreed_roof_share.is_none()));
    }

    #[test]
    fn large_pairings_are_sampled_and_bad_input_is_refused() {
        // A roof of 80 × 80 points: more than one pairing profiles.
        let xyz: Vec<[f32; 3]> = (0..6400)
            .map(|k| [(k % 80) as f32 * 0.25, (k / 80) as f32 * 0.25, 6.0])
            .collect();
        let hag = vec![6.0; xyz.len()];
        let truth = vec![BUILDING; xyz.len()];
        let s =
            shapes_by_pairing(&xyz, &hag, None, &truth, &truth, &FeatureParams::default()).unwrap();
        assert_eq!(s.len(), 1);
        assert_eq!(s[0].points, xyz.len() as u64);
        assert!(s[0].sampled as usize <= MAX_PER_PAIR && s[0].sampled > 3000);
        let short = &truth[..10];
        assert!(
            shapes_by_pairing(&xyz, &hag, None, short, &truth, &FeatureParams::default()).is_err()
        );
        // No vegetation or building at all: nothing to profile.
        let ground = vec![2u8; xyz.len()];
        let s = shapes_by_pairing(
            &xyz,
            &hag,
            None,
            &ground,
            &ground,
            &FeatureParams::default(),
        )
        .unwrap();
        assert!(s.is_empty());
    }
}
