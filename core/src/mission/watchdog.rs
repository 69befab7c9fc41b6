//! Progress watched, not only time: the robot's clock (odometry stamps)
//! advances while the vehicle drives and while it waits for orders, so a
//! clock that stops while the mission runs names a stalled vehicle node
//! (or the link to it). The launcher restarts it; after `max_restarts`
//! restarts in a row without the clock moving, the mission stops.

/// What the watchdog asks for now.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ClockVerdict {
    /// The clock moves (or has not started yet).
    Fine,
    /// Restart the vehicle: its clock stood at `robot_s` for `for_s` wall seconds.
    Restart {
        /// Robot seconds where the clock stopped.
        robot_s: f64,
        /// Wall seconds it has not moved.
        for_s: f64,
    },
    /// Stop the mission: `restarts` restarts in a row did not move the clock.
    GiveUp {
        /// Restarts made since the clock last moved.
        restarts: u32,
    },
}

/// Follows the robot's clock against the wall clock.
#[derive(Debug, Clone)]
pub struct Watchdog {
    stall_s: f64,
    max_restarts: u32,
    /// The newest robot time and the wall time it was first seen (or of the last restart).
    last: Option<(f64, f64)>,
    restarts: u32,
}

impl Watchdog {
    /// A clock standing `stall_s` wall seconds is a stall; `max_restarts` in
    /// a row without progress end the mission.
    pub fn new(stall_s: f64, max_restarts: u32) -> Self {
        Watchdog {
            stall_s,
            max_restarts,
            last: None,
            restarts: 0,
        }
    }

    /// The robot's clock read `robot_s` at wall time `wall_s`; any other
    /// reading than the last is progress (a restarted simulator's clock
    /// starts again at 0).
    pub fn robot_time(&mut self, robot_s: f64, wall_s: f64) {
        if self.last.is_none_or(|(r, _)| robot_s != r) {
            if self.last.is_some() {
                self.restarts = 0;
            }
            self.last = Some((robot_s, wall_s));
        }
    }

    /// What to do at wall time `wall_s`.
    pub fn check(&mut self, wall_s: f64) -> ClockVerdict {
        let Some((robot_s, since)) = self.last else {
            return ClockVerdict::Fine;
        };
        let for_s = wall_s - since;
        if for_s < self.stall_s {
            return ClockVerdict::Fine;
        }
        if self.restarts >= self.max_restarts {
            return ClockVerdict::GiveUp {
                restarts: self.restarts,
            };
        }
        self.restarts += 1;
        // The restarted node gets a whole period to show its clock.
        self.last = Some((robot_s, wall_s));
        ClockVerdict::Restart { robot_s, for_s }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_moving_clock_is_fine_a_stopped_one_restarts_then_gives_up() {
        let mut w = Watchdog::new(30.0, 2);
        assert_eq!(w.check(100.0), ClockVerdict::Fine, "no clock yet");
        w.robot_time(5.0, 0.0);
        w.robot_time(50.0, 20.0);
        assert_eq!(w.check(45.0), ClockVerdict::Fine);
        // Stamps that repeat are no progress.
        w.robot_time(50.0, 40.0);
        w.robot_time(50.0, 45.0);
        assert_eq!(
            w.check(51.0),
            ClockVerdict::Restart {
                robot_s: 50.0,
                for_s: 31.0
            }
        );
        assert_eq!(
            w.check(60.0),
            ClockVerdict::Fine,
            "a period for the restart"
        );
        assert!(matches!(w.check(81.0), ClockVerdict::Restart { .. }));
        assert_eq!(w.check(112.0), ClockVerdict::GiveUp { restarts: 2 });
    }

    #[test]
    fn progress_after_a_restart_resets_the_count() {
        let mut w = Watchdog::new(30.0, 1);
        w.robot_time(1.0, 0.0);
        assert!(matches!(w.check(31.0), ClockVerdict::Restart { .. }));
        w.robot_time(2.0, 40.0);
        assert!(
            matches!(w.check(71.0), ClockVerdict::Restart { .. }),
            "a new stall, not a give-up"
        );
    }
}
