//! Converting between [`Cloud`](skyground_core::cloud::Cloud) and `sensor_msgs/PointCloud2`.
//!
//! [`encode`] writes a fixed little-endian layout (see [`encode()`] for the
//! table); [`decode`] reads any layout a ROS 2 producer may send, validating
//! every size and offset first so that no input can make it panic.

mod datatype;
mod decode;
mod encode;
mod error;

pub use decode::{Decoded, decode};
pub use encode::{EncodeOptions, encode, encode_with};
pub use error::PointCloud2Error;
pub mod tiles;
