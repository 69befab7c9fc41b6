//! Scans on /registered_scan as the explorer's events: decoded, or logged
//! and dropped when malformed (the node goes on).

use std::time::{Duration, Instant};

use futures::StreamExt;
use ros2_client::Subscription;
use skyground_core::mission::explorer::ExplorerEvent;
use skyground_core::mission::scan_ids::{self, SentLog};
use skyground_core::vehicle::RobotClock;
use skyground_msgs::sensor_msgs::PointCloud2;
use tokio::sync::mpsc::UnboundedReceiver;

use super::pointcloud2::decode;
use super::scan_store::ScanInbox;
use crate::runtime::{Logger, NodeRuntime, RuntimeError, qos};
use crate::transport::{CloudPublisher, TransportConfig};

/// Scans the subscription holds before the oldest is dropped; the explorer
/// takes them as they come ([`scan_feed`]), so this only bounds a burst.
const SCAN_DEPTH: usize = 1024;

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

/// Scans larger than this are paced by their acknowledgements: above a
/// 16-beam LiDAR's whole revolution (28,800 points, 0.7 MB), below one of a
/// 64-beam's.
pub const PACED_SCAN_BYTES: usize = 1 << 20;

/// The writer's history: scans a reader has not acknowledged stay in it for
/// repair until this many newer ones push them out (then they are lost).
const SCAN_HISTORY: usize = 64;

/// Scans written between two waits for acknowledgements: a quarter of the
/// history, so a reader that stops acknowledging (stuck repairing a
/// fragmented scan, starved, stopped) has four waits of up to 3 s, ~12 s,
/// before its oldest unacknowledged scan is pushed out.
const PACE_EVERY: usize = SCAN_HISTORY / 4;

/// vehicle_sim's /registered_scan writer: reliable (a best-effort multi-MB
/// scan is lost with any one fragment), on a DDS writer of its own so that
/// scans wait for the first reader and the node, before it exits, for every
/// scan's acknowledgement.
pub struct ScanWriter {
    w: CloudPublisher,
    since: Instant,
    wait: Duration,
    open: bool,
    /// The log of the ids sent, and the last id it held at start.
    log: Option<SentLog>,
    last: Option<u64>,
    /// The platform index the ids carry (see `scan_ids::tagged`).
    platform: u8,
    /// Scans written since the last wait for acknowledgements.
    unpaced: std::cell::Cell<usize>,
}

impl ScanWriter {
    /// The writer; scans are cast once a reader matched, or after `wait`;
    /// the id of every scan DDS takes is appended to `scan_log` ("": none).
    pub fn new(rt: &mut NodeRuntime, wait: Duration, scan_log: &str) -> Result<Self, RuntimeError> {
        Self::on(rt, ("/registered_scan", 0), wait, scan_log)
    }

    /// As [`ScanWriter::new`], on `topic` for platform `platform` (the
    /// drone's /uav/registered_scan, 1): its logged ids carry the platform.
    pub fn on(
        rt: &mut NodeRuntime,
        (topic, platform): (&str, u8),
        wait: Duration,
        scan_log: &str,
    ) -> Result<Self, RuntimeError> {
        let err = |e: skyground_core::file::FileError| RuntimeError::Node(format!("scan_log: {e}"));
        let (log, last) = if scan_log.is_empty() {
            (None, None)
        } else {
            let path = std::path::Path::new(scan_log);
            // The log may be shared by both platforms: this one's last id.
            let ids = scan_ids::read_log(path).map_err(err)?.into_iter();
            let last = ids
                .filter(|&id| scan_ids::platform(id) == platform)
                .map(scan_ids::untagged)
                .max();
            (Some(SentLog::open(path).map_err(err)?), last)
        };
        let keep = TransportConfig {
            history_tiles: 1,
            ack_timeout_s: 3.0,
            ..TransportConfig::default()
        };
        let w = CloudPublisher::new(rt, topic, qos::reliable(SCAN_HISTORY), keep)?;
        Ok(Self {
            w,
            since: Instant::now(),
            wait,
            open: false,
            log,
            last,
            platform,
            unpaced: std::cell::Cell::new(0),
        })
    }

    /// `clock` going on a step after the last scan the log held (a
    /// restarted or resumed vehicle_sim, so that stamps, the ids, never repeat).
    pub fn go_on(&self, clock: RobotClock, step_s: f64, log: &Logger) -> RobotClock {
        let Some(last) = self.last else {
            return clock;
        };
        let at = scan_ids::secs(last) + step_s;
        log.info(&format!(
            "robot time goes on at {at:.2} s, after the last scan sent"
        ));
        clock.starting_at(at)
    }

    /// Whether to cast scans now: a volatile reader matched later would
    /// never get the ones written before it (issue 50: scans sent = merged).
    pub fn ready(&mut self, log: &Logger) -> bool {
        if !self.open && (self.w.newly_matched() || self.since.elapsed() >= self.wait) {
            self.open = true;
            if self.since.elapsed() >= self.wait {
                log.warn(&format!(
                    "no reader of /registered_scan within {:?}",
                    self.wait
                ));
            }
        }
        self.open
    }

    /// Writes one scan whole; one over [`PACED_SCAN_BYTES`], and every
    /// [`PACE_EVERY`]th, then waits (up to 3 s) for the acknowledgements:
    /// RustDDS sends 256-byte fragments and asks again for at most 256 lost
    /// ones at a time, so a burst of multi-MB scans that overflowed the
    /// reader's socket buffer took the rest of a mission to repair (issue 50:
    /// 49 of 168 scans arrived), and a reader that stopped acknowledging for
    /// 8 s lost 544 of 873 scans to the history's overflow.
    pub async fn write(&self, msg: PointCloud2) -> Result<(), RuntimeError> {
        let large = msg.data.len() > PACED_SCAN_BYTES;
        let stamp = scan_ids::id(msg.header.stamp.sec, msg.header.stamp.nanosec);
        let id = scan_ids::tagged(stamp, self.platform);
        self.w.write(msg).await?;
        if let Some(log) = &self.log {
            log.sent(id)
                .map_err(|e| RuntimeError::Node(format!("scan_log: {e}")))?;
        }
        let unpaced = self.unpaced.get() + 1;
        if large || unpaced >= PACE_EVERY {
            self.w.wait_acks().await;
            self.unpaced.set(0);
        } else {
            self.unpaced.set(unpaced);
        }
        Ok(())
    }

    /// Waits (up to 3 s) until every reliable reader acknowledged every scan.
    pub async fn wait_acks(&self) -> bool {
        self.w.wait_acks().await
    }
}

/// The explorer's event for one received scan; none for a read error or a
/// malformed cloud (said in the log).
fn scan_event<I, E>(
    log: &Logger,
    platform: u8,
    m: Result<(PointCloud2, I), E>,
) -> Option<ExplorerEvent> {
    let (msg, _) = m.ok()?;
    match decode(&msg) {
        Ok(d) => Some(ExplorerEvent::Scan {
            // Its stamp, marked with its platform, is its id (see skyground_core::mission::scan_ids).
            id: scan_ids::tagged(
                scan_ids::id(msg.header.stamp.sec, msg.header.stamp.nanosec),
                platform,
            ),
            xyz: d.cloud.xyz,
            labels: d.cloud.label,
        }),
        Err(e) => {
            log.warn(&format!("rejected a scan (platform {platform}): {e}"));
            None
        }
    }
}

/// Every scan of `sub`, taken as it arrives by a task of its own into an
/// unbounded queue: nothing the explorer does in between (a region planned,
/// its 13 M-point merge published at ~20 s paced by acknowledgements) stops
/// their reception, so the subscription's history never overflows (126 of
/// the reference demo's 9,966 scans were dropped there before; issue 50).
/// Each subscription comes with the platform index its scans' ids carry
/// (the ground robot's /registered_scan 0, the drone's /uav/registered_scan
/// 1). Each scan is written to `inbox` first: a killed explorer loses none
/// of those waiting in the queue.
pub fn scan_feed(
    log: Logger,
    subs: Vec<(Subscription<PointCloud2>, u8)>,
    inbox: Option<ScanInbox>,
) -> UnboundedReceiver<ExplorerEvent> {
    let (tx, rx) = tokio::sync::mpsc::unbounded_channel();
    for (sub, platform) in subs {
        feed_into(log.clone(), (sub, platform), inbox.clone(), tx.clone());
    }
    rx
}

/// The scans of `sub` into `inbox` and `tx`, in a task of their own.
fn feed_into(
    log: Logger,
    (sub, platform): (Subscription<PointCloud2>, u8),
    inbox: Option<ScanInbox>,
    tx: tokio::sync::mpsc::UnboundedSender<ExplorerEvent>,
) {
    tokio::spawn(async move {
        let scans = sub.async_stream();
        futures::pin_mut!(scans);
        let mut failures = 0;
        while let Some(m) = scans.next().await {
            let Some(e) = scan_event(&log, platform, m) else {
                continue;
            };
            if let Some(inbox) = &inbox {
                inbox.take(&e, &mut failures);
            }
            if tx.send(e).is_err() {
                break;
            }
        }
    });
}

/// The scans still arriving after a stop was asked, until none comes for
/// 0.3 s or `within` has passed (a robot that goes on scanning): the demo
/// stops vehicle_sim first, so every scan it sent is merged.
pub async fn late_scans(
    log: &Logger,
    scans: &mut UnboundedReceiver<ExplorerEvent>,
    within: Duration,
) -> Vec<ExplorerEvent> {
    let until = Instant::now() + within;
    let mut events = Vec::new();
    while Instant::now() < until
        && let Ok(Some(e)) = tokio::time::timeout(Duration::from_millis(300), scans.recv()).await
    {
        events.push(e);
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
