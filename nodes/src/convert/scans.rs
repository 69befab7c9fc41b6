//! Scans on /registered_scan as the explorer's events: decoded, or logged
//! and dropped when malformed (the node goes on).

use std::time::{Duration, Instant};

use futures::{Stream, StreamExt};
use skyground_core::mission::explorer::ExplorerEvent;
use skyground_msgs::sensor_msgs::PointCloud2;

use super::pointcloud2::decode;
use crate::runtime::{Logger, RuntimeError, qos};

/// Scans a subscription holds before the oldest is dropped: a burst of
/// multi-MB scans arrives faster than they are merged (issue 50).
const SCAN_DEPTH: usize = 64;

/// The QoS named by the explorer's `scan_qos`: `sensor` (best effort, as
/// robot drivers publish) or `reliable` (vehicle_sim's writer: no scan lost).
pub fn scan_qos(name: &str) -> Result<ros2_client::QosProfile, RuntimeError> {
    match name {
        "sensor" => Ok(qos::sensor(SCAN_DEPTH)),
        "reliable" => Ok(qos::reliable(SCAN_DEPTH)),
        _ => Err(RuntimeError::Node(format!(
            "scan_qos {name:?}: not sensor or reliable"
        ))),
    }
}

/// The explorer's event for one received scan; none for a read error or a
/// malformed cloud (said in the log).
pub fn scan_event<I, E>(log: &Logger, m: Result<(PointCloud2, I), E>) -> Option<ExplorerEvent> {
    let (msg, _) = m.ok()?;
    match decode(&msg) {
        Ok(d) => Some(ExplorerEvent::Scan {
            xyz: d.cloud.xyz,
            labels: d.cloud.label,
        }),
        Err(e) => {
            log.warn(&format!("rejected /registered_scan: {e}"));
            None
        }
    }
}

/// The scans still arriving on `scans` after a stop was asked, until none
/// comes for 0.3 s or `within` has passed (a robot that goes on scanning):
/// the demo stops vehicle_sim first, so every scan it sent is merged.
pub async fn late_scans<S, I, E>(
    log: &Logger,
    scans: &mut S,
    within: Duration,
) -> Vec<ExplorerEvent>
where
    S: Stream<Item = Result<(PointCloud2, I), E>> + Unpin,
{
    let until = Instant::now() + within;
    let mut events = Vec::new();
    while Instant::now() < until
        && let Ok(Some(m)) = tokio::time::timeout(Duration::from_millis(300), scans.next()).await
    {
        events.extend(scan_event(log, m));
    }
    if !events.is_empty() {
        log.info(&format!("{} scan(s) came as it stopped", events.len()));
    }
    events
}

#[cfg(test)]
mod tests {
    use super::*;
    use ros2_client::qos::Reliability;

    #[test]
    fn scan_qos_names_best_effort_or_reliable_and_refuses_others() {
        assert_eq!(
            scan_qos("sensor").unwrap().reliability,
            Reliability::BestEffort
        );
        assert!(matches!(
            scan_qos("reliable").unwrap().reliability,
            Reliability::Reliable { .. }
        ));
        let e = scan_qos("fast").unwrap_err().to_string();
        assert!(
            e.contains("\"fast\"") && e.contains("sensor or reliable"),
            "{e}"
        );
    }
}
