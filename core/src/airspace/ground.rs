//! The ground the robot can drive to, as the prior's height map shows it:
//! cells the survey saw ground in, joined to the robot's start through
//! neighbours whose ground differs by no more than a kerb. A closed
//! courtyard's ground is seen from above but joined to nothing outside.

use std::collections::VecDeque;

use super::map::Airspace;
use crate::geom::grid::Neighbours;

/// Cells searched around the start for ground to begin from (a start on a
/// cell the survey saw no ground in, under a car or a tree).
const START_SEARCH_CELLS: i64 = 6;

/// The ground cells joined to the start.
#[derive(Debug, Clone)]
pub struct GroundReach {
    cells: Vec<bool>,
}

impl GroundReach {
    /// How many cells the robot can reach.
    pub fn count(&self) -> usize {
        self.cells.iter().filter(|&&c| c).count()
    }
}

impl Airspace {
    /// The ground height the survey saw at `(x, y)`, if any.
    pub fn ground_at(&self, x: f32, y: f32) -> Option<f32> {
        let c = self.grid.index_of(f64::from(x), f64::from(y))?;
        let g = self.ground[c];
        (!g.is_nan()).then_some(g)
    }

    /// The ground joined to `from` (xy) by steps of at most `max_step_m`
    /// between neighbouring cells (8-connected).
    pub fn ground_reach(&self, from: [f32; 2], max_step_m: f32) -> GroundReach {
        let g = &self.grid;
        let mut cells = vec![false; g.len()];
        let (i0, j0) = g.key(f64::from(from[0]), f64::from(from[1]));
        let seed = (0..=START_SEARCH_CELLS)
            .flat_map(|r| (-r..=r).flat_map(move |dj| (-r..=r).map(move |di| (i0 + di, j0 + dj))))
            .find_map(|(i, j)| g.index(i, j).filter(|&c| !self.ground[c].is_nan()));
        let Some(seed) = seed else {
            return GroundReach { cells };
        };
        cells[seed] = true;
        let mut queue = VecDeque::from([seed]);
        while let Some(c) = queue.pop_front() {
            let (i, j) = ((c % g.nx) as i64, (c / g.nx) as i64);
            for &(di, dj) in Neighbours::Eight.offsets() {
                let Some(n) = g.index(i + di as i64, j + dj as i64) else {
                    continue;
                };
                let h = self.ground[n];
                if !cells[n] && !self.building[n] && (h - self.ground[c]).abs() <= max_step_m {
                    cells[n] = true;
                    queue.push_back(n);
                }
            }
        }
        GroundReach { cells }
    }

    /// Whether the robot can stand at `(x, y)`: ground joined to its start.
    pub fn can_stand(&self, reach: &GroundReach, x: f32, y: f32) -> bool {
        self.grid
            .index_of(f64::from(x), f64::from(y))
            .is_some_and(|c| reach.cells[c])
    }
}
