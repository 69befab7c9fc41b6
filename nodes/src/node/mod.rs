//! Every skyground node as a library function, so each runs as its own binary
//! and as `skyground node NAME` (what the demo launcher starts).

pub mod cloud_inspector;
pub mod cloud_publisher;
pub mod completeness_detector;
pub mod global_planner;
pub mod local_explorer;
pub mod px4_bridge;
pub mod robot_bridge;
pub mod scene_classifier;
pub mod target_generator;
pub mod uav_planner;
pub mod uav_sim;
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
    uav_planner,
    uav_sim,
    px4_bridge,
);

#[cfg(test)]
mod tests {
    use serde::Serialize;
    use serde::de::DeserializeOwned;
    use skyground_core::explore::ExploreParams;
    use skyground_core::follow::FollowConfig;
    use skyground_core::footprint::{DeriveParams, SplitParams};
    use skyground_core::graph::GraphParams;
    use skyground_core::ground::CsfParams;
    use skyground_core::missing::DetectParams;
    use skyground_core::route::RouteParams;
    use skyground_core::targets::TargetParams;

    use crate::runtime::NodeSpec;
    use crate::runtime::params::section;

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

    /// Asserts that section `key` of `spec`'s shipped YAML is `T::default()`
    /// (compared as JSON: not every params type has `PartialEq`).
    fn assert_shipped_default<T>(spec: &NodeSpec, key: &str)
    where
        T: Serialize + DeserializeOwned + Default + std::fmt::Debug,
    {
        let got: T = shipped(spec.name, spec.default_params, key);
        let same = serde_json::to_value(&got).ok() == serde_json::to_value(T::default()).ok();
        assert!(same, "{} {key}: {got:?}", spec.name);
    }

    // The YAML files carry the reasoning for each default; the library's
    // Default must say the same, or one of them is stale.
    #[test]
    fn shipped_yaml_sections_match_the_library_defaults() {
        use super::{completeness_detector as det, global_planner as plan};
        assert_shipped_default::<CsfParams>(&super::scene_classifier::SPEC, "csf");
        assert_shipped_default::<DetectParams>(&det::SPEC, "detect");
        assert_shipped_default::<SplitParams>(&det::SPEC, "split");
        assert_shipped_default::<DeriveParams>(&det::SPEC, "derive");
        assert_shipped_default::<TargetParams>(&super::target_generator::SPEC, "targets");
        assert_shipped_default::<GraphParams>(&plan::SPEC, "graph");
        assert_shipped_default::<RouteParams>(&plan::SPEC, "route");
        // The explorer and the planner build one graph.
        assert_shipped_default::<GraphParams>(&super::local_explorer::SPEC, "graph");
        assert_shipped_default::<ExploreParams>(&super::local_explorer::SPEC, "explore");
        assert_shipped_default::<FollowConfig>(&super::robot_bridge::SPEC, "follow");
        use skyground_core::airspace::AirspaceRules;
        use skyground_core::sorties::{GroundView, SortieParams};
        use skyground_core::vehicle::multirotor::MultirotorConfig;
        let uav = &super::uav_planner::SPEC;
        assert_shipped_default::<MultirotorConfig>(uav, "multirotor");
        assert_shipped_default::<AirspaceRules>(uav, "airspace");
        assert_shipped_default::<SortieParams>(uav, "sorties");
        assert_shipped_default::<GroundView>(uav, "ground_view");
        // The simulated drone flies as the planner plans it.
        assert_shipped_default::<MultirotorConfig>(&super::uav_sim::SPEC, "multirotor");
        assert_shipped_default::<FollowConfig>(&super::px4_bridge::SPEC, "follow");
        assert_shipped_default::<skyground_core::px4::OffboardConfig>(
            &super::px4_bridge::SPEC,
            "offboard",
        );
    }

    #[test]
    fn a_wrong_key_in_a_section_is_an_error() {
        let yaml = "completeness_detector:\n  ros__parameters:\n    detect:\n      deltaa: 1.0\n";
        let r: Result<std::collections::BTreeMap<String, DetectParams>, _> =
            section("completeness_detector", yaml, None, &["detect"]);
        assert!(r.is_err());
    }
}
