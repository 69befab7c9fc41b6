//! The shared node runtime: command line, params, DDS domain, QoS, logging,
//! clock and shutdown. Every skyground node is this plus a library call.

pub mod args;
pub mod creation_watch;
pub mod domain;
pub mod faults;
pub mod forward;
pub mod log;
pub mod model;
pub mod node;
pub mod param_services;
pub mod params;
pub mod qos;
pub mod shutdown;
pub mod specs;
pub mod tools;
pub mod watch;
pub mod work_beat;

pub use args::RosArgs;
pub use forward::forward;
pub use log::Logger;
pub use node::{NodeRuntime, RuntimeError, run_node, run_with};
pub use specs::NodeSpec;
pub use watch::{publish_logged, publish_watched};
