//! The `target_generator` node as its own binary (see `skyground_nodes::node::target_generator`).

use std::process::ExitCode;

use skyground_nodes::node::target_generator;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(target_generator::SPEC, async |rt, _args| {
        target_generator::run(rt).await
    })
}
