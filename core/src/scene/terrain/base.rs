//! Where a building stands, as the ground built around it needs it: the
//! footprint's box and the base height (shared by `around` and `streets`).

/// Where a building stands: its footprint's bounding box and base height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footprint {
    /// Minimum x, y.
    pub min: [f64; 2],
    /// Maximum x, y.
    pub max: [f64; 2],
    /// Lowest z of the building.
    pub base: f64,
}

impl Footprint {
    /// Distance in plan from (`x`, `y`) to the box (0 inside).
    pub(super) fn distance(&self, x: f64, y: f64) -> f64 {
        let dx = (self.min[0] - x).max(x - self.max[0]).max(0.0);
        let dy = (self.min[1] - y).max(y - self.max[1]).max(0.0);
        (dx * dx + dy * dy).sqrt()
    }
}
