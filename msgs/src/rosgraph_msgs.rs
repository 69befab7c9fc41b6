//! `rosgraph_msgs`: the simulated clock.

use serde::{Deserialize, Serialize};

use crate::builtin_interfaces::Time;
use crate::message::ros_message;

/// `rosgraph_msgs/msg/Clock`: the current simulated time, published on `/clock`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct Clock {
    /// Current time.
    pub clock: Time,
}

ros_message!(
    Clock,
    "rosgraph_msgs/msg/Clock",
    [Time],
    ["builtin_interfaces/Time clock"]
);
