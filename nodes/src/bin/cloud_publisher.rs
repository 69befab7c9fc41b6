//! The `cloud_publisher` node as its own binary (see `skyground_nodes::node::cloud_publisher`).

use std::process::ExitCode;

use skyground_nodes::node::cloud_publisher;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(cloud_publisher::SPEC, async |rt, _args| {
        cloud_publisher::run(rt).await
    })
}
