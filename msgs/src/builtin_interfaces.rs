//! `builtin_interfaces`: time stamps and durations.

use serde::{Deserialize, Serialize};

use crate::message::ros_message;

/// `builtin_interfaces/msg/Time`: a point in time (ROS or system clock).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct Time {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds past `sec`, in `0..1_000_000_000`.
    pub nanosec: u32,
}

impl Time {
    /// The time `s` seconds after the epoch (whole seconds floored, so the
    /// nanoseconds stay in range for negative times too).
    pub fn from_secs(s: f64) -> Self {
        let whole = s.floor();
        Time {
            sec: whole as i32,
            nanosec: (((s - whole) * 1e9) as u32).min(999_999_999),
        }
    }

    /// Seconds since the epoch.
    pub fn secs(&self) -> f64 {
        f64::from(self.sec) + f64::from(self.nanosec) * 1e-9
    }
}

/// `builtin_interfaces/msg/Duration`: a signed span of time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct Duration {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds added to `sec`, in `0..1_000_000_000`.
    pub nanosec: u32,
}

ros_message!(
    Time,
    "builtin_interfaces/msg/Time",
    [],
    ["int32 sec", "uint32 nanosec"]
);
ros_message!(
    Duration,
    "builtin_interfaces/msg/Duration",
    [],
    ["int32 sec", "uint32 nanosec"]
);

#[cfg(test)]
mod tests {
    use super::Time;

    #[test]
    fn seconds_round_trip_and_negative_times_keep_nanoseconds_in_range() {
        let t = Time::from_secs(12.25);
        assert_eq!((t.sec, t.nanosec), (12, 250_000_000));
        assert!((t.secs() - 12.25).abs() < 1e-9);
        let n = Time::from_secs(-0.5);
        assert_eq!((n.sec, n.nanosec), (-1, 500_000_000));
        assert!((n.secs() + 0.5).abs() < 1e-9);
    }
}
