//! The simulated ground vehicle: kinematics, terrain following and collision
//! checks against the scene (docs/design.md step 8). ROS-free: `vehicle_sim` drives it.

mod clock;
mod config;
mod incline;
mod probe;
mod schedule;
mod state;

pub use clock::RobotClock;
pub use config::VehicleConfig;
pub use incline::{INCLINE_BASE_M, incline_deg, profile_climbable};
pub use probe::{Terrain, free_spot, goal_inside_building, start_spot};
pub use schedule::{Every, ScanSchedule};
pub use state::{Step, Vehicle, VehicleState};
