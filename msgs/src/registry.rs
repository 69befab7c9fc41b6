//! Every message type of this crate by name, and the `ros2msg` schema text of each.

use crate::message::RosMessage;
use crate::{
    builtin_interfaces, diagnostic_msgs, geometry_msgs, nav_msgs, rcl_interfaces, rosgraph_msgs,
    sensor_msgs, std_msgs, tf2_msgs, visualization_msgs,
};

/// What the registry knows of one type.
struct Entry {
    /// Full type name (`pkg/msg/Type`).
    type_name: &'static str,
    /// Own field lines.
    definition: &'static str,
    /// Direct dependencies' full type names.
    dependencies: fn() -> Vec<&'static str>,
}

/// Lists the types once, producing both the entry table and the name list.
macro_rules! registry {
    ($($ty:ty),* $(,)?) => {
        /// One entry per known type.
        static ENTRIES: &[Entry] = &[$(Entry {
            type_name: <$ty as RosMessage>::TYPE_NAME,
            definition: <$ty as RosMessage>::DEFINITION,
            dependencies: <$ty as RosMessage>::dependencies,
        }),*];
        /// The names of [`ENTRIES`], same order.
        static NAMES: &[&str] = &[$(<$ty as RosMessage>::TYPE_NAME),*];

        /// Calls `visitor.visit::<M>()` with `M` the type named `type_name`
        /// (`pkg/msg/Type` or `pkg/Type`); `None` for an unknown name.
        pub fn with_type<V: TypeVisitor>(type_name: &str, visitor: V) -> Option<V::Output> {
            let full = normalize(type_name)?;
            $(if full == <$ty as RosMessage>::TYPE_NAME {
                return Some(visitor.visit::<$ty>());
            })*
            None
        }
    };
}

registry!(
    builtin_interfaces::Time,
    builtin_interfaces::Duration,
    std_msgs::Header,
    std_msgs::ColorRGBA,
    sensor_msgs::PointField,
    sensor_msgs::PointCloud2,
    sensor_msgs::CompressedImage,
    geometry_msgs::Point,
    geometry_msgs::Point32,
    geometry_msgs::Vector3,
    geometry_msgs::Quaternion,
    geometry_msgs::Pose,
    geometry_msgs::PoseStamped,
    geometry_msgs::PointStamped,
    geometry_msgs::Twist,
    geometry_msgs::Polygon,
    geometry_msgs::PolygonStamped,
    geometry_msgs::PoseWithCovariance,
    geometry_msgs::TwistWithCovariance,
    geometry_msgs::Transform,
    geometry_msgs::TransformStamped,
    tf2_msgs::TFMessage,
    nav_msgs::Path,
    nav_msgs::Odometry,
    visualization_msgs::UVCoordinate,
    visualization_msgs::MeshFile,
    visualization_msgs::Marker,
    visualization_msgs::MarkerArray,
    diagnostic_msgs::KeyValue,
    diagnostic_msgs::DiagnosticStatus,
    diagnostic_msgs::DiagnosticArray,
    rosgraph_msgs::Clock,
    rcl_interfaces::Log,
);

/// Code generic over a message type, run for a type chosen by name at run time
/// (recorders, echo tools).
pub trait TypeVisitor {
    /// What the visit returns.
    type Output;
    /// Runs with `M` the chosen type.
    fn visit<M: RosMessage + std::fmt::Debug>(self) -> Self::Output;
}

fn normalize(type_name: &str) -> Option<String> {
    let mut parts = type_name.split('/');
    match (parts.next(), parts.next(), parts.next(), parts.next()) {
        (Some(p), Some("msg"), Some(t), None) | (Some(p), Some(t), None, None) => {
            Some(format!("{p}/msg/{t}"))
        }
        _ => None,
    }
}

/// Full type names (`pkg/msg/Type`) of every message type this crate defines.
pub fn known_types() -> &'static [&'static str] {
    NAMES
}

/// The separator line between definitions in a `ros2msg` schema: 80 `=`.
const SEPARATOR: &str =
    "================================================================================";

/// The rosbag2/MCAP `ros2msg` schema of a type, or `None` for an unknown type.
///
/// `type_name` may be `pkg/msg/Type` or `pkg/Type`. The text is the type's own
/// field lines, then for each transitive dependency (depth first, in field
/// order, each once) a line of 80 `=`, a line `MSG: pkg/Type` and its field lines.
pub fn full_definition(type_name: &str) -> Option<String> {
    let root = find(type_name)?;
    let mut text = String::from(root.definition);
    let mut seen = vec![root.type_name];
    let mut stack: Vec<&'static str> = (root.dependencies)().into_iter().rev().collect();
    while let Some(name) = stack.pop() {
        if seen.contains(&name) {
            continue;
        }
        seen.push(name);
        let entry = find(name)?;
        text.push_str(SEPARATOR);
        text.push_str("\nMSG: ");
        text.push_str(&short_name(entry.type_name));
        text.push('\n');
        text.push_str(entry.definition);
        stack.extend((entry.dependencies)().into_iter().rev());
    }
    Some(text)
}

/// Looks a type up by `pkg/msg/Type` or `pkg/Type`.
fn find(type_name: &str) -> Option<&'static Entry> {
    ENTRIES
        .iter()
        .find(|e| e.type_name == type_name || short_name(e.type_name) == type_name)
}

/// `pkg/msg/Type` → `pkg/Type`.
fn short_name(type_name: &str) -> String {
    type_name.replacen("/msg/", "/", 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_dependency_is_registered() {
        for entry in ENTRIES {
            for dep in (entry.dependencies)() {
                assert!(
                    find(dep).is_some(),
                    "{} uses unknown {dep}",
                    entry.type_name
                );
            }
        }
    }

    #[test]
    fn names_are_unique() {
        for (i, a) in NAMES.iter().enumerate() {
            assert!(!NAMES[i + 1..].contains(a), "{a} listed twice");
        }
    }

    #[test]
    fn full_definition_lists_each_dependency_once() {
        let text = full_definition("nav_msgs/msg/Odometry").unwrap();
        assert!(text.starts_with("std_msgs/Header header\nstring child_frame_id\n"));
        for dep in [
            "std_msgs/Header",
            "builtin_interfaces/Time",
            "geometry_msgs/PoseWithCovariance",
            "geometry_msgs/Pose",
            "geometry_msgs/Point",
            "geometry_msgs/Quaternion",
            "geometry_msgs/TwistWithCovariance",
            "geometry_msgs/Twist",
            "geometry_msgs/Vector3",
        ] {
            let line = format!("\nMSG: {dep}\n");
            assert_eq!(text.matches(&line).count(), 1, "{dep} in\n{text}");
        }
        assert_eq!(text.matches(SEPARATOR).count(), 9);
        assert!(text.contains(&format!("{SEPARATOR}\nMSG: std_msgs/Header\n")));
        assert_eq!(SEPARATOR.len(), 80);
    }

    #[test]
    fn full_definition_of_leaf_is_its_own_text() {
        assert_eq!(
            full_definition("builtin_interfaces/Time").as_deref(),
            Some("int32 sec\nuint32 nanosec\n")
        );
        assert_eq!(full_definition("nope/msg/Nope"), None);
    }

    #[test]
    fn with_type_dispatches_by_name() {
        struct Name;
        impl TypeVisitor for Name {
            type Output = &'static str;
            fn visit<M: RosMessage + std::fmt::Debug>(self) -> &'static str {
                M::TYPE_NAME
            }
        }
        assert_eq!(with_type("nav_msgs/Path", Name), Some("nav_msgs/msg/Path"));
        assert_eq!(
            with_type("sensor_msgs/msg/PointCloud2", Name),
            Some("sensor_msgs/msg/PointCloud2")
        );
        assert_eq!(with_type("nav_msgs/msg/Nope", Name), None);
        assert_eq!(with_type("garbage", Name), None);
    }
}
