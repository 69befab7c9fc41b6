//! skyground-nodes: the ROS 2 side of skyground. A shared node runtime, the
//! cloud transport, the MCAP recorder, and one thin binary per node.

pub mod bag;
pub mod cli;
pub mod convert;
pub mod netns;
pub mod node;
pub mod runtime;
pub mod tap;
pub mod transport;
