//! Every skyground node as a library function, so each runs as its own binary
//! and as `skyground node NAME` (what the demo launcher starts).

pub mod cloud_inspector;
pub mod cloud_publisher;
pub mod completeness_detector;
pub mod global_planner;
pub mod local_explorer;
pub mod scene_classifier;
pub mod target_generator;
pub mod vehicle_sim;

use std::process::ExitCode;

use crate::runtime::{RosArgs, run_with};

/// Names of the nodes `skyground node` can run.
pub const NAMES: &[&str] = &[
    "cloud_publisher",
    "cloud_inspector",
    "scene_classifier",
    "completeness_detector",
    "target_generator",
    "global_planner",
    "local_explorer",
    "vehicle_sim",
];

/// Runs the node called `name` with its ROS arguments; `None` for an unknown name.
pub fn run_by_name(name: &str, ros: RosArgs) -> Option<ExitCode> {
    Some(match name {
        "cloud_publisher" => run_with(cloud_publisher::SPEC, ros, vec![], async |rt, _| {
            cloud_publisher::run(rt).await
        }),
        "cloud_inspector" => run_with(cloud_inspector::SPEC, ros, vec![], async |rt, _| {
            cloud_inspector::run(rt).await
        }),
        "scene_classifier" => run_with(scene_classifier::SPEC, ros, vec![], async |rt, _| {
            scene_classifier::run(rt).await
        }),
        "completeness_detector" => {
            run_with(completeness_detector::SPEC, ros, vec![], async |rt, _| {
                completeness_detector::run(rt).await
            })
        }
        "target_generator" => run_with(target_generator::SPEC, ros, vec![], async |rt, _| {
            target_generator::run(rt).await
        }),
        "global_planner" => run_with(global_planner::SPEC, ros, vec![], async |rt, _| {
            global_planner::run(rt).await
        }),
        "local_explorer" => run_with(local_explorer::SPEC, ros, vec![], async |rt, _| {
            local_explorer::run(rt).await
        }),
        "vehicle_sim" => run_with(vehicle_sim::SPEC, ros, vec![], async |rt, _| {
            vehicle_sim::run(rt).await
        }),
        _ => return None,
    })
}
