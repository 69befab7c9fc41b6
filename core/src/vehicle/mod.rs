//! The simulated vehicles: the ground robot (kinematics, terrain following
//! and collision checks against the scene, docs/design.md step 8) and the
//! [`multirotor`]. ROS-free: `vehicle_sim` drives them.

mod clock;
mod config;
mod incline;
pub mod multirotor;
mod probe;
mod schedule;
mod start;
mod state;

pub use clock::RobotClock;
pub use config::VehicleConfig;
pub use incline::{INCLINE_BASE_M, incline_deg, profile_climbable};
pub use probe::{Terrain, goal_inside_building};
pub use schedule::{Every, ScanSchedule};
pub use start::{
    GraphStart, NEAR_RADIUS_M, START_CLEARANCE_M, StartError, find_start, free_spot,
    start_on_classes, start_spot,
};
pub use state::{Step, Vehicle, VehicleState};
