//! [`BagError`]: why a bag could not be written or read, always naming the file.

use std::path::PathBuf;

/// Why a bag could not be written or read. Every message starts with the bag's path.
#[derive(Debug, thiserror::Error)]
pub enum BagError {
    /// The bag file could not be created (missing directory, permissions, ...).
    #[error("{path}: cannot create the bag file: {source}")]
    Create {
        /// The bag file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The bag file could not be read.
    #[error("{path}: cannot read the bag file: {source}")]
    Read {
        /// The bag file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// A topic was added with a type skyground-msgs has no definition for.
    #[error(
        "{path}: topic {topic}: unknown message type `{type_name}` (skyground-msgs knows only the types of skyground_msgs::known_types())"
    )]
    UnknownType {
        /// The bag file.
        path: PathBuf,
        /// The topic being added.
        topic: String,
        /// The requested type name.
        type_name: String,
    },
    /// A topic was added twice with different types.
    #[error(
        "{path}: topic {topic} is already recorded as {existing}, cannot add it as {requested}"
    )]
    TopicTypeConflict {
        /// The bag file.
        path: PathBuf,
        /// The topic being added.
        topic: String,
        /// The type the topic was first added with.
        existing: String,
        /// The type of the second request.
        requested: String,
    },
    /// [`BagWriter::write`](super::BagWriter::write) was given a channel id `add_topic` did not return.
    #[error("{path}: no channel {channel}; use the id add_topic returned")]
    UnknownChannel {
        /// The bag file.
        path: PathBuf,
        /// The channel id given.
        channel: u16,
    },
    /// A message to write is too short to hold the CDR encapsulation header.
    #[error(
        "{path}: message on channel {channel} is {len} bytes, shorter than the 4-byte CDR encapsulation header"
    )]
    NotCdr {
        /// The bag file.
        path: PathBuf,
        /// The channel written to.
        channel: u16,
        /// The message length.
        len: usize,
    },
    /// The MCAP writer failed (typically an I/O error: disk full, file removed).
    #[error("{path}: writing the MCAP file failed: {source}")]
    Write {
        /// The bag file.
        path: PathBuf,
        /// The MCAP library's reason.
        source: mcap::McapError,
    },
    /// The file is not a readable MCAP file (bad magic, corrupt record, failed CRC).
    #[error("{path}: not a readable MCAP file: {source}")]
    Malformed {
        /// The bag file.
        path: PathBuf,
        /// The MCAP library's reason.
        source: mcap::McapError,
    },
    /// The file stops before the MCAP footer: the recorder was killed before finishing it.
    #[error(
        "{path}: the recording is cut off (no MCAP footer: the recorder stopped before finishing the bag); \
         {intact} messages before the cut are intact and read_intact_messages returns them"
    )]
    Truncated {
        /// The bag file.
        path: PathBuf,
        /// How many messages can still be read before the cut.
        intact: usize,
    },
    /// A channel has no schema, so its message type is unknown.
    #[error("{path}: topic {topic} has no schema, so its message type is unknown")]
    NoSchema {
        /// The bag file.
        path: PathBuf,
        /// The topic of the channel.
        topic: String,
    },
    /// A channel's messages are not CDR.
    #[error("{path}: topic {topic} has message encoding `{encoding}`, expected `cdr`")]
    NotCdrChannel {
        /// The bag file.
        path: PathBuf,
        /// The topic of the channel.
        topic: String,
        /// The channel's message encoding.
        encoding: String,
    },
}
