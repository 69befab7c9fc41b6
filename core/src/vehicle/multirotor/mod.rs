//! The simulated multirotor (issue 52 part 1): 3D kinematics within speed,
//! climb, descent, acceleration and yaw-rate limits (`flight`), a body
//! sphere kept out of the true scene by parry3d's point query (`body`), a
//! battery counted in flight seconds with a home pad to land on and swap it
//! (`config`, `flight`), and a Mid-360-like LiDAR cast by the same caster
//! as the ground robot's (`lidar`); its sorties flown one battery each
//! (`queue`). ROS-free, like the ground vehicle.

mod body;
mod config;
mod flight;
mod lidar;
mod queue;

pub use body::SceneBody;
pub use config::MultirotorConfig;
pub use flight::{FlightStep, Multirotor, MultirotorState};
pub use lidar::mid360_like;
pub use queue::SortieQueue;

#[cfg(test)]
mod tests;
