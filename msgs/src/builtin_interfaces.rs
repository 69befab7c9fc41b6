//! `builtin_interfaces`: time stamps and durations.

use serde::{Deserialize, Serialize};

use crate::message::ros_message;

/// `builtin_interfaces/msg/Time`: a point in time (ROS or system clock).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct Time {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds past `sec`, in `0..1_000_000_000`.
    pub nanosec: u32,
}

/// `builtin_interfaces/msg/Duration`: a signed span of time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct Duration {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds added to `sec`, in `0..1_000_000_000`.
    pub nanosec: u32,
}

ros_message!(
    Time,
    "builtin_interfaces/msg/Time",
    [],
    ["int32 sec", "uint32 nanosec"]
);
ros_message!(
    Duration,
    "builtin_interfaces/msg/Duration",
    [],
    ["int32 sec", "uint32 nanosec"]
);
