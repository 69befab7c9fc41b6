//! `std_msgs`: the message header and colours.

use serde::{Deserialize, Serialize};

use crate::builtin_interfaces::Time;
use crate::message::ros_message;

/// `std_msgs/msg/Header`: stamp and coordinate frame of the data that follows.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct Header {
    /// Acquisition time of the data.
    pub stamp: Time,
    /// Coordinate frame the data is expressed in (e.g. `map`).
    pub frame_id: String,
}

/// `std_msgs/msg/ColorRGBA`: a colour with alpha, each channel in `0..=1`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct ColorRGBA {
    /// Red.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
    /// Alpha (0 transparent, 1 opaque).
    pub a: f32,
}

ros_message!(
    Header,
    "std_msgs/msg/Header",
    [Time],
    ["builtin_interfaces/Time stamp", "string frame_id"]
);
ros_message!(
    ColorRGBA,
    "std_msgs/msg/ColorRGBA",
    [],
    ["float32 r", "float32 g", "float32 b", "float32 a"]
);
