//! The global route (docs/design.md step 6): target points snapped to their
//! nearest reachable node, regions to the nodes inside them, graph distances
//! between all of them, and a tour from the start — the paper's greedy
//! alternation and a nearest-neighbour + 2-opt + Or-opt tour, the shorter one
//! driven.
//!
//! - [`RouteParams`] (`params`), [`RouteError`] (`error`);
//! - `stops`: snapping targets ([`Stop`]); `tour`: the two tour builders on a cost matrix;
//! - `plan`: [`plan`], [`replan`] → [`Route`];
//! - `set_downs`: more places to set the robot down when one piece of
//!   ground does not reach every target ([`plan_set_downs`]), and the way
//!   out for a robot its blocked spots cut off ([`way_out`]);
//! - `drive_by`: point stops whose gaps the rest of the route sees anyway,
//!   taken out before the vehicle sets off ([`drop_seen_on_the_way`]);
//! - `budget`: how long a route takes ([`route_budget`]), the demo's time
//!   limit that follows the work ([`WorkLimit`]).

mod budget;
mod drive_by;
mod error;
mod params;
mod plan;
mod set_downs;
mod stops;
pub(crate) mod tour;

pub use budget::{Budget, BudgetParams, PlannedWork, WorkLimit, route_budget};
pub use drive_by::{DriveBy, drop_seen_on_the_way};
pub use error::RouteError;
pub use params::{RouteParams, TourChoice};
pub use plan::{Route, Visited, plan, replan};
pub use set_downs::{
    Ground, PIECES_TRIED, SetDown, SetDowns, WAY_OUT_MAX_M, next_set_down, plan_set_downs, way_out,
};
pub use stops::Stop;
