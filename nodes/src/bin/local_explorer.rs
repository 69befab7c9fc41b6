//! The `local_explorer` node as its own binary (see `skyground_nodes::node::local_explorer`).

use std::process::ExitCode;

use skyground_nodes::node::local_explorer;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(local_explorer::SPEC, async |rt, _args| {
        local_explorer::run(rt).await
    })
}
