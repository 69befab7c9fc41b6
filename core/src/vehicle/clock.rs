//! Simulated time that means robot time: the simulator runs ahead of wall
//! time while the vehicle works, and at wall speed while it waits for
//! orders, so the mission's seconds are what a robot would spend.

/// The simulator's clock, advanced one fixed step at a time.
///
/// While the vehicle works (drives, turns, scans) simulated time runs up to
/// `factor` times faster than wall time. While it waits for the planners it
/// runs at wall speed: waiting for a computation costs what it costs on a
/// real computer. A simulator that falls behind does not catch up later
/// (catching up would count waiting as `factor` times its length).
#[derive(Debug, Clone, PartialEq)]
pub struct RobotClock {
    step_s: f64,
    factor: f64,
    sim_s: f64,
    /// Wall and simulated seconds at the last change of pace, and the pace.
    anchor: (f64, f64, f64),
    working_s: f64,
    waiting_s: f64,
}

/// How far (wall seconds) the simulator may fall behind its pace before it
/// stops trying to make up the difference.
const MAX_LAG_S: f64 = 0.05;

impl RobotClock {
    /// A clock at 0 s stepping `step_s` simulated seconds, `factor` times
    /// faster than wall time while the vehicle works (both positive).
    pub fn new(step_s: f64, factor: f64) -> Self {
        Self {
            step_s,
            factor,
            sim_s: 0.0,
            anchor: (0.0, 0.0, 1.0),
            working_s: 0.0,
            waiting_s: 0.0,
        }
    }

    /// The clock set to `sim_s` (a restarted simulator going on after its
    /// last stamp, so stamps never repeat), at its waiting pace.
    pub fn starting_at(mut self, sim_s: f64) -> Self {
        self.sim_s = sim_s;
        self.anchor = (0.0, sim_s, 1.0);
        self
    }

    /// Simulated seconds so far.
    pub fn now(&self) -> f64 {
        self.sim_s
    }

    /// Simulated seconds the vehicle worked (drove, turned, scanned) and waited.
    pub fn split(&self) -> (f64, f64) {
        (self.working_s, self.waiting_s)
    }

    /// Advances one step at `wall_s` (seconds since the simulation began);
    /// returns the wall seconds to sleep before the next step.
    pub fn tick(&mut self, working: bool, wall_s: f64) -> f64 {
        let pace = if working { self.factor } else { 1.0 };
        if pace != self.anchor.2 {
            self.anchor = (wall_s, self.sim_s, pace);
        }
        self.sim_s += self.step_s;
        if working {
            self.working_s += self.step_s;
        } else {
            self.waiting_s += self.step_s;
        }
        let due = self.anchor.0 + (self.sim_s - self.anchor.1) / pace;
        if wall_s - due > MAX_LAG_S {
            self.anchor = (wall_s, self.sim_s, pace);
            return 0.0;
        }
        (due - wall_s).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `n` ticks with a simulator that needs `cost` wall s per step.
    fn run(c: &mut RobotClock, working: bool, n: usize, cost: f64, wall: &mut f64) {
        for _ in 0..n {
            *wall += cost;
            *wall += c.tick(working, *wall);
        }
    }

    #[test]
    fn working_runs_factor_times_faster() {
        let mut c = RobotClock::new(0.02, 20.0);
        let mut wall = 0.0;
        run(&mut c, true, 1000, 0.0, &mut wall);
        assert!((c.now() - 20.0).abs() < 1e-9);
        assert!((wall - 1.0).abs() < 1e-6, "{wall}");
    }

    #[test]
    fn waiting_runs_at_wall_speed() {
        let mut c = RobotClock::new(0.02, 20.0);
        let mut wall = 0.0;
        run(&mut c, false, 100, 0.0, &mut wall);
        assert!((wall - 2.0).abs() < 1e-6, "{wall}");
        assert_eq!(c.split(), (0.0, c.now()));
    }

    #[test]
    fn a_slow_simulator_does_not_catch_up_while_waiting() {
        let mut c = RobotClock::new(0.02, 20.0);
        let mut wall = 0.0;
        // Working at 4x instead of 20x: 10 simulated s take 2.5 wall s.
        run(&mut c, true, 500, 0.005, &mut wall);
        assert!((wall - 2.5).abs() < 0.01, "{wall}");
        // Then one wall second of waiting is one simulated second, not the
        // 40 simulated seconds a catching-up clock would count.
        let before = c.now();
        run(&mut c, false, 50, 0.0, &mut wall);
        assert!((c.now() - before - 1.0).abs() < 1e-9);
        assert!((wall - 3.5).abs() < 0.06, "{wall}");
        let (work, wait) = c.split();
        assert!((work - 10.0).abs() < 1e-9 && (wait - 1.0).abs() < 1e-9);
    }

    #[test]
    fn a_clock_started_later_goes_on_from_there_at_wall_speed() {
        let mut c = RobotClock::new(0.02, 20.0).starting_at(500.0);
        let mut wall = 0.0;
        run(&mut c, false, 50, 0.0, &mut wall);
        assert!((c.now() - 501.0).abs() < 1e-9);
        assert!(
            (wall - 1.0).abs() < 1e-6,
            "no sleep for the 500 s before: {wall}"
        );
    }
}
