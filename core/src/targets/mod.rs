//! Targets for the ground robot (DESIGN.md step 4): points to stand at and
//! regions to explore. The plain types here are what the detector hands the
//! planner; how they are generated lives beside them.

mod types;

pub use types::{Region, TargetPoint, TargetSet};
