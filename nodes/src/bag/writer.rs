//! [`BagWriter`]: records CDR messages into one rosbag2-style MCAP file.

use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use mcap::records::MessageHeader;
use mcap::{WriteOptions, Writer};
use skyground_msgs::{full_definition, known_types};

use super::error::BagError;
use super::qos::TopicQos;

/// Uncompressed bytes per chunk; rosbag2's MCAP storage plugin uses the same default.
const CHUNK_SIZE: u64 = 768 * 1024;
/// zstd level 1, rosbag2's "fast" preset: recording must keep up with the sensors.
const ZSTD_LEVEL: u32 = 1;
/// The `library` field of the MCAP header.
const LIBRARY: &str = concat!("skyground-nodes ", env!("CARGO_PKG_VERSION"));

/// One recorded topic: its type and the channel its messages go to.
#[derive(Debug)]
struct Topic {
    /// Full type name (`pkg/msg/Type`).
    type_name: &'static str,
    /// MCAP channel id.
    channel: u16,
}

/// Writes an MCAP file as rosbag2 does: profile `ros2`, one `ros2msg` schema per type,
/// one `cdr` channel per topic with its `offered_qos_profiles`, zstd-compressed chunks.
///
/// [`finish`](Self::finish) writes the summary (indexes, statistics) and reports any
/// I/O error. Dropping the writer instead also finishes the file (the `mcap` writer
/// finishes itself on drop), so a recorder that stops on a signal and unwinds normally
/// leaves a valid bag, but errors of that last write are lost. A process killed
/// outright leaves a file without footer; [`read_intact_messages`](super::read_intact_messages)
/// recovers its complete chunks, [`flush`](Self::flush) bounds what such a kill loses.
pub struct BagWriter {
    /// The bag file, for error messages.
    path: PathBuf,
    /// The MCAP writer over the buffered file.
    mcap: Writer<BufWriter<File>>,
    /// Schema id per full type name.
    schemas: HashMap<&'static str, u16>,
    /// Recorded topics by name.
    topics: HashMap<String, Topic>,
    /// Next message sequence number per channel.
    sequences: HashMap<u16, u32>,
}

impl BagWriter {
    /// Creates (or truncates) the MCAP file at `path` and writes its header.
    pub fn create(path: impl AsRef<Path>) -> Result<Self, BagError> {
        let path = path.as_ref().to_path_buf();
        let file = File::create(&path).map_err(|source| BagError::Create {
            path: path.clone(),
            source,
        })?;
        let options = WriteOptions::new()
            .profile("ros2")
            .library(LIBRARY)
            .compression(Some(mcap::Compression::Zstd))
            .compression_level(ZSTD_LEVEL)
            .compression_threads(0)
            .chunk_size(Some(CHUNK_SIZE));
        let mcap = options
            .create(BufWriter::new(file))
            .map_err(|source| BagError::Write {
                path: path.clone(),
                source,
            })?;
        Ok(Self {
            path,
            mcap,
            schemas: HashMap::new(),
            topics: HashMap::new(),
            sequences: HashMap::new(),
        })
    }

    /// The bag file this writer writes.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Registers `topic` with message type `type_name` (`pkg/msg/Type` or `pkg/Type`) and
    /// returns the channel id to [`write`](Self::write) its messages to.
    ///
    /// The type's schema is written once, however many topics use it. Adding a topic again
    /// with the same type returns the channel it already has (the first QoS is kept).
    pub fn add_topic(
        &mut self,
        topic: &str,
        type_name: &str,
        qos: &TopicQos,
    ) -> Result<u16, BagError> {
        let Some(canonical) = canonical_type_name(type_name) else {
            return Err(BagError::UnknownType {
                path: self.path.clone(),
                topic: topic.to_owned(),
                type_name: type_name.to_owned(),
            });
        };
        if let Some(existing) = self.topics.get(topic) {
            if existing.type_name == canonical {
                return Ok(existing.channel);
            }
            return Err(BagError::TopicTypeConflict {
                path: self.path.clone(),
                topic: topic.to_owned(),
                existing: existing.type_name.to_owned(),
                requested: canonical.to_owned(),
            });
        }
        let schema = self.schema_id(topic, canonical)?;
        let metadata = BTreeMap::from([(
            "offered_qos_profiles".to_owned(),
            qos.offered_qos_profiles(),
        )]);
        let channel = self
            .mcap
            .add_channel(schema, topic, "cdr", &metadata)
            .map_err(|source| self.write_error(source))?;
        self.topics.insert(
            topic.to_owned(),
            Topic {
                type_name: canonical,
                channel,
            },
        );
        self.sequences.insert(channel, 0);
        Ok(channel)
    }

    /// Writes one message: `cdr` is its ROS 2 serialized form (encapsulation header, then
    /// CDR), `log_time_ns` when it was received, `publish_time_ns` when it was sent, both
    /// nanoseconds since the Unix epoch.
    pub fn write(
        &mut self,
        channel: u16,
        log_time_ns: u64,
        publish_time_ns: u64,
        cdr: &[u8],
    ) -> Result<(), BagError> {
        let Some(next) = self.sequences.get_mut(&channel) else {
            return Err(BagError::UnknownChannel {
                path: self.path.clone(),
                channel,
            });
        };
        if cdr.len() < 4 {
            return Err(BagError::NotCdr {
                path: self.path.clone(),
                channel,
                len: cdr.len(),
            });
        }
        let sequence = *next;
        *next = next.wrapping_add(1);
        let header = MessageHeader {
            channel_id: channel,
            sequence,
            log_time: log_time_ns,
            publish_time: publish_time_ns,
        };
        self.mcap
            .write_to_known_channel(&header, cdr)
            .map_err(|source| self.write_error(source))
    }

    /// Closes the current chunk and flushes it to the file, so that a crash after this
    /// point loses nothing written before it. Costs compression ratio if called often.
    pub fn flush(&mut self) -> Result<(), BagError> {
        self.mcap.flush().map_err(|source| self.write_error(source))
    }

    /// Writes the summary section (schemas, channels, chunk indexes, statistics) and the
    /// footer, flushes the file and syncs it to disk.
    pub fn finish(mut self) -> Result<(), BagError> {
        self.mcap
            .finish()
            .map_err(|source| self.write_error(source))?;
        let path = self.path;
        let io_error = |source| BagError::Write {
            path: path.clone(),
            source: mcap::McapError::Io(source),
        };
        let file = self
            .mcap
            .into_inner()
            .into_inner()
            .map_err(|e| io_error(e.into_error()))?;
        file.sync_all().map_err(io_error)
    }

    /// The schema id of a known type, writing the schema on first use.
    fn schema_id(&mut self, topic: &str, type_name: &'static str) -> Result<u16, BagError> {
        if let Some(&id) = self.schemas.get(type_name) {
            return Ok(id);
        }
        let Some(definition) = full_definition(type_name) else {
            return Err(BagError::UnknownType {
                path: self.path.clone(),
                topic: topic.to_owned(),
                type_name: type_name.to_owned(),
            });
        };
        let id = self
            .mcap
            .add_schema(type_name, "ros2msg", definition.as_bytes())
            .map_err(|source| self.write_error(source))?;
        self.schemas.insert(type_name, id);
        Ok(id)
    }

    /// Wraps an MCAP error with this bag's path.
    fn write_error(&self, source: mcap::McapError) -> BagError {
        BagError::Write {
            path: self.path.clone(),
            source,
        }
    }
}

/// The registry's `pkg/msg/Type` name for `pkg/msg/Type` or `pkg/Type`, if known.
fn canonical_type_name(type_name: &str) -> Option<&'static str> {
    known_types()
        .iter()
        .copied()
        .find(|known| *known == type_name || known.replacen("/msg/", "/", 1) == type_name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writer_can_move_into_a_task() {
        fn assert_send<T: Send>() {}
        assert_send::<BagWriter>();
    }

    #[test]
    fn short_and_full_type_names_resolve() {
        assert_eq!(
            canonical_type_name("sensor_msgs/PointCloud2"),
            Some("sensor_msgs/msg/PointCloud2")
        );
        assert_eq!(
            canonical_type_name("nav_msgs/msg/Path"),
            Some("nav_msgs/msg/Path")
        );
        assert_eq!(canonical_type_name("nav_msgs/msg/Nope"), None);
        assert_eq!(canonical_type_name("Path"), None);
    }
}
