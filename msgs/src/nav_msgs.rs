//! `nav_msgs`: paths and odometry.

use serde::{Deserialize, Serialize};

use crate::geometry_msgs::{PoseStamped, PoseWithCovariance, TwistWithCovariance};
use crate::message::ros_message;
use crate::std_msgs::Header;

/// `nav_msgs/msg/Path`: a sequence of poses to follow.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Path {
    /// Stamp and frame of the path.
    pub header: Header,
    /// Poses in travel order.
    pub poses: Vec<PoseStamped>,
}

/// `nav_msgs/msg/Odometry`: estimated pose (in `header.frame_id`) and twist (in `child_frame_id`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Odometry {
    /// Stamp and frame of the pose.
    pub header: Header,
    /// Frame of the twist (the body frame).
    pub child_frame_id: String,
    /// Estimated pose with covariance.
    pub pose: PoseWithCovariance,
    /// Estimated velocity with covariance.
    pub twist: TwistWithCovariance,
}

ros_message!(
    Path,
    "nav_msgs/msg/Path",
    [Header, PoseStamped],
    [
        "std_msgs/Header header",
        "geometry_msgs/PoseStamped[] poses"
    ]
);
ros_message!(
    Odometry,
    "nav_msgs/msg/Odometry",
    [Header, PoseWithCovariance, TwistWithCovariance],
    [
        "std_msgs/Header header",
        "string child_frame_id",
        "geometry_msgs/PoseWithCovariance pose",
        "geometry_msgs/TwistWithCovariance twist",
    ]
);
