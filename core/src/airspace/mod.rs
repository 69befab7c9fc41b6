//! Where the drone may fly (issue 52 part 2): its free space from the
//! aerial prior (`map`: a height map of the prior's highest points, whose
//! buildings and trees count as solid down to the ground), an altitude
//! ceiling above take-off, a minimum distance to buildings, a margin beyond
//! the body radius from everything else and an optional geofence (`rules`).
//! A position or a plan that breaks one is refused with the reason
//! (`violation`). `ground`: the ground the robot can drive to, for the
//! choice of platform. ROS-free.

mod ground;
mod map;
mod rules;
mod violation;

pub use ground::GroundReach;
pub use map::{Airspace, AirspaceError};
pub use rules::{AirspaceRules, Geofence, geofence};
pub use violation::{Obstacle, Refusal, Violation};

#[cfg(test)]
mod tests;
