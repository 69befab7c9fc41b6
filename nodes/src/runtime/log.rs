//! Node logging: every line goes to stderr and to /rosout, as rclpy nodes do.

use std::sync::Arc;
use std::time::{SystemTime, UNIX_EPOCH};

use ros2_client::builtin_interfaces::Time;
use ros2_client::log::LogLevel;
use ros2_client::rosout::{NodeLoggingHandle, RosoutRaw};

/// A cheap, clonable logger bound to one node.
#[derive(Clone)]
pub struct Logger {
    name: Arc<str>,
    rosout: Option<Arc<NodeLoggingHandle>>,
    min: Level,
}

/// Severity, in ROS 2's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    /// Debug detail.
    Debug,
    /// Normal progress.
    Info,
    /// Something odd, work goes on.
    Warn,
    /// Something failed, the node goes on.
    Error,
}

impl Level {
    /// Parses `--log-level` values (debug, info, warn, error; any case).
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "debug" => Some(Self::Debug),
            "info" => Some(Self::Info),
            "warn" | "warning" => Some(Self::Warn),
            "error" | "fatal" => Some(Self::Error),
            _ => None,
        }
    }

    fn tag(self) -> &'static str {
        match self {
            Self::Debug => "DEBUG",
            Self::Info => "INFO",
            Self::Warn => "WARN",
            Self::Error => "ERROR",
        }
    }
}

/// Writes one log line to stderr in rclpy's console format; returns its time.
pub(super) fn stderr_line(level: Level, name: &str, msg: &str) -> std::time::Duration {
    let now = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or_default();
    eprintln!(
        "[{}] [{}.{:09}] [{name}]: {msg}",
        level.tag(),
        now.as_secs(),
        now.subsec_nanos(),
    );
    now
}

impl Logger {
    /// A logger writing to stderr, and to /rosout when `rosout` is given.
    pub fn new(name: &str, rosout: Option<NodeLoggingHandle>, min: Level) -> Self {
        Self {
            name: name.into(),
            rosout: rosout.map(Arc::new),
            min,
        }
    }

    /// The same logger without /rosout: for where DDS may be stuck.
    pub fn stderr_only(&self) -> Self {
        Self {
            rosout: None,
            ..self.clone()
        }
    }

    /// Logs at `level`.
    pub fn log(&self, level: Level, msg: &str) {
        if level < self.min {
            return;
        }
        let now = stderr_line(level, &self.name, msg);
        if let Some(h) = &self.rosout {
            let stamp = Time::from_nanos(i64::try_from(now.as_nanos()).unwrap_or(i64::MAX));
            let lvl = match level {
                Level::Debug => LogLevel::Debug,
                Level::Info => LogLevel::Info,
                Level::Warn => LogLevel::Warn,
                Level::Error => LogLevel::Error,
            };
            h.rosout_raw(stamp, lvl, &self.name, msg, file!(), "", 0);
        }
    }

    /// Logs at debug level.
    pub fn debug(&self, msg: &str) {
        self.log(Level::Debug, msg);
    }

    /// Logs at info level.
    pub fn info(&self, msg: &str) {
        self.log(Level::Info, msg);
    }

    /// Logs at warn level.
    pub fn warn(&self, msg: &str) {
        self.log(Level::Warn, msg);
    }

    /// Logs at error level.
    pub fn error(&self, msg: &str) {
        self.log(Level::Error, msg);
    }

    /// Logs a failed publish on `topic` (a DDS write error) and says whether it went out.
    pub fn sent<E: std::fmt::Debug>(&self, topic: &str, r: Result<(), E>) -> bool {
        r.map_err(|e| self.warn(&format!("publishing on {topic} failed: {e:?}")))
            .is_ok()
    }
}

/// Warnings and errors of the DDS libraries (RustDDS, ros2-client), which
/// speak through the `log` facade: on the node's stderr, tagged `NAME/dds`,
/// so a participant that cannot join a multicast group or bind a port says
/// so in the node's log instead of showing up later as a silent stall.
/// Each kind of warning is shown once: RustDDS warns about every datagram
/// over 1,500 bytes, thousands a mission.
struct LibraryLog {
    name: Arc<str>,
    seen: std::sync::Mutex<std::collections::HashSet<String>>,
}

/// Library messages that say nothing about a fault: RustDDS notes every
/// datagram over 1,500 bytes (IP fragments it); ros2-client, that ROS_DISTRO
/// is unset (we speak kilted's types without a ROS install); every
/// ros2-client node reads /clock as builtin_interfaces/Time, which RustDDS
/// calls inconsistent with the rosgraph_msgs/Clock that clocks publish
/// (the runtime reads /clock itself); and at exit, readers and writers
/// dropped after their event loop stopped or while its queue was full
/// (nodes remove none while they run).
const HARMLESS: &[&str] = &[
    "Message size = ",
    "ROS_DISTRO is not set",
    "\"rosgraph_msgs::msg::dds_::Clock_\"",
    "Cannot remove Reader GUID",
    "Cannot remove Writer GUID",
    "Cannot notify spin task to stop",
];

/// A message with its numbers (decimal or hex: GUIDs) taken out: what makes
/// two warnings alike.
fn kind_of(msg: &str) -> String {
    msg.chars()
        .filter(|c| !c.is_ascii_hexdigit())
        .take(80)
        .collect()
}

impl log::Log for LibraryLog {
    fn enabled(&self, m: &log::Metadata<'_>) -> bool {
        m.level() <= log::Level::Warn
    }

    fn log(&self, r: &log::Record<'_>) {
        if !self.enabled(r.metadata()) {
            return;
        }
        let msg = r.args().to_string();
        if HARMLESS.iter().any(|h| msg.contains(h)) {
            return;
        }
        let first = self
            .seen
            .lock()
            .map_or(true, |mut seen| seen.insert(kind_of(&msg)));
        if !first {
            return;
        }
        let level = if r.level() == log::Level::Error {
            Level::Error
        } else {
            Level::Warn
        };
        let text = format!("{msg} ({}; alike ones not repeated)", r.target());
        stderr_line(level, &format!("{}/dds", self.name), &text);
    }

    fn flush(&self) {}
}

/// Sends the DDS libraries' warnings and errors to stderr as `name`'s (once
/// per process; later calls keep the first).
pub fn install_library_log(name: &str) {
    let logger = Box::new(LibraryLog {
        name: name.into(),
        seen: std::sync::Mutex::default(),
    });
    if log::set_boxed_logger(logger).is_ok() {
        log::set_max_level(log::LevelFilter::Warn);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alike_library_warnings_are_shown_once_and_harmless_ones_not_at_all() {
        let a = "Cannot get multicast discovery listener: Os { code: 19 }";
        let b = "Cannot get multicast discovery listener: Os { code: 98 }";
        assert_eq!(kind_of(a), kind_of(b));
        assert_ne!(kind_of(a), kind_of("Could not find free ParticipantId"));
        let guid = |g: &str| format!("Cannot remove Reader GUID {{{g}}}: gone");
        assert_eq!(
            kind_of(&guid("0112c504b413776e2f43d0f6")),
            kind_of(&guid("01128cf8d8d1b7d1fff80c66"))
        );
        let harmless = |m: &str| HARMLESS.iter().any(|h| m.contains(h));
        assert!(harmless("try_send_to_locator: Message size = 65348"));
        assert!(harmless(
            "Inconsistent topic update from GUID {x}: type was: \"rosgraph_msgs::msg::dds_::Clock_\" new type: \"builtin_interfaces::msg::dds_::Time_\""
        ));
        assert!(!harmless(a));
        assert!(!harmless(
            "SO_RCVBUF clamped: requested 33554432 bytes but got 8388608 bytes"
        ));
    }
}
