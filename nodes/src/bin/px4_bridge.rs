//! The `px4_bridge` node as its own binary (see `skyground_nodes::node::px4_bridge`).

use std::process::ExitCode;

use skyground_nodes::node::px4_bridge;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(px4_bridge::SPEC, async |rt, _args| {
        px4_bridge::run(rt).await
    })
}
