//! rosbag2-compatible MCAP bags: [`BagWriter`] records, [`read_messages`] reads back.
//!
//! The file layout is what rosbag2's MCAP storage plugin writes, so `ros2 bag`,
//! rosbags, Foxglove and the `mcap` tools read it: header profile `ros2`; per message
//! type one schema named `pkg/msg/Type` with encoding `ros2msg` and the type's full
//! definition (dependencies after lines of 80 `=`); per topic one channel with message
//! encoding `cdr` and the `offered_qos_profiles` metadata; messages in zstd-compressed
//! chunks; a summary with chunk and message indexes and statistics.

mod error;
mod qos;
mod reader;
mod writer;

pub use error::BagError;
pub use qos::TopicQos;
pub use reader::{
    BagMessage, TopicSize, read_intact_messages, read_messages, read_topic_qos, topic_sizes,
};
pub use writer::BagWriter;
