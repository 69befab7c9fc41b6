//! Publishing clouds of any size so that stock receivers get them whole.

use std::time::{Duration, Instant};

use crate::convert::pointcloud2::tiles;
use futures::{FutureExt, StreamExt};
use ros2_client::QosProfile;
use rustdds::no_key::DataWriterCdr;
use rustdds::{DataWriterStatus, QosPolicies, StatusEvented, TopicDescription};
use serde::Deserialize;
use skyground_msgs::sensor_msgs::PointCloud2;

use crate::runtime::{NodeRuntime, RuntimeError};

/// How clouds are cut and paced (the `transport.*` params of cloud nodes).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TransportConfig {
    /// Points per tile; receivers must use the same value to reassemble.
    pub tile_points: u32,
    /// Tiles sent before waiting for every reliable reader's acknowledgement.
    pub window_tiles: usize,
    /// Longest wait for acknowledgements before going on (a dead reader must
    /// not stall the publisher), seconds.
    pub ack_timeout_s: f64,
    /// History kept for late joiners, in tiles (bounds the latched cloud size).
    pub history_tiles: usize,
}

impl Default for TransportConfig {
    fn default() -> Self {
        Self {
            tile_points: tiles::DEFAULT_TILE_POINTS,
            window_tiles: 4,
            ack_timeout_s: 10.0,
            history_tiles: 256,
        }
    }
}

/// What one publish did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PublishStats {
    /// Messages sent.
    pub tiles: usize,
    /// Payload bytes (point data only).
    pub bytes: usize,
    /// Wall time until every reader acknowledged (or the timeout), seconds.
    pub seconds: f64,
    /// False when some reader did not acknowledge within the timeout.
    pub acknowledged: bool,
}

/// A PointCloud2 publisher that tiles and paces (see the module docs).
///
/// It writes through a RustDDS DataWriter of its own, because ros2-client's
/// Publisher does not expose acknowledgement waits; topic name, type and QoS
/// are the ROS 2 ones, so every ROS 2 subscriber matches it.
pub struct CloudPublisher {
    writer: DataWriterCdr<PointCloud2>,
    participant: rustdds::DomainParticipant,
    dds_topic: String,
    config: TransportConfig,
}

impl CloudPublisher {
    /// Creates the publisher; `qos` history is raised to `history_tiles`.
    pub fn new(
        rt: &mut NodeRuntime,
        topic: &str,
        qos: QosProfile,
        config: TransportConfig,
    ) -> Result<Self, RuntimeError> {
        let qos = match qos.history {
            ros2_client::qos::History::KeepLast { depth } => {
                qos.history(ros2_client::qos::History::KeepLast {
                    depth: depth.max(config.history_tiles),
                })
            }
            ros2_client::qos::History::KeepAll => qos,
        };
        let t = rt.topic::<PointCloud2>(topic, &qos)?;
        let dds_qos: QosPolicies = (&qos).into();
        let create = |what: &str, e: String| RuntimeError::Create {
            what: format!("{what} for {topic}"),
            reason: e,
        };
        let _armed = rt.creating(&format!("DDS writer for {topic}"));
        let publisher = rt
            .context()
            .domain_participant()
            .create_publisher(&dds_qos)
            .map_err(|e| create("DDS publisher", e.to_string()))?;
        let writer = publisher
            .create_datawriter_no_key_cdr::<PointCloud2>(&t, Some(dds_qos))
            .map_err(|e| create("DDS writer", e.to_string()))?;
        Ok(Self {
            writer,
            participant: rt.context().domain_participant(),
            dds_topic: t.name(),
            config,
        })
    }

    /// Number of subscriptions discovered on the topic (other participants).
    pub fn subscription_count(&self) -> usize {
        self.participant
            .discovered_readers()
            .iter()
            .filter(|r| r.subscription_topic_data.topic_name == self.dds_topic)
            .count()
    }

    /// Waits until at least `n` subscriptions matched, or `timeout`.
    pub async fn wait_for_subscriptions(&self, n: usize, timeout: Duration) -> bool {
        let end = Instant::now() + timeout;
        while self.subscription_count() < n {
            if Instant::now() > end {
                return false;
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        true
    }

    /// Whether a reader matched since the last call (reads the writer's
    /// status events without waiting).
    pub fn newly_matched(&self) -> bool {
        let mut events = self.writer.as_async_status_stream();
        let mut matched = false;
        while let Some(Some(e)) = events.next().now_or_never() {
            matched |= matches!(e, DataWriterStatus::PublicationMatched { .. });
        }
        matched
    }

    /// Publishes one cloud, tiled and paced.
    pub async fn publish(&self, msg: PointCloud2) -> Result<PublishStats, RuntimeError> {
        let t0 = Instant::now();
        let bytes = msg.data.len();
        let parts = tiles::split(msg, self.config.tile_points);
        let n = parts.len();
        let mut acknowledged = true;
        for (k, tile) in parts.into_iter().enumerate() {
            self.writer
                .async_write(tile, None)
                .await
                .map_err(|e| RuntimeError::Node(format!("cannot publish cloud tile {k}: {e}")))?;
            let window_full = (k + 1) % self.config.window_tiles.max(1) == 0;
            if window_full || k + 1 == n {
                acknowledged &= self.wait_acks().await;
            }
        }
        Ok(PublishStats {
            tiles: n,
            bytes,
            seconds: t0.elapsed().as_secs_f64(),
            acknowledged,
        })
    }

    /// Writes one message whole (a scan), without waiting for readers.
    pub async fn write(&self, msg: PointCloud2) -> Result<(), RuntimeError> {
        (self.writer.async_write(msg, None).await)
            .map_err(|e| RuntimeError::Node(format!("DDS refused the message: {e}")))
    }

    /// Waits until every reader acknowledged all written, at most
    /// `ack_timeout_s`: a node about to exit calls it so that what DDS took
    /// reaches its readers (false: some reader did not acknowledge).
    pub async fn wait_acks(&self) -> bool {
        let limit = Duration::from_secs_f64(self.config.ack_timeout_s.max(0.001));
        matches!(
            tokio::time::timeout(limit, self.writer.async_wait_for_acknowledgments()).await,
            Ok(Ok(true))
        )
    }
}
