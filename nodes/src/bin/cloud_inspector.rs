//! The `cloud_inspector` node as its own binary (see `skyground_nodes::node::cloud_inspector`).

use std::process::ExitCode;

use skyground_nodes::node::cloud_inspector;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(cloud_inspector::SPEC, async |rt, _args| {
        cloud_inspector::run(rt).await
    })
}
