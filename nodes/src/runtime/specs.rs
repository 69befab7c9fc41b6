//! Every node's [`NodeSpec`]: its name, its shipped params and the ones it
//! reads again as it works. The nodes run with these, and the CLI's
//! commands read the same defaults here (never from a node module).

/// What a node binary declares about itself.
#[derive(Debug, Clone, Copy)]
pub struct NodeSpec {
    /// Default node name.
    pub name: &'static str,
    /// Default parameters: the text of `config/<name>.yaml`, compiled in so
    /// that the params file stays the single source of defaults.
    pub default_params: &'static str,
    /// Parameters the node reads again as it works, so a set (`ros2 param
    /// set`) takes effect (a name, or a prefix ending in `.`); every other
    /// one is read once at start-up and a set to it is refused.
    pub live: &'static [&'static str],
}

/// `pub const $spec`: the [`NodeSpec`] of node `$name`, whose defaults are
/// `config/$name.yaml`, with its live parameters.
macro_rules! node_spec {
    ($spec:ident = $name:literal $(, live: [$($live:literal),* $(,)?])?) => {
        #[doc = concat!("Name and default params of ", $name, ".")]
        pub const $spec: NodeSpec = NodeSpec {
            name: $name,
            default_params: include_str!(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../config/",
                $name,
                ".yaml"
            )),
            live: &[$($($live),*)?],
        };
    };
}

node_spec!(CLOUD_PUBLISHER = "cloud_publisher");
node_spec!(CLOUD_INSPECTOR = "cloud_inspector", live: ["max_clouds"]);
node_spec!(SCENE_CLASSIFIER = "scene_classifier");
node_spec!(COMPLETENESS_DETECTOR = "completeness_detector");
node_spec!(TARGET_GENERATOR = "target_generator");
node_spec!(GLOBAL_PLANNER = "global_planner");
node_spec!(LOCAL_EXPLORER = "local_explorer");
node_spec!(VEHICLE_SIM = "vehicle_sim");
node_spec!(UAV_SIM = "uav_sim");
node_spec!(UAV_PLANNER = "uav_planner");
// follow.* are live: a `ros2 param set` counts from the robot's next pose on.
node_spec!(ROBOT_BRIDGE = "robot_bridge", live: ["follow."]);
// follow.* are live, as robot_bridge's.
node_spec!(PX4_BRIDGE = "px4_bridge", live: ["follow."]);
