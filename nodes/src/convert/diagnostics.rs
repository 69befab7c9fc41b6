//! diagnostic_msgs helpers.

use skyground_core::mission::{ProtocolError, Wire};
use skyground_msgs::diagnostic_msgs::{DiagnosticArray, DiagnosticStatus, KeyValue};
use skyground_msgs::std_msgs::Header;

use crate::runtime::Logger;

/// A key–value pair.
pub fn kv(key: &str, value: impl ToString) -> KeyValue {
    KeyValue {
        key: key.into(),
        value: value.to_string(),
    }
}

/// A status with its values.
pub fn status(
    name: impl Into<String>,
    level: u8,
    message: impl Into<String>,
    values: Vec<KeyValue>,
) -> DiagnosticStatus {
    DiagnosticStatus {
        level,
        name: name.into(),
        message: message.into(),
        hardware_id: String::new(),
        values,
    }
}

/// The value of `key` in a status, parsed.
pub fn value<T: std::str::FromStr>(s: &DiagnosticStatus, key: &str) -> Option<T> {
    s.values
        .iter()
        .find(|v| v.key == key)
        .and_then(|v| v.value.parse().ok())
}

/// A mission status (core's wire form) as the message.
pub fn to_status(w: Wire) -> DiagnosticStatus {
    DiagnosticStatus {
        level: w.level,
        name: w.name,
        message: w.message,
        hardware_id: String::new(),
        values: w
            .values
            .into_iter()
            .map(|(key, value)| KeyValue { key, value })
            .collect(),
    }
}

/// A message as core's wire form, to be read by a mission status.
pub fn from_status(s: &DiagnosticStatus) -> Wire {
    Wire {
        level: s.level,
        name: s.name.clone(),
        message: s.message.clone(),
        values: s
            .values
            .iter()
            .map(|kv| (kv.key.clone(), kv.value.clone()))
            .collect(),
    }
}

/// Every status of a received array read as `T`; unreadable ones are logged.
pub fn statuses<T, I, E>(
    log: &Logger,
    m: Result<(DiagnosticArray, I), E>,
    read: fn(&Wire) -> Result<T, ProtocolError>,
) -> Vec<T> {
    let Ok((arr, _)) = m else { return vec![] };
    arr.status
        .iter()
        .filter_map(|s| {
            read(&from_status(s))
                .map_err(|e| log.warn(&e.to_string()))
                .ok()
        })
        .collect()
}

/// One mission status in an array.
pub fn array(header: Header, w: Wire) -> DiagnosticArray {
    DiagnosticArray {
        header,
        status: vec![to_status(w)],
    }
}

#[cfg(test)]
mod tests {
    use skyground_core::mission::{BlockedSpot, PlannerStatus};

    use super::*;

    #[test]
    fn a_mission_status_round_trips_through_the_message() {
        let s = PlannerStatus {
            phase: "driving".into(),
            round: 2,
            target_points: 5,
            active_region: Some((3, 11)),
            blocked: vec![BlockedSpot {
                at: [1.5, -2.25],
                radius: 0.9,
            }],
            ..PlannerStatus::default()
        };
        let msg = to_status(s.to_wire());
        assert_eq!(msg.message, "driving");
        assert_eq!(value::<u32>(&msg, "round"), Some(2));
        assert_eq!(PlannerStatus::from_wire(&from_status(&msg)), Ok(s));
    }

    #[test]
    fn values_round_trip() {
        let s = status(
            "b1",
            DiagnosticStatus::OK,
            "ok",
            vec![kv("r_missing", 0.25), kv("n", 3)],
        );
        assert_eq!(value::<f64>(&s, "r_missing"), Some(0.25));
        assert_eq!(value::<u32>(&s, "n"), Some(3));
        assert_eq!(value::<u32>(&s, "absent"), None);
    }
}
