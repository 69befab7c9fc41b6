//! The ROS 2 serialized form: a 4-byte encapsulation header, then CDR.
//!
//! CDR aligns each primitive to its size, counted from the end of the
//! encapsulation header; padding bytes are written as zero (rclpy leaves them
//! uninitialised, so compare padding-insensitively). Nothing is appended after
//! the last field, which matches rclpy's `serialize_message`.

use byteorder::{BigEndian, LittleEndian};
use serde::Serialize;
use serde::de::DeserializeOwned;

/// Encapsulation header of little-endian plain CDR (`CDR_LE`), as ROS 2 writes it.
pub const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// Why a message could not be (de)serialized.
#[derive(Debug, thiserror::Error)]
pub enum CdrError {
    /// Fewer bytes than the encapsulation header.
    #[error("serialized message is {len} bytes, shorter than the 4-byte CDR encapsulation header")]
    TooShort {
        /// Length of the input.
        len: usize,
    },
    /// The encapsulation id is not plain CDR.
    #[error(
        "unsupported encapsulation {id:#06x}: expected 0x0001 (CDR little endian) or 0x0000 (CDR big endian)"
    )]
    Encapsulation {
        /// The first two bytes, big-endian.
        id: u16,
    },
    /// The CDR encoder rejected the value.
    #[error("CDR encoding failed: {0}")]
    Encode(cdr_encoding::Error),
    /// The payload does not hold a value of the requested type.
    #[error("CDR payload does not decode as the requested message type: {0}")]
    Decode(cdr_encoding::Error),
}

/// Serializes a message as rclpy's `serialize_message` does: `00 01 00 00`, then little-endian CDR.
pub fn to_cdr<M: Serialize>(message: &M) -> Result<Vec<u8>, CdrError> {
    let mut bytes = Vec::with_capacity(64);
    bytes.extend_from_slice(&CDR_LE_HEADER);
    cdr_encoding::to_writer::<M, LittleEndian, _>(&mut bytes, message).map_err(CdrError::Encode)?;
    Ok(bytes)
}

/// Deserializes a message from its ROS 2 serialized form (little- or big-endian CDR).
///
/// Bytes after the last field (e.g. DDS trailing padding) are ignored.
pub fn from_cdr<M: DeserializeOwned>(bytes: &[u8]) -> Result<M, CdrError> {
    let (header, payload) = match bytes.split_first_chunk::<4>() {
        Some(split) => split,
        None => return Err(CdrError::TooShort { len: bytes.len() }),
    };
    let decoded = match u16::from_be_bytes([header[0], header[1]]) {
        0x0001 => cdr_encoding::from_bytes::<M, LittleEndian>(payload),
        0x0000 => cdr_encoding::from_bytes::<M, BigEndian>(payload),
        id => return Err(CdrError::Encapsulation { id }),
    };
    decoded
        .map(|(message, _)| message)
        .map_err(CdrError::Decode)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor_msgs::PointCloud2;
    use crate::std_msgs::Header;

    #[test]
    fn empty_header_matches_rclpy() {
        // rclpy: serialize_message(Header()).hex()
        let bytes = to_cdr(&Header::default()).unwrap();
        assert_eq!(hex(&bytes), "0001000000000000000000000100000000");
    }

    #[test]
    fn empty_pointcloud2_has_rclpy_length_and_zero_padding() {
        // rclpy writes 49 bytes; its 6 padding bytes are uninitialised memory.
        let bytes = to_cdr(&PointCloud2::default()).unwrap();
        assert_eq!(
            hex(&bytes),
            "00010000000000000000000001000000000000000000000000000000000000000000000000000000000000000000000000"
        );
        assert_eq!(bytes.len(), 49);
    }

    #[test]
    fn round_trip_and_header_checks() {
        let h = Header {
            frame_id: "map".into(),
            ..Header::default()
        };
        let bytes = to_cdr(&h).unwrap();
        assert_eq!(from_cdr::<Header>(&bytes).unwrap(), h);
        assert!(matches!(
            from_cdr::<Header>(&[0, 1]),
            Err(CdrError::TooShort { len: 2 })
        ));
        assert!(matches!(
            from_cdr::<Header>(&[0, 3, 0, 0]),
            Err(CdrError::Encapsulation { id: 3 })
        ));
        assert!(matches!(
            from_cdr::<Header>(&bytes[..10]),
            Err(CdrError::Decode(_))
        ));
    }

    #[test]
    fn big_endian_payload_decodes() {
        let bytes = [0, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0, 9];
        let t: crate::builtin_interfaces::Time = from_cdr(&bytes).unwrap();
        assert_eq!((t.sec, t.nanosec), (7, 9));
    }

    fn hex(bytes: &[u8]) -> String {
        bytes.iter().map(|b| format!("{b:02x}")).collect()
    }
}
