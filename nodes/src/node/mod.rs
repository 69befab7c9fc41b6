//! Every skyground node as a library function, so each runs as its own binary
//! and as `skyground node NAME` (what the demo launcher starts).

pub mod cloud_inspector;
pub mod cloud_publisher;
pub mod vehicle_sim;

use std::process::ExitCode;

use crate::runtime::{RosArgs, run_with};

/// Names of the nodes `skyground node` can run.
pub const NAMES: &[&str] = &["cloud_publisher", "cloud_inspector", "vehicle_sim"];

/// Runs the node called `name` with its ROS arguments; `None` for an unknown name.
pub fn run_by_name(name: &str, ros: RosArgs) -> Option<ExitCode> {
    Some(match name {
        "cloud_publisher" => run_with(cloud_publisher::SPEC, ros, vec![], async |rt, _| {
            cloud_publisher::run(rt).await
        }),
        "cloud_inspector" => run_with(cloud_inspector::SPEC, ros, vec![], async |rt, _| {
            cloud_inspector::run(rt).await
        }),
        "vehicle_sim" => run_with(vehicle_sim::SPEC, ros, vec![], async |rt, _| {
            vehicle_sim::run(rt).await
        }),
        _ => return None,
    })
}
