//! The target set on the wire: /target_points as target points, and the
//! stamp both its halves (/target_points, /target_regions) carry as one key.

use skyground_core::cloud::Cloud;
use skyground_core::targets::TargetPoint;
use skyground_msgs::builtin_interfaces::Time;

use crate::transport::with_buildings;

/// The target generator stamps both halves of a target set alike.
pub fn stamp_key(t: Time) -> u64 {
    (u64::from(t.sec as u32) << 32) | u64::from(t.nanosec)
}

/// The points of a /target_points cloud, with their building ids (0 where it has none).
pub fn target_points(cloud: Cloud) -> Vec<TargetPoint> {
    let (xyz, ids) = with_buildings(cloud);
    xyz.into_iter()
        .zip(ids)
        .map(|(xyz, building)| TargetPoint { xyz, building })
        .collect()
}
