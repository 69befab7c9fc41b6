//! diagnostic_msgs helpers.

use skyground_msgs::diagnostic_msgs::{DiagnosticStatus, KeyValue};

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

#[cfg(test)]
mod tests {
    use super::*;

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
