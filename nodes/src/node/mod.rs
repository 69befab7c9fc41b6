//! Every skyground node as a library function, so each runs as its own binary
//! and as `skyground node NAME` (what the demo launcher starts).

pub mod cloud_inspector;
pub mod cloud_publisher;
pub mod completeness_detector;
pub mod global_planner;
pub mod local_explorer;
pub mod robot_bridge;
pub mod scene_classifier;
pub mod target_generator;
pub mod vehicle_sim;

use std::process::ExitCode;

use crate::runtime::{RosArgs, run_with};

/// `NAMES` and `run_by_name` over the node modules listed.
macro_rules! nodes {
    ($($node:ident),* $(,)?) => {
        /// Names of the nodes `skyground node` can run.
        pub const NAMES: &[&str] = &[$(stringify!($node)),*];

        /// Runs the node called `name` with its ROS arguments; `None` for an unknown name.
        pub fn run_by_name(name: &str, ros: RosArgs) -> Option<ExitCode> {
            Some(match name {
                $(stringify!($node) => run_with($node::SPEC, ros, vec![], async |rt, _| {
                    $node::run(rt).await
                }),)*
                _ => return None,
            })
        }
    };
}

nodes!(
    cloud_publisher,
    cloud_inspector,
    scene_classifier,
    completeness_detector,
    target_generator,
    global_planner,
    local_explorer,
    vehicle_sim,
    robot_bridge,
);

#[cfg(test)]
mod tests {
    use serde::Serialize;
    use serde::de::DeserializeOwned;
    use skyground_core::explore::ExploreParams;
    use skyground_core::footprint::{DeriveParams, SplitParams};
    use skyground_core::graph::GraphParams;
    use skyground_core::ground::CsfParams;
    use skyground_core::missing::DetectParams;
    use skyground_core::route::RouteParams;
    use skyground_core::targets::TargetParams;

    use crate::cli::detect::section;

    /// The section `key` of a node's shipped YAML, as the node reads it.
    fn shipped<T: DeserializeOwned>(node: &str, yaml: &str, key: &str) -> T {
        #[derive(serde::Deserialize)]
        struct One<T> {
            #[serde(flatten)]
            inner: std::collections::BTreeMap<String, T>,
        }
        let one: One<T> = section(node, yaml, None, &[key]).expect("shipped YAML parses");
        one.inner.into_values().next().expect("section present")
    }

    fn same<T: Serialize>(a: &T, b: &T) -> bool {
        serde_json::to_value(a).ok() == serde_json::to_value(b).ok()
    }

    // The YAML files carry the reasoning for each default; the library's
    // Default must say the same, or one of them is stale.
    #[test]
    fn shipped_yaml_sections_match_the_library_defaults() {
        let cls = super::scene_classifier::SPEC;
        let c: CsfParams = shipped(cls.name, cls.default_params, "csf");
        assert_eq!(c, CsfParams::default());
        let det = super::completeness_detector::SPEC;
        let d: DetectParams = shipped(det.name, det.default_params, "detect");
        assert!(same(&d, &DetectParams::default()), "detect: {d:?}");
        let s: SplitParams = shipped(det.name, det.default_params, "split");
        assert_eq!(s, SplitParams::default());
        let v: DeriveParams = shipped(det.name, det.default_params, "derive");
        assert_eq!(v, DeriveParams::default());
        let gen_ = super::target_generator::SPEC;
        let t: TargetParams = shipped(gen_.name, gen_.default_params, "targets");
        assert!(same(&t, &TargetParams::default()), "targets: {t:?}");
        let plan = super::global_planner::SPEC;
        let g: GraphParams = shipped(plan.name, plan.default_params, "graph");
        assert_eq!(g, GraphParams::default());
        let r: RouteParams = shipped(plan.name, plan.default_params, "route");
        assert_eq!(r, RouteParams::default());
        let exp = super::local_explorer::SPEC;
        let g2: GraphParams = shipped(exp.name, exp.default_params, "graph");
        assert_eq!(
            g2,
            GraphParams::default(),
            "explorer and planner build one graph"
        );
        let e: ExploreParams = shipped(exp.name, exp.default_params, "explore");
        assert_eq!(e, ExploreParams::default());
        let br = super::robot_bridge::SPEC;
        let f: skyground_core::follow::FollowConfig = shipped(br.name, br.default_params, "follow");
        assert_eq!(f, skyground_core::follow::FollowConfig::default());
    }

    #[test]
    fn a_wrong_key_in_a_section_is_an_error() {
        let yaml = "completeness_detector:\n  ros__parameters:\n    detect:\n      deltaa: 1.0\n";
        let r: Result<std::collections::BTreeMap<String, DetectParams>, _> =
            section("completeness_detector", yaml, None, &["detect"]);
        assert!(r.is_err());
    }
}
