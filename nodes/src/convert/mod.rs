//! Library values ↔ standard ROS messages, in one place so every node
//! speaks the same dialect (frames, namespaces, colours); [`pointcloud2`]
//! is the codec between a [`Cloud`](skyground_core::cloud::Cloud) and
//! `sensor_msgs/PointCloud2`.

pub mod areas;
pub mod detection;
pub mod diagnostics;
pub mod markers;
pub mod path;
pub mod pointcloud2;
pub mod px4;
pub mod scan_store;
pub mod scans;
pub mod targets;
pub mod tf;
