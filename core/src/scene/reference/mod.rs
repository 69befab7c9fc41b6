//! The built-in reference scene: 200 m × 200 m of gently sloped terrain,
//! streets and parks, 18 buildings of varied shape and trees near facades.
//!
//! Procedural and seeded: the same seed gives the identical scene on every
//! machine (own SplitMix64 generator, IEEE-exact arithmetic only).
//!
//! - terrain (`terrain`): one Ground object, a 128 × 128 grid (1.5625 m cells),
//!   2–3.5 % slope plus ±0.5 m undulation; [`ReferenceTerrain`] answers height
//!   queries without building the scene;
//! - buildings (`buildings`): ids 1..=18 in plan order, each one closed,
//!   outward-oriented mesh named `building_NN_<shape>` (podium with three
//!   towers, boxes across a 2–4 m alley, towers, courtyard block, L, U, slab on
//!   pillars with an open ground floor, gable-roofed houses). Walls reach 0.5 m
//!   below the lowest terrain point of their footprint, so no gap opens under
//!   them; heights are above the highest terrain point;
//! - trees (`trees`): each one Vegetation object `tree_NN` (hexagonal trunk +
//!   icosphere crown, two closed parts).

mod buildings;
pub(crate) mod solids;
mod terrain;
mod trees;

pub use terrain::{CELLS, ReferenceTerrain, SIZE};

use super::builder::SceneBuilder;
use super::{ObjectKind, Scene};

/// The default seed of the reference scene.
pub const REFERENCE_SEED: u64 = 20_240_617;

/// Builds the reference scene of `seed` (frame origin 0; x, y ∈ [0, 200] m).
pub fn reference_scene(seed: u64) -> Scene {
    let terrain = ReferenceTerrain::new(seed);
    let mut b = SceneBuilder::new([0.0; 3]);
    b.add("terrain", ObjectKind::Ground, 0, &terrain.mesh());
    let plans = buildings::plan_buildings(seed);
    for (k, plan) in plans.iter().enumerate() {
        let id = u32::try_from(k + 1).unwrap_or(u32::MAX);
        b.add(
            plan.name.clone(),
            ObjectKind::Building,
            id,
            &plan.mesh(&terrain),
        );
    }
    for (k, t) in trees::plan_trees(seed, &plans).iter().enumerate() {
        let ground = terrain.mesh_height(t.xy[0], t.xy[1]);
        let mesh = solids::tree(t.xy[0], t.xy[1], ground, t.trunk_h, t.crown_r, t.squash);
        b.add(
            format!("tree_{:02}", k + 1),
            ObjectKind::Vegetation,
            0,
            &mesh,
        );
    }
    b.finish()
}
