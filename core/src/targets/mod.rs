//! Targets for the ground robot (docs/design.md step 4): points to stand at and
//! regions to explore. The plain types here are what the detector hands the
//! planner; how they are generated lives beside them.
//!
//! - [`types`] — [`TargetPoint`], [`Region`], [`TargetSet`].
//! - [`params`] — [`TargetParams`]; [`site`]: [`Site`], the grid of where a robot may stand.
//! - [`generate`](mod@generate) — [`generate()`] → targets and [`Dropped`] counts.
//! - [`consolidate`](mod@consolidate) — [`consolidate()`]: one stop for every gap it sees.

pub mod consolidate;
mod from_missing;
pub mod generate;
pub mod params;
pub mod site;
mod types;

pub use consolidate::{Consolidation, consolidate};
pub use from_missing::{BuildingPlan, generate_from_missing};
pub use generate::{Dropped, generate};
pub use params::TargetParams;
pub use site::{Site, SiteError};
pub use types::{Region, TargetPoint, TargetSet};
