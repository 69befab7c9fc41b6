//! How densely a cloud samples its surfaces, and parameters that follow it:
//! a length written `auto` in a params file is derived from the measured
//! density by a documented rule; a number overrides the rule.

mod auto;
mod measure;

pub use auto::Auto;
pub use measure::{DENSITY_CELL_M, Density};
