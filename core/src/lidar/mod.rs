//! Ray casting against scene meshes and simulated LiDAR sensors (docs/design.md
//! step 8 "Vehicle + LiDAR" and the airborne prior of "Scenes").
//!
//! - [`Caster`]: a BVH over a [`Scene`](crate::scene::Scene), built once;
//!   closest-hit queries one at a time or in parallel batches (`caster`,
//!   `bvh`, `triangle`); [`CastBackend::Parry`] casts through parry3d's
//!   `TriMesh` instead (`parry_mesh`).
//! - [`spinning`]: a multi-beam spinning LiDAR on a ground vehicle
//!   (VLP-16 defaults) → [`ScanPoints`]; a revolution is cast in packets of
//!   32 columns × 2 beams that walk the BVH together (`bvh::packet`), with
//!   the same hits as ray by ray.
//! - [`airborne`]: an airborne laser scanner flying parallel strips →
//!   [`Cloud`](crate::cloud::Cloud).
//! - [`synthetic`]: boxes on a plane and a dense city-like scene for tests
//!   and benchmarks; [`bench`](mod@bench): the ray-throughput figure.

#![warn(missing_docs)]

pub mod airborne;
pub mod bench;
mod bvh;
mod caster;
mod intensity;
mod parry_mesh;
pub mod patches;
mod pose;
mod ray;
pub mod spinning;
pub mod synthetic;
mod triangle;

pub use airborne::{AirborneConfig, FlightPattern, ReturnMode, airborne_scan};
pub use bench::{BenchFigures, bench_rays};
pub use caster::{CastBackend, Caster, CasterError};
pub use intensity::{INTENSITY_FULL_SCALE, reflectance, return_intensity};
pub use pose::Pose;
pub use ray::{Hit, Ray};
pub use spinning::{LidarConfig, ScanPoints, scan};
