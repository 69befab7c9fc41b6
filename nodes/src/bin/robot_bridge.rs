//! The `robot_bridge` node as its own binary (see `skyground_nodes::node::robot_bridge`).

use std::process::ExitCode;

use skyground_nodes::node::robot_bridge;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(robot_bridge::SPEC, async |rt, _args| {
        robot_bridge::run(rt).await
    })
}
