//! A node's work counter ([`skyground_core::work`]) on /work_progress every
//! [`EVERY`], from a task of its own: it goes on while the node's event loop
//! is deep in a long computation, so the demo's watchdog sees the count move
//! in a long replan and stand in a node spinning without progress, or stopped.

use std::time::Duration;

use skyground_msgs::diagnostic_msgs::{DiagnosticArray, DiagnosticStatus, KeyValue};

use super::{NodeRuntime, RuntimeError, qos};

/// The topic.
pub const TOPIC: &str = "/work_progress";
/// How often the count goes out.
pub const EVERY: Duration = Duration::from_secs(2);

/// The message saying `node` has done `steps` steps.
pub fn message(node: &str, steps: u64) -> DiagnosticArray {
    DiagnosticArray {
        header: Default::default(),
        status: vec![DiagnosticStatus {
            level: DiagnosticStatus::OK,
            name: node.into(),
            message: "work steps done".into(),
            hardware_id: String::new(),
            values: vec![KeyValue {
                key: "steps".into(),
                value: steps.to_string(),
            }],
        }],
    }
}

/// The node and steps a message says; `None` for another message.
pub fn read(m: &DiagnosticArray) -> Option<(&str, u64)> {
    let s = m.status.first()?;
    let v = s.values.iter().find(|v| v.key == "steps")?;
    Some((s.name.as_str(), v.value.parse().ok()?))
}

/// Starts publishing this node's work count.
pub fn beat(rt: &mut NodeRuntime, node: &'static str) -> Result<(), RuntimeError> {
    let publisher = rt.publisher::<DiagnosticArray>(TOPIC, qos::sensor(4))?;
    tokio::spawn(async move {
        let mut tick = tokio::time::interval(EVERY);
        loop {
            tick.tick().await;
            let m = message(node, skyground_core::work::steps());
            let _ = publisher.async_publish(m).await;
        }
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_work_message_reads_back_and_another_does_not() {
        assert_eq!(
            read(&message("global_planner", 42)),
            Some(("global_planner", 42))
        );
        let mut other = message("x", 1);
        other.status[0].values.clear();
        assert_eq!(read(&other), None);
        assert_eq!(read(&DiagnosticArray::default()), None);
    }
}
