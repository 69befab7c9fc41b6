//! The `uav_planner` node as its own binary (see `skyground_nodes::node::uav_planner`).

use std::process::ExitCode;

use skyground_nodes::node::uav_planner;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(uav_planner::SPEC, async |rt, _args| {
        uav_planner::run(rt).await
    })
}
