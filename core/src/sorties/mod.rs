//! The drone's share of the work (issue 52 part 3, library): viewpoints
//! around the gaps no ground stop sees (candidates at standoff along each
//! gap's normal, checked against the airspace and by sight lines over the
//! prior's height map, then a greedy set cover as `targets::consolidate`
//! does for ground stops), and sorties: a TSP tour of the viewpoints from
//! home, cut so each sortie comes home within the battery. ROS-free.

mod assign;
mod params;
mod tour;
mod viewpoints;

pub use assign::{GroundView, for_the_drone};
pub use params::SortieParams;
pub use tour::{Sortie, leg, sorties, take_off, why_unreachable};
pub use viewpoints::{candidates, cover, sees};

use serde::{Deserialize, Serialize};

use crate::airspace::{Airspace, AirspaceError, AirspaceRules, Geofence};
use crate::cloud::Cloud;
use crate::missing::MissingPoint;
use crate::mission::uav::UavPlan;
use crate::params::ParamError;
use crate::vehicle::multirotor::MultirotorConfig;

/// The drone's plan: its viewpoints, its sorties, what it sees.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SortiePlan {
    /// The viewpoints kept (body centre, local frame).
    pub viewpoints: Vec<[f32; 3]>,
    /// The flights that visit them.
    pub sorties: Vec<Sortie>,
    /// Viewpoints no sortie reaches.
    pub unreachable: Vec<usize>,
    /// Why the first of them is unreachable (`None`: every one is reached).
    pub why_unreachable: Option<String>,
    /// Per gap given, whether a kept viewpoint sees it.
    pub seen: Vec<bool>,
}

/// Plans the drone's viewpoints and sorties for the gaps `missing` (those
/// the ground robot leaves: no ground stop sees them or none is reachable).
pub fn plan(
    missing: &[MissingPoint],
    airspace: &Airspace,
    cfg: &MultirotorConfig,
    p: &SortieParams,
) -> Result<SortiePlan, ParamError> {
    p.validate()?;
    cfg.validate()?;
    let cands = candidates(missing, airspace, p);
    let (kept, seen) = cover(&cands, missing, airspace, p, cfg.sensor_drop);
    let viewpoints: Vec<[f32; 3]> = kept.iter().map(|&k| cands[k]).collect();
    let (sorties, unreachable) = sorties(airspace, cfg, &viewpoints, p.hover_s);
    let why_unreachable = unreachable
        .first()
        .map(|&v| why_unreachable(airspace, cfg, viewpoints[v], p.hover_s));
    Ok(SortiePlan {
        viewpoints,
        sorties,
        unreachable,
        why_unreachable,
        seen,
    })
}

/// The drone's share of a detection: the airspace over `prior` (inside
/// `fence` when one is given) with the drone standing at `home`, the gaps
/// no ground stop reached from `ground_start` sees, and the sorties that
/// see them; `UavPlan` counts it.
pub fn for_detection(
    prior: &Cloud,
    missing: &[MissingPoint],
    (home, ground_start): ([f32; 3], [f32; 2]),
    (cfg, rules, fence): (&MultirotorConfig, &AirspaceRules, Option<&Geofence>),
    (p, view): (&SortieParams, &GroundView),
) -> Result<(SortiePlan, UavPlan), AirspaceError> {
    view.validate()?;
    let mut airspace = Airspace::from_prior(prior, *rules, cfg.radius, home)?;
    if let Some(f) = fence {
        airspace = airspace.with_fence(f.clone());
    }
    let reach = airspace.ground_reach(ground_start, view.max_step_m);
    let drone = for_the_drone(missing, &airspace, &reach, view);
    let theirs: Vec<MissingPoint> = missing
        .iter()
        .zip(&drone)
        .filter(|&(_, &d)| d)
        .map(|(m, _)| *m)
        .collect();
    let plan = plan(&theirs, &airspace, cfg, p)?;
    let counts = UavPlan {
        gaps: missing.len() as u32,
        drone_gaps: theirs.len() as u32,
        seen: plan.seen.iter().filter(|&&s| s).count() as u32,
        viewpoints: plan.viewpoints.len() as u32,
        sorties: plan.sorties.len() as u32,
        unreachable: plan.unreachable.len() as u32,
        // An empty float sum is −0.0: + 0.0 keeps "-0 s" out of the logs.
        flight_s: plan
            .sorties
            .iter()
            .map(|s| f64::from(s.flight_s))
            .sum::<f64>()
            + 0.0,
        refused: String::new(),
    };
    Ok((plan, counts))
}

#[cfg(test)]
mod tests;
