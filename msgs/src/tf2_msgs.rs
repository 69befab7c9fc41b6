//! `tf2_msgs`: the transform tree as `/tf` and `/tf_static` carry it.

use serde::{Deserialize, Serialize};

use crate::geometry_msgs::TransformStamped;
use crate::message::ros_message;

/// `tf2_msgs/msg/TFMessage`: transforms published together on `/tf` or `/tf_static`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct TFMessage {
    /// The transforms.
    pub transforms: Vec<TransformStamped>,
}

ros_message!(
    TFMessage,
    "tf2_msgs/msg/TFMessage",
    [TransformStamped],
    ["geometry_msgs/TransformStamped[] transforms"]
);
