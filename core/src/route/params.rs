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
    /// A point stop the vehicle has already driven past this close (xy, m)
    /// is dropped: its 360° LiDAR saw from there what it would see at the
    /// stop. 0 (the default: no gain measured) keeps every stop.
    pub skip_passed_m: f32,
    /// A point stop is dropped once every gap it would see was in view
    /// from where the vehicle drove (the targets' `sees` test on the
    /// driven positions); the rest of the round follows the planned order.
    /// Off by default: on the reference it drove more (docs/profile.md).
    pub skip_seen: bool,
}

impl Default for RouteParams {
    fn default() -> Self {
        Self {
            max_snap_m: 3.0,
            tour: TourChoice::Shortest,
            max_passes: 100,
            skip_passed_m: 0.0,
            skip_seen: false,
        }
    }
}

impl RouteParams {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("route");
        c.positive("max_snap_m", self.max_snap_m)?;
        c.non_negative("skip_passed_m", self.skip_passed_m)?;
        c.that(
            self.max_passes <= 100_000,
            "max_passes",
            self.max_passes,
            "must be at most 100000",
        )
    }
}
