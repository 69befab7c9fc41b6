//! The `vehicle_sim` node as its own binary (see `skyground_nodes::node::vehicle_sim`).

use std::process::ExitCode;

use skyground_nodes::node::vehicle_sim;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(vehicle_sim::SPEC, async |rt, _args| {
        vehicle_sim::run(rt).await
    })
}
