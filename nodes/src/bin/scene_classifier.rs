//! The `scene_classifier` node as its own binary (see `skyground_nodes::node::scene_classifier`).

use std::process::ExitCode;

use skyground_nodes::node::scene_classifier;
use skyground_nodes::runtime::run_node;

fn main() -> ExitCode {
    run_node(scene_classifier::SPEC, async |rt, _args| {
        scene_classifier::run(rt).await
    })
}
