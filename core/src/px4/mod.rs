//! Field mode for a PX4 drone: frames between skyground (map ENU, body FLU)
//! and PX4 (local NED, body FRD), and the offboard state machine that takes
//! a path to PX4 one way-point at a time (`px4_bridge` is its thin node).

pub mod frames;
pub mod odometry;
pub mod offboard;

pub use odometry::{MapPose, NedOdometry, Px4Error, check_path};
pub use offboard::{AtEnd, Command, Offboard, OffboardConfig, Out, Phase, Setpoint};
