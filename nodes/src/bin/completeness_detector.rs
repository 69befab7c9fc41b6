//! The `completeness_detector` node as its own binary (see `skyground_nodes::node::completeness_detector`).

use std::process::ExitCode;

use skyground_nodes::node::completeness_detector;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(completeness_detector::SPEC, async |rt, _args| {
        completeness_detector::run(rt).await
    })
}
