//! The global route (docs/design.md step 6): target points snapped to their
//! nearest reachable node, regions to the nodes inside them, graph distances
//! between all of them, and a tour from the start — the paper's greedy
//! alternation and a nearest-neighbour + 2-opt + Or-opt tour, the shorter one
//! driven.
//!
//! - [`RouteParams`] (`params`), [`RouteError`] (`error`);
//! - `stops`: snapping targets ([`Stop`]); `tour`: the two tour builders on a cost matrix;
//! - `plan`: [`plan`], [`replan`] → [`Route`];
//! - `budget`: how long a route takes ([`route_budget`]), the demo's time
//!   limit that follows the work ([`WorkLimit`]).

mod budget;
mod error;
mod params;
mod plan;
mod stops;
pub(crate) mod tour;

pub use budget::{Budget, BudgetParams, PlannedWork, WorkLimit, route_budget};
pub use error::RouteError;
pub use params::{RouteParams, TourChoice};
pub use plan::{Route, Visited, in_order, plan, replan};
pub use stops::Stop;
