//! Reading a rosbag2-style MCAP file back: every message with its topic, type and time.

use std::path::{Path, PathBuf};

use mcap::read::Options;
use mcap::{McapError, MessageStream};

use super::error::BagError;

/// One recorded message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BagMessage {
    /// Topic name, e.g. `/cloud`.
    pub topic: String,
    /// Full type name from the channel's schema, e.g. `sensor_msgs/msg/PointCloud2`.
    pub type_name: String,
    /// Receive time, nanoseconds since the Unix epoch.
    pub log_time_ns: u64,
    /// Send time, nanoseconds since the Unix epoch.
    pub publish_time_ns: u64,
    /// The ROS 2 serialized message: encapsulation header, then CDR.
    pub cdr: Vec<u8>,
}

/// Every message of a complete bag, in log-time order (ties keep file order).
///
/// A file that stops before the MCAP footer (recorder killed before finishing) is
/// reported as [`BagError::Truncated`] with the number of intact messages; read those
/// with [`read_intact_messages`]. Channels must be `cdr` with a schema.
pub fn read_messages(path: impl AsRef<Path>) -> Result<Vec<BagMessage>, BagError> {
    let path = path.as_ref();
    let bytes = read_file(path)?;
    let (messages, stop) = scan(path, &bytes)?;
    match stop {
        Stop::End => Ok(messages),
        Stop::Cut => Err(BagError::Truncated {
            path: path.to_path_buf(),
            intact: messages.len(),
        }),
        Stop::Corrupt(source) => Err(malformed(path, source)),
    }
}

/// The messages of a bag up to where it is cut off, in log-time order.
///
/// For a complete bag this equals [`read_messages`]. For a file whose recorder was
/// killed (no MCAP footer), it returns the messages of every chunk before the first
/// unreadable record, which is normally the chunk being written when the recorder died.
pub fn read_intact_messages(path: impl AsRef<Path>) -> Result<Vec<BagMessage>, BagError> {
    let path = path.as_ref();
    let bytes = read_file(path)?;
    let (messages, stop) = scan(path, &bytes)?;
    match stop {
        Stop::End | Stop::Cut => Ok(messages),
        Stop::Corrupt(source) => Err(malformed(path, source)),
    }
}

/// Messages and serialized bytes of one topic of a bag.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct TopicSize {
    /// Messages recorded.
    pub messages: u64,
    /// Their serialized size (CDR with its header), bytes, before the bag's compression.
    pub bytes: u64,
}

/// Messages and bytes per topic of a bag, also of one cut off (a killed
/// recorder): the messages up to the cut are counted.
pub fn topic_sizes(
    path: impl AsRef<Path>,
) -> Result<std::collections::BTreeMap<String, TopicSize>, BagError> {
    let path = path.as_ref();
    let bytes = read_file(path)?;
    let options = Options::ValidateChunkCrcs | Options::IgnoreEndMagic;
    let stream = MessageStream::new_with_options(&bytes, options)
        .map_err(|source| malformed(path, source))?;
    let mut sizes = std::collections::BTreeMap::<String, TopicSize>::new();
    // Counting stops at the first unreadable record, as reading a cut bag does.
    for m in stream.map_while(Result::ok) {
        let t = sizes.entry(m.channel.topic.clone()).or_default();
        t.messages += 1;
        t.bytes += m.data.len() as u64;
    }
    Ok(sizes)
}

/// Where reading a file stopped.
#[derive(Debug)]
enum Stop {
    /// At the end of a complete file.
    End,
    /// The file has no footer: at the end of its data section, or at the first record
    /// that could not be read.
    Cut,
    /// A complete file has an unreadable record.
    Corrupt(McapError),
}

/// The QoS each topic of a bag was offered with (rosbag2's
/// `offered_qos_profiles` channel metadata); topics without it are left out.
pub fn read_topic_qos(
    path: impl AsRef<Path>,
) -> Result<std::collections::BTreeMap<String, super::TopicQos>, BagError> {
    let path = path.as_ref();
    let bytes = read_file(path)?;
    let summary = mcap::Summary::read(&bytes).map_err(|source| malformed(path, source))?;
    let mut out = std::collections::BTreeMap::new();
    for channel in summary.iter().flat_map(|s| s.channels.values()) {
        if let Some(q) = channel
            .metadata
            .get("offered_qos_profiles")
            .and_then(|t| super::TopicQos::from_offered_qos_profiles(t))
        {
            out.insert(channel.topic.clone(), q);
        }
    }
    Ok(out)
}

/// Reads messages in file order, then sorts them by log time; says where it stopped.
fn scan(path: &Path, bytes: &[u8]) -> Result<(Vec<BagMessage>, Stop), BagError> {
    let complete = match mcap::read::footer(bytes) {
        Ok(_) => true,
        // Starts like an MCAP file (or is a prefix of its magic, even empty: the
        // recorder died before its first write reached the disk) but has no footer.
        Err(McapError::BadMagic | McapError::UnexpectedEof)
            if bytes.starts_with(mcap::MAGIC) || mcap::MAGIC.starts_with(bytes) =>
        {
            false
        }
        Err(source) => return Err(malformed(path, source)),
    };
    let options = if complete {
        Options::ValidateChunkCrcs.into()
    } else {
        Options::ValidateChunkCrcs | Options::IgnoreEndMagic
    };
    let stream = MessageStream::new_with_options(bytes, options)
        .map_err(|source| malformed(path, source))?;
    let mut messages = Vec::new();
    let mut error = None;
    for message in stream {
        match message {
            Ok(message) => messages.push(bag_message(path, message)?),
            Err(source) => {
                error = Some(source);
                break;
            }
        }
    }
    messages.sort_by_key(|m| m.log_time_ns);
    let stop = match (complete, error) {
        (true, None) => Stop::End,
        (true, Some(source)) => Stop::Corrupt(source),
        (false, error) => {
            if let Some(source) = error {
                log::debug!("{}: cut off at: {source}", path.display());
            }
            Stop::Cut
        }
    };
    Ok((messages, stop))
}

/// Checks the channel of an MCAP message and copies it out.
fn bag_message(path: &Path, message: mcap::Message<'_>) -> Result<BagMessage, BagError> {
    let channel = &message.channel;
    if channel.message_encoding != "cdr" {
        return Err(BagError::NotCdrChannel {
            path: path.to_path_buf(),
            topic: channel.topic.clone(),
            encoding: channel.message_encoding.clone(),
        });
    }
    let Some(schema) = &channel.schema else {
        return Err(BagError::NoSchema {
            path: path.to_path_buf(),
            topic: channel.topic.clone(),
        });
    };
    Ok(BagMessage {
        topic: channel.topic.clone(),
        type_name: schema.name.clone(),
        log_time_ns: message.log_time,
        publish_time_ns: message.publish_time,
        cdr: message.data.into_owned(),
    })
}

/// The whole file in memory.
fn read_file(path: &Path) -> Result<Vec<u8>, BagError> {
    std::fs::read(path).map_err(|source| BagError::Read {
        path: path.to_path_buf(),
        source,
    })
}

/// Wraps an MCAP parse error with the bag's path.
fn malformed(path: &Path, source: McapError) -> BagError {
    BagError::Malformed {
        path: PathBuf::from(path),
        source,
    }
}
