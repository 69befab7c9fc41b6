//! skyground-core: the ROS-free algorithms of skyground, as pure functions on plain data.
//!
//! Modules follow the method's data flow (see docs/design.md): `cloud`, `crs`, `scene`, `prior` (a real survey as the prior) and
//! `lidar` hold the inputs and the simulated world; then `ground` (CSF),
//! `features`, `forest` and `classify` (step 1), `footprint` (2), `slice`,
//! `skeleton` and `missing` (3), `targets` (4), `graph` (5), `route` (6),
//! `explore` (7), `vehicle` (8: the ground robot and the multirotor),
//! `airspace` (where the drone may fly), `sorties` (the drone's viewpoints
//! and flights) and `metrics` (9); `validity` checks a CityJSON Solid as
//! val3dity does (ISO 19107, its error codes); `work` counts long
//! computations' steps, for the launcher's watchdog.

pub mod airspace;
pub mod classify;
pub mod cloud;
pub mod crs;
pub mod density;
pub mod explore;
pub mod features;
pub mod field;
pub mod file;
pub mod follow;
pub mod footprint;
pub mod forest;
pub mod geom;
pub mod graph;
pub mod ground;
pub mod io;
pub mod lidar;
pub mod metrics;
pub mod missing;
pub mod mission;
pub mod params;
pub mod plot;
pub mod prior;
pub mod px4;
pub mod reconstruct;
pub mod rng;
pub mod route;
pub mod scene;
pub mod skeleton;
pub mod slice;
pub mod sorties;
pub mod targets;
pub mod validity;
pub mod vehicle;
pub mod work;
