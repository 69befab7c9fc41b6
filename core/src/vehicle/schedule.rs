//! When the simulated vehicle publishes: fixed rates in simulated time, and
//! a LiDAR that casts again only once it has moved (a 360° sensor that has
//! not moved sees what it saw).

/// An event due every `1 / rate_hz` simulated seconds, from t = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Every {
    period: f64,
    next: f64,
}

impl Every {
    /// Every `1 / rate_hz` s (rates below 1 mHz count as 1 mHz).
    pub fn new(rate_hz: f64) -> Self {
        Every {
            period: 1.0 / rate_hz.max(1e-3),
            next: 0.0,
        }
    }

    /// True when the event is due at `t`; the next one is one period later.
    pub fn due(&mut self, t: f64) -> bool {
        let due = t >= self.next;
        if due {
            self.next += self.period;
        }
        due
    }
}

/// When the LiDAR casts: at its rate once the sensor has moved
/// `min_move_m` since the last scan, else every `stationary_period_s`.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanSchedule {
    rate: Every,
    min_move_m: f64,
    stationary_period_s: f64,
    last: Option<([f32; 3], f64)>,
}

impl ScanSchedule {
    /// A schedule at `rate_hz`.
    pub fn new(rate_hz: f64, min_move_m: f64, stationary_period_s: f64) -> Self {
        ScanSchedule {
            rate: Every::new(rate_hz),
            min_move_m,
            stationary_period_s,
            last: None,
        }
    }

    /// True when a scan is to be cast at `t` with the sensor at `sensor`.
    pub fn due(&mut self, t: f64, sensor: [f32; 3]) -> bool {
        if !self.rate.due(t) {
            return false;
        }
        let moved = |(q, t0): ([f32; 3], f64)| {
            let d: f32 = (0..3).map(|k| (sensor[k] - q[k]).powi(2)).sum();
            f64::from(d.sqrt()) >= self.min_move_m || t - t0 >= self.stationary_period_s
        };
        let due = self.last.is_none_or(moved);
        if due {
            self.last = Some((sensor, t));
        }
        due
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rate_fires_once_per_period() {
        let mut e = Every::new(10.0);
        let fired = (0..100).filter(|i| e.due(f64::from(*i) * 0.01)).count();
        assert_eq!(fired, 10);
    }

    #[test]
    fn a_standing_sensor_scans_only_every_stationary_period() {
        let mut s = ScanSchedule::new(10.0, 0.5, 2.0);
        let times: Vec<f64> = (0..=50).map(|i| f64::from(i) * 0.1).collect();
        let standing: Vec<f64> = times
            .iter()
            .copied()
            .filter(|&t| s.due(t, [0.0; 3]))
            .collect();
        assert_eq!(standing.len(), 3, "{standing:?}");
        assert!((standing[1] - 2.0).abs() < 0.11, "{standing:?}");
        // Moving 1 m/s: every fifth LiDAR period has moved 0.5 m (bar rounding).
        let mut s = ScanSchedule::new(10.0, 0.5, 2.0);
        let moving = times
            .iter()
            .filter(|&&t| s.due(t, [t as f32, 0.0, 0.0]))
            .count();
        assert!((10..=11).contains(&moving), "{moving}");
    }
}
