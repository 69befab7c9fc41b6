//! The [`RosMessage`] trait: what a Rust struct must say about the ROS 2 type it mirrors.

use serde::Serialize;
use serde::de::DeserializeOwned;

/// A Rust struct whose serde field order is the CDR layout of a ROS 2 message type.
pub trait RosMessage: Serialize + DeserializeOwned + Clone + Send + Sync + 'static {
    /// ROS 2 type name, e.g. "sensor_msgs/msg/PointCloud2".
    const TYPE_NAME: &'static str;
    /// Own .msg field lines (no comments) of this type only, one per line.
    const DEFINITION: &'static str;
    /// Names of the message types this one's fields use (direct dependencies), as TYPE_NAME strings.
    fn dependencies() -> Vec<&'static str>;
}

/// Implements [`RosMessage`] for a struct: type name, direct dependencies, .msg field lines.
macro_rules! ros_message {
    ($ty:ty, $name:literal, [$($dep:ty),* $(,)?], [$($line:literal),* $(,)?]) => {
        impl $crate::message::RosMessage for $ty {
            const TYPE_NAME: &'static str = $name;
            const DEFINITION: &'static str = concat!($($line, "\n"),*);
            fn dependencies() -> Vec<&'static str> {
                vec![$(<$dep as $crate::message::RosMessage>::TYPE_NAME),*]
            }
        }
    };
}

pub(crate) use ros_message;
