//! Type-erased subscriptions for tools that pick a topic's type at run time
//! (`skyground echo`, `skyground record`).

use std::future::Future;
use std::pin::Pin;

use futures::StreamExt;
use ros2_client::{QosProfile, Subscription};
use skyground_msgs::{RosMessage, TypeVisitor, to_cdr, with_type};

use crate::runtime::{NodeRuntime, RuntimeError};

/// One message as a tool sees it.
pub struct Tapped {
    /// ROS 2 serialized form (CDR with encapsulation header), as on the wire.
    pub cdr: Vec<u8>,
    /// The message as JSON (field names as in the .msg), when asked for.
    pub json: Option<serde_json::Value>,
    /// The publisher's source timestamp, ns since the epoch (0 when unknown).
    pub publish_time_ns: u64,
}

/// A boxed future, so taps of different types share one interface.
pub type TapFuture<'a> = Pin<Box<dyn Future<Output = Option<Result<Tapped, String>>> + Send + 'a>>;

/// A subscription whose message type is known only at run time.
pub trait Tap: Send {
    /// The full type name (`pkg/msg/Type`).
    fn type_name(&self) -> &'static str;
    /// The next message, an error text for an unreadable one, `None` at the end.
    fn next(&mut self) -> TapFuture<'_>;
}

struct TypedTap<M: RosMessage> {
    sub: Subscription<M>,
    json: bool,
}

impl<M: RosMessage> Tap for TypedTap<M> {
    fn type_name(&self) -> &'static str {
        M::TYPE_NAME
    }

    fn next(&mut self) -> TapFuture<'_> {
        Box::pin(async move {
            let stream = self.sub.async_stream();
            futures::pin_mut!(stream);
            let item = stream.next().await?;
            Some(
                item.map_err(|e| format!("unreadable message: {e}"))
                    .and_then(|(msg, info)| {
                        let publish_time_ns = info
                            .source_timestamp()
                            .map_or(0, |t| u64::try_from(t.to_nanos()).unwrap_or(0));
                        let cdr = to_cdr(&msg).map_err(|e| e.to_string())?;
                        let json = if self.json {
                            Some(serde_json::to_value(&msg).map_err(|e| e.to_string())?)
                        } else {
                            None
                        };
                        Ok(Tapped {
                            cdr,
                            json,
                            publish_time_ns,
                        })
                    }),
            )
        })
    }
}

struct MakeTap<'a> {
    rt: &'a mut NodeRuntime,
    topic: &'a str,
    qos: QosProfile,
    json: bool,
}

impl TypeVisitor for MakeTap<'_> {
    type Output = Result<Box<dyn Tap>, RuntimeError>;

    fn visit<M: RosMessage + std::fmt::Debug>(self) -> Self::Output {
        let sub = self.rt.subscription::<M>(self.topic, self.qos)?;
        Ok(Box::new(TypedTap {
            sub,
            json: self.json,
        }))
    }
}

/// Subscribes to `topic` as type `type_name` (`pkg/msg/Type` or `pkg/Type`).
pub fn tap(
    rt: &mut NodeRuntime,
    topic: &str,
    type_name: &str,
    qos: QosProfile,
    json: bool,
) -> Result<Box<dyn Tap>, RuntimeError> {
    with_type(
        type_name,
        MakeTap {
            rt,
            topic,
            qos,
            json,
        },
    )
    .unwrap_or_else(|| {
        Err(RuntimeError::Node(format!(
            "unknown message type `{type_name}` (known: {})",
            skyground_msgs::known_types().join(", ")
        )))
    })
}

/// The ROS 2 type name of a DDS type name (`pkg::msg::dds_::Type_`).
pub fn ros_type_of_dds(dds: &str) -> Option<String> {
    let mut parts = dds.split("::");
    let pkg = parts.next()?;
    let kind = parts.next()?;
    let _dds = parts.next().filter(|p| *p == "dds_")?;
    let ty = parts.next()?.strip_suffix('_')?;
    Some(format!("{pkg}/{kind}/{ty}"))
}

/// What discovery knows of a topic's publishers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TopicInfo {
    /// ROS 2 type name.
    pub type_name: String,
    /// Every publisher is reliable.
    pub reliable: bool,
    /// Every publisher is transient local.
    pub transient_local: bool,
}

/// Looks up a topic's type and its publishers' QoS in DDS discovery.
pub fn discover(rt: &NodeRuntime, topic: &str) -> Option<TopicInfo> {
    let dds_name = format!("rt{topic}");
    let writers: Vec<_> = rt
        .context()
        .domain_participant()
        .discovered_writers()
        .into_iter()
        .filter(|w| w.publication_topic_data.topic_name == dds_name)
        .collect();
    let first = writers.first()?;
    let type_name = ros_type_of_dds(&first.publication_topic_data.type_name)?;
    let reliable = writers.iter().all(|w| {
        matches!(
            w.publication_topic_data.reliability,
            Some(rustdds::policy::Reliability::Reliable { .. })
        )
    });
    let transient_local = writers.iter().all(|w| {
        matches!(
            w.publication_topic_data.durability,
            Some(rustdds::policy::Durability::TransientLocal)
        )
    });
    Some(TopicInfo {
        type_name,
        reliable,
        transient_local,
    })
}

/// A publisher on `topic` of type `type_name` (`pkg/msg/Type` or `pkg/Type`).
pub fn emitter(
    rt: &mut NodeRuntime,
    topic: &str,
    type_name: &str,
    qos: QosProfile,
) -> Result<Box<dyn Emit>, RuntimeError> {
    with_type(type_name, MakeEmit { rt, topic, qos }).unwrap_or_else(|| {
        Err(RuntimeError::Node(format!(
            "unknown message type `{type_name}` (known: {})",
            skyground_msgs::known_types().join(", ")
        )))
    })
}

/// A publisher whose message type is known only at run time (`skyground play`).
pub trait Emit: Send {
    /// Publishes one ROS 2 serialized message (encapsulation header + CDR).
    fn emit<'a>(
        &'a self,
        cdr: &'a [u8],
    ) -> Pin<Box<dyn Future<Output = Result<(), String>> + Send + 'a>>;
}

struct TypedEmit<M: RosMessage> {
    publisher: ros2_client::Publisher<M>,
}

impl<M: RosMessage> Emit for TypedEmit<M> {
    fn emit<'a>(
        &'a self,
        cdr: &'a [u8],
    ) -> Pin<Box<dyn Future<Output = Result<(), String>> + Send + 'a>> {
        Box::pin(async move {
            let msg: M = skyground_msgs::from_cdr(cdr)
                .map_err(|e| format!("undecodable {}: {e}", M::TYPE_NAME))?;
            self.publisher
                .async_publish(msg)
                .await
                .map_err(|e| format!("{e}"))
        })
    }
}

struct MakeEmit<'a> {
    rt: &'a mut NodeRuntime,
    topic: &'a str,
    qos: QosProfile,
}

impl TypeVisitor for MakeEmit<'_> {
    type Output = Result<Box<dyn Emit>, RuntimeError>;

    fn visit<M: RosMessage + std::fmt::Debug>(self) -> Self::Output {
        let publisher = self.rt.publisher::<M>(self.topic, self.qos)?;
        Ok(Box::new(TypedEmit { publisher }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dds_type_names_convert() {
        assert_eq!(
            ros_type_of_dds("sensor_msgs::msg::dds_::PointCloud2_").as_deref(),
            Some("sensor_msgs/msg/PointCloud2")
        );
        assert_eq!(ros_type_of_dds("PointCloud2"), None);
    }
}
