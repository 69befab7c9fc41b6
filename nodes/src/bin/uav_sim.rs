//! The `uav_sim` node as its own binary (see `skyground_nodes::node::uav_sim`).

use std::process::ExitCode;

use skyground_nodes::node::uav_sim;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(uav_sim::SPEC, async |rt, _args| uav_sim::run(rt).await)
}
