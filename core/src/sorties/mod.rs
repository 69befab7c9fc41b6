//! The drone's share of the work (issue 52 part 3, library): viewpoints
//! around the gaps no ground stop sees (candidates at standoff along each
//! gap's normal, checked against the airspace and by sight lines over the
//! prior's height map, then a greedy set cover as `targets::consolidate`
//! does for ground stops), and sorties: a TSP tour of the viewpoints from
//! home, cut so each sortie comes home within the battery. ROS-free.

mod params;
mod tour;
mod viewpoints;

pub use params::SortieParams;
pub use tour::{Sortie, leg, sorties};
pub use viewpoints::{candidates, cover, sees};

use serde::{Deserialize, Serialize};

use crate::airspace::Airspace;
use crate::missing::MissingPoint;
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
    Ok(SortiePlan {
        viewpoints,
        sorties,
        unreachable,
        seen,
    })
}

#[cfg(test)]
mod tests;
