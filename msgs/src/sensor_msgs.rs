//! `sensor_msgs`: point clouds and compressed images.

use serde::{Deserialize, Serialize};

use crate::message::ros_message;
use crate::std_msgs::Header;

/// `sensor_msgs/msg/PointField`: name, offset and type of one field of a point.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct PointField {
    /// Field name (`x`, `intensity`, ...).
    pub name: String,
    /// Byte offset of the field from the start of the point.
    pub offset: u32,
    /// Datatype code, one of the constants below.
    pub datatype: u8,
    /// Number of elements of `datatype` in the field.
    pub count: u32,
}

impl PointField {
    /// Datatype code of `int8`.
    pub const INT8: u8 = 1;
    /// Datatype code of `uint8`.
    pub const UINT8: u8 = 2;
    /// Datatype code of `int16`.
    pub const INT16: u8 = 3;
    /// Datatype code of `uint16`.
    pub const UINT16: u8 = 4;
    /// Datatype code of `int32`.
    pub const INT32: u8 = 5;
    /// Datatype code of `uint32`.
    pub const UINT32: u8 = 6;
    /// Datatype code of `float32`.
    pub const FLOAT32: u8 = 7;
    /// Datatype code of `float64`.
    pub const FLOAT64: u8 = 8;

    /// A field of one `datatype` value at byte `offset` (every field
    /// skyground writes, and every one most writers do).
    pub fn single(name: &str, offset: u32, datatype: u8) -> Self {
        Self {
            name: name.into(),
            offset,
            datatype,
            count: 1,
        }
    }
}

/// `sensor_msgs/msg/PointCloud2`: points as packed binary records (see [`crate::pointcloud2`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct PointCloud2 {
    /// Stamp and frame of the cloud.
    pub header: Header,
    /// Number of rows (1 for an unorganized cloud).
    pub height: u32,
    /// Number of points per row.
    pub width: u32,
    /// Layout of one point.
    pub fields: Vec<PointField>,
    /// True when multi-byte values in `data` are big endian.
    pub is_bigendian: bool,
    /// Bytes per point.
    pub point_step: u32,
    /// Bytes per row (at least `width * point_step`).
    pub row_step: u32,
    /// Point records, `row_step * height` bytes.
    #[serde(with = "serde_bytes")]
    pub data: Vec<u8>,
    /// True when no point has a non-finite coordinate.
    pub is_dense: bool,
}

/// `sensor_msgs/msg/CompressedImage`: an encoded image (used as a marker texture).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct CompressedImage {
    /// Stamp and frame of the image.
    pub header: Header,
    /// Encoding, e.g. `png` or `jpeg`.
    pub format: String,
    /// The encoded image bytes.
    #[serde(with = "serde_bytes")]
    pub data: Vec<u8>,
}

ros_message!(
    PointField,
    "sensor_msgs/msg/PointField",
    [],
    [
        "uint8 INT8 = 1",
        "uint8 UINT8 = 2",
        "uint8 INT16 = 3",
        "uint8 UINT16 = 4",
        "uint8 INT32 = 5",
        "uint8 UINT32 = 6",
        "uint8 FLOAT32 = 7",
        "uint8 FLOAT64 = 8",
        "string name",
        "uint32 offset",
        "uint8 datatype",
        "uint32 count",
    ]
);
ros_message!(
    PointCloud2,
    "sensor_msgs/msg/PointCloud2",
    [Header, PointField],
    [
        "std_msgs/Header header",
        "uint32 height",
        "uint32 width",
        "sensor_msgs/PointField[] fields",
        "bool is_bigendian",
        "uint32 point_step",
        "uint32 row_step",
        "uint8[] data",
        "bool is_dense",
    ]
);
ros_message!(
    CompressedImage,
    "sensor_msgs/msg/CompressedImage",
    [Header],
    ["std_msgs/Header header", "string format", "uint8[] data"]
);
