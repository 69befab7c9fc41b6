//! Surfaces at grade. Where terrain drops away (a river bank, a slope to
//! a data void) the cloth hangs below the top of the slope, and the flat
//! ground along it is left standing; the forest then reads it as a roof
//! (Autzen's river bank: 9,600 points, one 300 m "building"). A footbridge
//! rising from the bank is read the same way. A roof stands on walls: its
//! edge is a storey above the ground beside it. A surface the ground runs
//! into without a step is terrain, or a bridge where ground lies beneath
//! it.
//!
//! On a plan grid, building cells are grown from the ground cells: a cell
//! joins when its highest building point lies within [`STEP_M`] of the
//! surface of a neighbour already joined. Its building points become
//! ground, or bridge deck (17) where the cell holds ground more than
//! [`DECK_CLEARANCE_M`] below that surface.

use std::collections::{HashMap, VecDeque};

use serde::Serialize;

use crate::cloud::class::{BRIDGE_DECK, BUILDING, GROUND};

/// Largest rise (m) from one joined cell to the next: more than a kerb,
/// far less than a storey.
pub const STEP_M: f32 = 0.3;

/// Smallest plan cell (m); sparser clouds get twice their point spacing,
/// so each cell holds points.
pub const MIN_CELL_M: f32 = 1.0;

/// A joined cell with ground this far (m) below its surface is a deck
/// over that ground.
pub const DECK_CLEARANCE_M: f32 = 2.0;

/// What [`join_terrain`] relabelled, and the points the forest took back
/// as ground ([`super::classify_at`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct AtGrade {
    /// Building points that continue the terrain: now ground.
    pub to_ground: usize,
    /// Building points that continue the terrain over lower ground: now
    /// bridge deck.
    pub to_bridge_deck: usize,
    /// Points the ground filter left standing that the forest calls
    /// ground: now ground.
    pub forest_ground: usize,
    /// Points with no other within the forest's largest sphere and no
    /// ground near, that the terrain's slope calls ground
    /// ([`super::lone::lone_ground`]): now ground.
    pub lone_ground: usize,
}

impl AtGrade {
    /// What a user is told when points were relabelled; `None` otherwise.
    pub fn message(&self) -> Option<String> {
        let joined = (self.to_ground + self.to_bridge_deck > 0).then(|| {
            format!(
                "{} point(s) read as roofs continue the terrain without a step (ground the cloth hung below, at a bank or a slope): {} now ground, {} bridge deck",
                self.to_ground + self.to_bridge_deck,
                self.to_ground,
                self.to_bridge_deck
            )
        });
        let forest = (self.forest_ground > 0).then(|| {
            format!(
                "{} point(s) the ground filter left standing are ground to the forest (terrain the cloth hung off, on a slope or a bank): now ground",
                self.forest_ground
            )
        });
        let lone = (self.lone_ground > 0).then(|| {
            format!(
                "{} lone point(s) (no other within the forest's reach, no ground near: a sparse survey) lie within the steepest terrain slope of the ground round them: now ground",
                self.lone_ground
            )
        });
        let lines: Vec<String> = [joined, forest, lone].into_iter().flatten().collect();
        (!lines.is_empty()).then(|| lines.join("\n"))
    }
}

/// Heights in one plan cell.
#[derive(Debug, Clone, Copy)]
struct Cell {
    ground_min: f32,
    ground_max: f32,
    building_top: f32,
}

impl Default for Cell {
    fn default() -> Self {
        Self {
            ground_min: f32::INFINITY,
            ground_max: f32::NEG_INFINITY,
            building_top: f32::NEG_INFINITY,
        }
    }
}

/// Relabels building points (6) whose surface continues the ground (2)
/// without a step; `spacing_m`: the cloud's point spacing.
pub fn join_terrain(xyz: &[[f32; 3]], labels: &mut [u8], spacing_m: f32) -> AtGrade {
    let mut counts = AtGrade::default();
    if xyz.len() != labels.len() {
        return counts;
    }
    let spacing = if spacing_m.is_finite() {
        spacing_m
    } else {
        0.0
    };
    let cell = MIN_CELL_M.max(2.0 * spacing);
    let key = |p: &[f32; 3]| [(p[0] / cell).floor() as i32, (p[1] / cell).floor() as i32];
    let mut cells: HashMap<[i32; 2], Cell> = HashMap::new();
    for (p, &l) in xyz.iter().zip(labels.iter()) {
        if !p.iter().all(|v| v.is_finite()) || (l != GROUND && l != BUILDING) {
            continue;
        }
        let c = cells.entry(key(p)).or_default();
        if l == GROUND {
            c.ground_min = c.ground_min.min(p[2]);
            c.ground_max = c.ground_max.max(p[2]);
        } else {
            c.building_top = c.building_top.max(p[2]);
        }
    }
    let is_building = |c: &Cell| c.building_top.is_finite();
    // Surface height of each joined cell, seeded by the ground cells
    // without a building point; a building cell is in it once joined.
    let mut surface: HashMap<[i32; 2], f32> = HashMap::new();
    let mut queue: VecDeque<([i32; 2], f32)> = VecDeque::new();
    for (k, c) in &cells {
        if !is_building(c) && c.ground_max.is_finite() {
            surface.insert(*k, c.ground_max);
            queue.push_back((*k, c.ground_max));
        }
    }
    let seeds = surface.len();
    while let Some((k, z)) = queue.pop_front() {
        for dx in -1..=1 {
            for dy in -1..=1 {
                let n = [k[0] + dx, k[1] + dy];
                if surface.contains_key(&n) {
                    continue;
                }
                let Some(c) = cells.get(&n).filter(|c| is_building(c)) else {
                    continue;
                };
                if (c.building_top - z).abs() <= STEP_M {
                    surface.insert(n, c.building_top);
                    queue.push_back((n, c.building_top));
                }
            }
        }
    }
    if surface.len() == seeds {
        return counts;
    }
    for (p, l) in xyz.iter().zip(labels.iter_mut()) {
        if *l != BUILDING || !p.iter().all(|v| v.is_finite()) {
            continue;
        }
        let k = key(p);
        let Some(&top) = surface.get(&k) else {
            continue;
        };
        let over_ground = cells
            .get(&k)
            .is_some_and(|c| c.ground_min < top - DECK_CLEARANCE_M);
        if over_ground {
            *l = BRIDGE_DECK;
            counts.to_bridge_deck += 1;
        } else {
            *l = GROUND;
            counts.to_ground += 1;
        }
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::class::VEGETATION;

    /// Points 0.5 m apart over `x0..x1` × `y0..y1` at height `z(x, y)`.
    fn patch(
        (x0, x1): (f32, f32),
        (y0, y1): (f32, f32),
        label: u8,
        z: impl Fn(f32, f32) -> f32,
    ) -> Vec<([f32; 3], u8)> {
        let mut v = Vec::new();
        let mut x = x0;
        while x < x1 {
            let mut y = y0;
            while y < y1 {
                v.push(([x, y, z(x, y)], label));
                y += 0.5;
            }
            x += 0.5;
        }
        v
    }

    fn split(v: Vec<([f32; 3], u8)>) -> (Vec<[f32; 3]>, Vec<u8>) {
        v.into_iter().unzip()
    }

    #[test]
    fn a_bank_top_the_cloth_missed_becomes_ground_and_a_house_stays() {
        // Ground at 0 for x < 20; the bank top, read as a roof, carries on
        // at 0–0.1 m to x = 30, where the bank drops to a river at −5 m.
        // A house (roof at 6 m on walls) stands on the ground at x 5–12.
        let mut v = patch((0.0, 20.0), (0.0, 20.0), GROUND, |_, _| 0.0);
        v.retain(|(p, _)| !(p[0] >= 5.0 && p[0] < 12.0 && p[1] >= 5.0 && p[1] < 12.0));
        v.extend(patch((5.0, 12.0), (5.0, 12.0), BUILDING, |_, _| 6.0));
        v.extend(patch((20.0, 30.0), (0.0, 20.0), BUILDING, |x, _| {
            0.01 * (x - 20.0)
        }));
        v.extend(patch((34.0, 40.0), (0.0, 20.0), GROUND, |_, _| -5.0));
        // A tree on the bank top stays a tree.
        v.extend(patch((24.0, 26.0), (8.0, 10.0), VEGETATION, |_, _| 3.0));
        let (xyz, mut labels) = split(v);
        let before = labels.clone();
        let got = join_terrain(&xyz, &mut labels, 0.5);
        let bank = before
            .iter()
            .zip(&xyz)
            .filter(|(l, p)| **l == BUILDING && p[0] >= 20.0)
            .count();
        assert_eq!(got.to_ground, bank, "{got:?}");
        assert_eq!(got.to_bridge_deck, 0);
        for ((p, l), b) in xyz.iter().zip(&labels).zip(&before) {
            if p[0] < 20.0 || *b == VEGETATION {
                assert_eq!(l, b, "{p:?}");
            } else {
                assert_eq!(*l, GROUND, "{p:?}");
            }
        }
        assert!(got.message().is_some_and(|m| m.contains("now ground")));
    }

    #[test]
    fn a_footbridge_rising_from_the_ground_is_a_deck_where_ground_lies_beneath() {
        // Ground at 0 for x < 10, and a road beneath the deck at x 30–40;
        // a 4 m wide deck from x = 10 rising 15 % (0.15 m a cell) to x = 50,
        // 3 m over the road where it crosses.
        let mut v = patch((0.0, 10.0), (0.0, 4.0), GROUND, |_, _| 0.0);
        v.extend(patch((30.0, 40.0), (0.0, 4.0), GROUND, |_, _| 0.0));
        v.extend(patch((10.0, 50.0), (0.0, 4.0), BUILDING, |x, _| {
            0.15 * (x - 10.0)
        }));
        let (xyz, mut labels) = split(v);
        let got = join_terrain(&xyz, &mut labels, 0.5);
        for (p, l) in xyz.iter().zip(&labels) {
            if p[2] > 0.0 && (30.0..40.0).contains(&p[0]) {
                assert_eq!(*l, BRIDGE_DECK, "{p:?}");
            }
        }
        assert!(got.to_bridge_deck > 0 && got.to_ground > 0, "{got:?}");
        assert!(labels.iter().all(|&l| l != BUILDING));
    }

    #[test]
    fn a_roof_on_walls_a_flat_roof_beside_a_bank_and_bad_input_are_left_alone() {
        // A flat roof 3 m up whose walls' feet the roof check called
        // building: the cells at the wall hold both, so their top is the roof.
        let mut v = patch((0.0, 30.0), (0.0, 30.0), GROUND, |_, _| 0.0);
        v.retain(|(p, _)| !(p[0] >= 10.0 && p[0] < 20.0 && p[1] >= 10.0 && p[1] < 20.0));
        v.extend(patch((10.0, 20.0), (10.0, 20.0), BUILDING, |_, _| 3.0));
        v.extend(patch((10.0, 20.0), (10.0, 10.5), BUILDING, |_, _| 0.1));
        let (xyz, mut labels) = split(v);
        let before = labels.clone();
        assert_eq!(join_terrain(&xyz, &mut labels, 0.5), AtGrade::default());
        assert_eq!(labels, before);
        // Lengths that disagree, or a NaN spacing: nothing changes.
        assert_eq!(
            join_terrain(&xyz, &mut labels[..3].to_vec(), 0.5),
            AtGrade::default()
        );
        assert_eq!(
            join_terrain(&xyz, &mut labels, f32::NAN),
            AtGrade::default()
        );
        assert_eq!(labels, before);
    }
}
