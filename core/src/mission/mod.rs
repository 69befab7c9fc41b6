//! The mission's executive as plain state machines (docs/design.md steps
//! 5–7): typed events in, typed commands out, no ROS. Nodes translate
//! messages to [`planner::PlannerEvent`] / [`explorer::ExplorerEvent`] and
//! the commands back to messages.
//!
//! - `protocol`: the status structs every node speaks, and their wire form;
//! - `inspect`: cloud_inspector's /cloud_stats status;
//! - `georef`: /georeference, the local frame's origin and CRS;
//! - `ground`: the one ground graph planner and explorer share, blocked spots included;
//! - `planner`: phases, rounds, retries, restore after a restart, leg cutting;
//! - `kept_round`: the round's targets kept, so a resumed mission finishes it;
//! - `explorer`: when a region starts and ends, when scans count;
//! - `detector`: when detection re-runs on the merged cloud;
//! - `progress`: what a launcher follows of the rounds, and when the loop ends;
//! - `scan_ids`: scans told apart by their stamps, sent against merged;
//! - `watchdog`: the robot's clock watched, a stalled vehicle restarted;
//! - `waiting`: when a planner that lacks an input says so, and what DDS matched;
//! - `quality`: what a mission did per building, as a city model's attributes.

pub mod detector;
pub mod explorer;
pub mod georef;
pub mod ground;
pub mod inspect;
pub mod kept_round;
pub mod planner;
pub mod progress;
pub mod protocol;
pub mod quality;
pub mod scan_ids;
pub mod uav;
pub mod waiting;
pub mod watchdog;

pub use georef::Georeference;
pub use inspect::{CloudStatus, CloudSummary, LabelCount};
pub use protocol::{
    BlockedSpot, BuildingStatus, ExplorerState, ExplorerStatus, Phase, PlannerStatus,
    ProtocolError, VehicleEvent, VehicleStatus, Wire,
};
pub use quality::{Mission, building_attributes};
