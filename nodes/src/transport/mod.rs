//! Point clouds over DDS: tiled, acknowledgement-paced publishing and
//! reassembling subscriptions (the rule is in `crate::convert::pointcloud2::tiles`).

mod publisher;
mod subscriber;

pub use publisher::{CloudPublisher, PublishStats, TransportConfig};
pub use subscriber::{CloudSubscription, Received, labelled, next_cloud_of, with_buildings};
