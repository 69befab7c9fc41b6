//! Tunables of the global route, filled from the planner's params YAML.

use serde::{Deserialize, Serialize};

use crate::params::{Checks, ParamError};

/// Which tour the route follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TourChoice {
    /// The shortest of the three tours.
    Shortest,
    /// The paper's alternation of point and region targets by shortest distance.
    Greedy,
    /// Nearest neighbour improved by 2-opt and Or-opt.
    Tsp,
    /// Street by street: the TSP with a cost on every change of street.
    Streets,
}

/// How targets are tied to the graph and toured (docs/design.md step 6).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RouteParams {
    /// A target point farther (xy) than this from every reachable node is unreachable, metres.
    pub max_snap_m: f32,
    /// Which tour to follow.
    pub tour: TourChoice,
    /// Improvement passes of 2-opt + Or-opt at most (each pass is O(n²)).
    pub max_passes: u32,
    /// A point stop is left off the route when every gap it would see is
    /// in view from where the rest of the route drives anyway (the targets'
    /// `sees` test along the route without it), decided when the route is made.
    pub skip_seen: bool,
    /// With `skip_seen`, a view from the way counts for a gap only if it is
    /// at most this many times farther from it than the stop: a drive-by
    /// that merely sees a gap from 20 m at 70° lays a few sparse beam rows
    /// on the wall where the stop, at its standoff before it, covers it.
    pub seen_range_ratio: f32,
    /// With `skip_seen`, and at most this many degrees more oblique than the stop's view.
    pub seen_extra_incidence_deg: f32,
}

impl Default for RouteParams {
    fn default() -> Self {
        Self {
            max_snap_m: 3.0,
            tour: TourChoice::Shortest,
            max_passes: 100,
            skip_seen: false,
            seen_range_ratio: 1.25,
            seen_extra_incidence_deg: 15.0,
        }
    }
}

impl RouteParams {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("route");
        c.positive("max_snap_m", self.max_snap_m)?;
        let ratio = self.seen_range_ratio;
        c.that(
            ratio.is_finite() && ratio >= 1.0,
            "seen_range_ratio",
            ratio,
            "must be finite and ≥ 1",
        )?;
        c.within(
            "seen_extra_incidence_deg",
            self.seen_extra_incidence_deg,
            0.0,
            180.0,
        )?;
        c.within("max_passes", self.max_passes, 0, 100_000)
    }
}
