//! The `skyground` command's subcommands (each a thin shell around the library
//! or the node runtime).

pub mod aerial;
pub mod bench;
pub mod city_model;
pub mod classify;
pub mod crop;
pub mod demo;
pub mod detect;
pub mod detections;
pub mod echo;
pub mod eval;
pub mod field;
pub mod footprints;
pub mod info;
pub mod merged;
pub mod plan;
pub mod play;
pub mod prior;
pub mod profile;
pub mod reconstruct;
pub mod record;
pub mod sink;
pub mod units;

use std::time::{Duration, Instant};

use ros2_client::QosProfile;

use crate::runtime::{NodeRuntime, NodeSpec, RuntimeError, qos};
use crate::tap::{TopicInfo, discover};

/// A library error as a subcommand's error (its message is the user's).
pub fn err(e: impl std::fmt::Display) -> RuntimeError {
    RuntimeError::Node(e.to_string())
}

/// `e` as an error about `files`: its message names them first, unless it
/// already names one (a user who ran a command on several files learns
/// which one was refused).
pub fn about(files: &[std::path::PathBuf], e: RuntimeError) -> RuntimeError {
    let text = e.to_string();
    if files
        .iter()
        .any(|f| text.contains(&f.display().to_string()))
    {
        return e;
    }
    RuntimeError::Node(format!("{}: {text}", units::describe(files)))
}

/// A node spec for a CLI tool (no params file).
pub const fn tool_spec(name: &'static str) -> NodeSpec {
    NodeSpec {
        name,
        default_params: "",
        live: &[],
    }
}

/// Waits up to `timeout` for a publisher of `topic` to be discovered.
pub async fn wait_for_topic(rt: &NodeRuntime, topic: &str, timeout: Duration) -> Option<TopicInfo> {
    let end = Instant::now() + timeout;
    loop {
        if let Some(info) = discover(rt, topic) {
            return Some(info);
        }
        if Instant::now() > end || rt.shutdown.requested() {
            return None;
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// The QoS that matches every discovered publisher and gets latched data.
pub fn qos_for(info: &TopicInfo, depth: usize) -> QosProfile {
    match (info.reliable, info.transient_local) {
        (true, true) => qos::latched(depth),
        (true, false) => qos::reliable(depth),
        _ => qos::sensor(depth),
    }
}

/// Splits `TOPIC[:TYPE]`.
pub fn topic_and_type(arg: &str) -> (String, Option<String>) {
    match arg.split_once(':') {
        Some((t, ty)) if !ty.is_empty() => (t.to_string(), Some(ty.to_string())),
        _ => (arg.to_string(), None),
    }
}

/// Resolves a topic's type and QoS: explicit type and QoS name win, the rest
/// comes from discovery.
pub async fn resolve(
    rt: &NodeRuntime,
    topic: &str,
    type_name: Option<&str>,
    qos_name: &str,
    depth: usize,
    timeout: Duration,
) -> Result<(String, QosProfile), RuntimeError> {
    let explicit_qos = if qos_name == "auto" {
        None
    } else {
        Some(qos::by_name(qos_name, depth).ok_or_else(|| {
            RuntimeError::Node(format!(
                "unknown qos `{qos_name}` (auto, latched, reliable, sensor)"
            ))
        })?)
    };
    if let (Some(t), Some(q)) = (type_name, explicit_qos.clone()) {
        return Ok((t.to_string(), q));
    }
    let info = wait_for_topic(rt, topic, timeout).await.ok_or_else(|| {
        RuntimeError::Node(format!(
            "no publisher of {topic} discovered within {:.0} s (give its type as {topic}:pkg/msg/Type)",
            timeout.as_secs_f64()
        ))
    })?;
    let q = explicit_qos.unwrap_or_else(|| qos_for(&info, depth));
    Ok((type_name.map_or(info.type_name, str::to_string), q))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn topic_type_split() {
        assert_eq!(
            topic_and_type("/a:nav_msgs/msg/Path"),
            ("/a".to_string(), Some("nav_msgs/msg/Path".to_string()))
        );
        assert_eq!(topic_and_type("/a"), ("/a".to_string(), None));
    }
}
