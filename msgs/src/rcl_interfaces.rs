//! `rcl_interfaces`: log records as published on `/rosout`.

use serde::{Deserialize, Serialize};

use crate::builtin_interfaces::Time;
use crate::message::ros_message;

/// `rcl_interfaces/msg/Log`: one log record of a node.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct Log {
    /// When the record was made.
    pub stamp: Time,
    /// Severity, one of the level constants below.
    pub level: u8,
    /// Logger name (usually the node name).
    pub name: String,
    /// The message text.
    pub msg: String,
    /// Source file of the call.
    pub file: String,
    /// Function of the call.
    pub function: String,
    /// Line of the call.
    pub line: u32,
}

impl Log {
    /// Level: debug.
    pub const DEBUG: u8 = 10;
    /// Level: info.
    pub const INFO: u8 = 20;
    /// Level: warning.
    pub const WARN: u8 = 30;
    /// Level: error.
    pub const ERROR: u8 = 40;
    /// Level: fatal.
    pub const FATAL: u8 = 50;
}

ros_message!(
    Log,
    "rcl_interfaces/msg/Log",
    [Time],
    [
        "uint8 DEBUG = 10",
        "uint8 INFO = 20",
        "uint8 WARN = 30",
        "uint8 ERROR = 40",
        "uint8 FATAL = 50",
        "builtin_interfaces/Time stamp",
        "uint8 level",
        "string name",
        "string msg",
        "string file",
        "string function",
        "uint32 line",
    ]
);
