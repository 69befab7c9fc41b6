//! Work done, counted: long computations (graph searches, route tours, the
//! explorer's viewpoint choice, missing-surface detection) step a
//! process-wide counter from inside their loops, and a node publishes it
//! every few seconds, so a launcher tells a node deep in a long replan (the
//! count moves) from one spinning without progress or stopped (it stands).
//! Process-wide because each node is a process of its own; a relaxed atomic
//! add, so cheap enough for an outer loop.

use std::sync::atomic::{AtomicU64, Ordering};

static STEPS: AtomicU64 = AtomicU64::new(0);

/// One step of work done.
pub fn step() {
    STEPS.fetch_add(1, Ordering::Relaxed);
}

/// Steps done in this process so far.
pub fn steps() -> u64 {
    STEPS.load(Ordering::Relaxed)
}

#[cfg(test)]
mod tests {
    #[test]
    fn steps_count_up() {
        let before = super::steps();
        super::step();
        super::step();
        // Other tests may step too (one process): at least ours counted.
        assert!(super::steps() >= before + 2);
    }
}
