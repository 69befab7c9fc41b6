//! The `global_planner` node as its own binary (see `skyground_nodes::node::global_planner`).

use std::process::ExitCode;

use skyground_nodes::node::global_planner;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(global_planner::SPEC, async |rt, _args| {
        global_planner::run(rt).await
    })
}
