//! `diagnostic_msgs`: health reports of components.

use serde::{Deserialize, Serialize};

use crate::message::ros_message;
use crate::std_msgs::Header;

/// `diagnostic_msgs/msg/KeyValue`: one named value of a status report.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct KeyValue {
    /// What the value is.
    pub key: String,
    /// The value, as text.
    pub value: String,
}

/// `diagnostic_msgs/msg/DiagnosticStatus`: the state of one component.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct DiagnosticStatus {
    /// Severity: [`DiagnosticStatus::OK`], `WARN`, `ERROR` or `STALE` (a .msg `byte`).
    pub level: u8,
    /// Component name.
    pub name: String,
    /// Human-readable summary.
    pub message: String,
    /// Hardware identifier, if any.
    pub hardware_id: String,
    /// Further named values.
    pub values: Vec<KeyValue>,
}

impl DiagnosticStatus {
    /// Level: all is well.
    pub const OK: u8 = 0;
    /// Level: degraded.
    pub const WARN: u8 = 1;
    /// Level: failed.
    pub const ERROR: u8 = 2;
    /// Level: no recent report.
    pub const STALE: u8 = 3;
}

/// `diagnostic_msgs/msg/DiagnosticArray`: several status reports at one time.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct DiagnosticArray {
    /// Stamp of the report.
    pub header: Header,
    /// One status per component.
    pub status: Vec<DiagnosticStatus>,
}

ros_message!(
    KeyValue,
    "diagnostic_msgs/msg/KeyValue",
    [],
    ["string key", "string value"]
);
ros_message!(
    DiagnosticStatus,
    "diagnostic_msgs/msg/DiagnosticStatus",
    [KeyValue],
    [
        "byte OK = 0",
        "byte WARN = 1",
        "byte ERROR = 2",
        "byte STALE = 3",
        "byte level",
        "string name",
        "string message",
        "string hardware_id",
        "diagnostic_msgs/KeyValue[] values",
    ]
);
ros_message!(
    DiagnosticArray,
    "diagnostic_msgs/msg/DiagnosticArray",
    [Header, DiagnosticStatus],
    [
        "std_msgs/Header header",
        "diagnostic_msgs/DiagnosticStatus[] status"
    ]
);
