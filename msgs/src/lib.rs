//! skyground-msgs: the ROS 2 message types skyground uses.
//!
//! One module per ROS package; each struct's serde field order is its .msg
//! field order, which is its CDR layout. [`to_cdr`] / [`from_cdr`] give the
//! ROS 2 serialized form (as rclpy's `serialize_message`), [`full_definition`]
//! the `ros2msg` schema for MCAP. It knows no algorithm: the conversion
//! between a cloud and `sensor_msgs/PointCloud2` is the nodes' (`convert::pointcloud2`).

#![warn(missing_docs)]

pub mod builtin_interfaces;
pub mod cdr;
pub mod diagnostic_msgs;
mod fixed_array;
pub mod geometry_msgs;
pub mod message;
pub mod nav_msgs;
pub mod px4_msgs;
pub mod rcl_interfaces;
pub mod registry;
pub mod rosgraph_msgs;
pub mod samples;
pub mod sensor_msgs;
pub mod std_msgs;
pub mod tf2_msgs;
pub mod visualization_msgs;

pub use cdr::{CdrError, from_cdr, to_cdr};
pub use message::RosMessage;
pub use registry::{TypeVisitor, full_definition, known_types, with_type};
