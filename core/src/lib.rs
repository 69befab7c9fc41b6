//! skyground-core: the ROS-free algorithms of skyground, as pure functions on plain data.
//!
//! Modules follow the method's data flow (see DESIGN.md): `cloud` holds point
//! clouds and their file formats; later steps add scene, lidar, ground, features,
//! forest, footprint, slice, skeleton, missing, targets, graph, route, explore, metrics.

pub mod cloud;
pub mod lidar;
pub mod metrics;
pub mod scene;
pub mod vehicle;
