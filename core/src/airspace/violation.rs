//! Why a position or a plan is refused.

/// What is near: a building, or anything else the prior holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Obstacle {
    /// A building (facade or roof).
    Building,
    /// Ground, vegetation or anything else.
    Other,
}

/// One rule a position breaks.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Violation {
    /// Outside the prior's extent: nothing is known there.
    #[error("({:.1}, {:.1}, {:.1}) lies outside the prior: nothing is known there", at[0], at[1], at[2])]
    Unmapped {
        /// The position, m (local frame).
        at: [f32; 3],
    },
    /// Above the ceiling.
    #[error("({:.1}, {:.1}, {:.1}) is {above_m:.1} m above take-off, over the {ceiling_m:.0} m ceiling", at[0], at[1], at[2])]
    AboveCeiling {
        /// The position, m.
        at: [f32; 3],
        /// Its height above the take-off point, m.
        above_m: f32,
        /// The ceiling, m above take-off.
        ceiling_m: f32,
    },
    /// Outside the geofence.
    #[error("({:.1}, {:.1}, {:.1}) lies outside the geofence (the body is kept inside it)", at[0], at[1], at[2])]
    OutsideFence {
        /// The position, m.
        at: [f32; 3],
    },
    /// Too near something.
    #[error("({:.1}, {:.1}, {:.1}) is {distance_m:.2} m from {}, under the {required_m:.2} m kept", at[0], at[1], at[2], if *what == Obstacle::Building { "a building" } else { "the ground or an object" })]
    TooClose {
        /// The position, m.
        at: [f32; 3],
        /// What is near.
        what: Obstacle,
        /// Its distance, m.
        distance_m: f32,
        /// The distance the rules keep, m.
        required_m: f32,
    },
}

/// A plan refused: the first way-point or segment that breaks a rule.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("plan refused at its way-point {leg} (on the way from the one before): {violation}")]
pub struct Refusal {
    /// The way-point index the refused leg leads to (0: the start itself).
    pub leg: usize,
    /// The rule broken.
    pub violation: Violation,
}
