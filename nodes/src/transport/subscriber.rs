//! Receiving clouds: reassembles tiles and decodes, reporting bad messages
//! without stopping.

use crate::convert::pointcloud2::{self, Decoded, tiles::Assembler};
use futures::StreamExt;
use ros2_client::{QosProfile, Subscription};
use skyground_core::cloud::Cloud;
use skyground_msgs::sensor_msgs::PointCloud2;

use crate::runtime::{Logger, NodeRuntime, RuntimeError};

/// One whole cloud as it arrived, or why it could not be used.
pub enum Received {
    /// A decoded cloud and the message it came from.
    Cloud {
        /// The reassembled message.
        msg: PointCloud2,
        /// Its decoded points (boxed: a cloud is large, an error small).
        decoded: Box<Decoded>,
    },
    /// A message that could not be read (CDR error) or decoded (layout error).
    Bad(String),
}

/// A PointCloud2 subscription that yields whole, decoded clouds.
pub struct CloudSubscription {
    sub: Subscription<PointCloud2>,
    assembler: Assembler,
    topic: String,
}

impl CloudSubscription {
    /// Subscribes to `topic` with tiles of `tile_points` points.
    pub fn new(
        rt: &mut NodeRuntime,
        topic: &str,
        qos: QosProfile,
        tile_points: u32,
    ) -> Result<Self, RuntimeError> {
        Ok(Self {
            sub: rt.subscription::<PointCloud2>(topic, qos)?,
            assembler: Assembler::new(tile_points),
            topic: topic.to_owned(),
        })
    }

    /// How many publishers DDS has matched to this subscription.
    pub fn publisher_count(&self, node: &ros2_client::Node) -> usize {
        self.sub.get_publisher_count(node)
    }

    /// Waits for the next whole cloud (or bad message). `None` when the
    /// subscription ended.
    pub async fn next(&mut self) -> Option<Received> {
        let stream = self.sub.async_stream();
        futures::pin_mut!(stream);
        loop {
            match stream.next().await? {
                Err(e) => return Some(Received::Bad(format!("unreadable message: {e}"))),
                Ok((tile, _info)) => {
                    if let Some(msg) = self.assembler.push(tile) {
                        return Some(match pointcloud2::decode(&msg) {
                            Ok(decoded) => Received::Cloud {
                                msg,
                                decoded: Box::new(decoded),
                            },
                            Err(e) => Received::Bad(e.to_string()),
                        });
                    }
                }
            }
        }
    }

    /// [`Self::next`] with a bad cloud logged (`rejected TOPIC: why`) and
    /// given as `Some(None)`; `None` when the subscription ended.
    pub async fn next_cloud(&mut self, log: &Logger) -> Option<Option<(PointCloud2, Decoded)>> {
        Some(match self.next().await? {
            Received::Cloud { msg, decoded } => Some((msg, *decoded)),
            Received::Bad(reason) => {
                log.error(&format!("rejected {}: {reason}", self.topic));
                None
            }
        })
    }

    /// [`Self::next_cloud`] of a classified cloud: its points and labels; a
    /// cloud without labels is logged and given as `Some(None)`.
    pub async fn next_labelled(
        &mut self,
        log: &Logger,
    ) -> Option<Option<(Vec<[f32; 3]>, Vec<u8>)>> {
        let cloud = self.next_cloud(log).await?;
        Some(cloud.and_then(|(_, d)| labelled(log, &self.topic, d.cloud)))
    }

    /// Partial clouds given up because a newer one started.
    pub fn abandoned(&self) -> usize {
        self.assembler.abandoned()
    }
}

/// [`CloudSubscription::next_cloud`] of a subscription a node may not have;
/// without one it is never ready (for a `select!` branch).
pub async fn next_cloud_of(
    sub: Option<&mut CloudSubscription>,
    log: &Logger,
) -> Option<Option<(PointCloud2, Decoded)>> {
    match sub {
        Some(s) => s.next_cloud(log).await,
        None => std::future::pending().await,
    }
}

/// A classified cloud's points and labels; a cloud without labels is logged
/// (it came from before the classifier) and gives `None`.
pub fn labelled(log: &Logger, topic: &str, cloud: Cloud) -> Option<(Vec<[f32; 3]>, Vec<u8>)> {
    match cloud.label {
        Some(labels) => Some((cloud.xyz, labels)),
        None => {
            log.error(&format!(
                "{topic} has no `label` field: run scene_classifier first"
            ));
            None
        }
    }
}

/// A cloud's points and their building ids (0 where it has none).
pub fn with_buildings(cloud: Cloud) -> (Vec<[f32; 3]>, Vec<u32>) {
    let ids = cloud.building.unwrap_or_else(|| vec![0; cloud.xyz.len()]);
    (cloud.xyz, ids)
}
