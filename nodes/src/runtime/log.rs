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

impl Logger {
    /// A logger writing to stderr, and to /rosout when `rosout` is given.
    pub fn new(name: &str, rosout: Option<NodeLoggingHandle>, min: Level) -> Self {
        Self {
            name: name.into(),
            rosout: rosout.map(Arc::new),
            min,
        }
    }

    /// Logs at `level`.
    pub fn log(&self, level: Level, msg: &str) {
        if level < self.min {
            return;
        }
        let now = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .unwrap_or_default();
        eprintln!(
            "[{}] [{}.{:09}] [{}]: {}",
            level.tag(),
            now.as_secs(),
            now.subsec_nanos(),
            self.name,
            msg
        );
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
