//! One non-trivial value of every known message type, with its JSON and CDR forms.
//!
//! Used to check byte equality with rclpy (`tests/python/test_cdr_equality.py`):
//! every field is non-zero, strings have odd lengths (one has non-ASCII text)
//! and arrays hold at least two elements, so alignment and padding are exercised.

use serde::Serialize;

use crate::builtin_interfaces::{Duration, Time};
use crate::cdr::to_cdr;
use crate::diagnostic_msgs::{DiagnosticArray, DiagnosticStatus, KeyValue};
use crate::geometry_msgs::{
    Point, Point32, PointStamped, Polygon, PolygonStamped, Pose, PoseStamped, PoseWithCovariance,
    Quaternion, Transform, TransformStamped, Twist, TwistWithCovariance, Vector3,
};
use crate::message::RosMessage;
use crate::nav_msgs::{Odometry, Path};
use crate::rcl_interfaces::Log;
use crate::rosgraph_msgs::Clock;
use crate::sensor_msgs::{CompressedImage, PointCloud2, PointField};
use crate::std_msgs::{ColorRGBA, Header};
use crate::tf2_msgs::TFMessage;
use crate::visualization_msgs::{Marker, MarkerArray, MeshFile, UVCoordinate};

/// A message value in two forms: JSON field values and its ROS 2 serialized bytes.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// Full type name, e.g. `sensor_msgs/msg/PointCloud2`.
    pub type_name: &'static str,
    /// Field values as nested JSON objects keyed by .msg field names (`uint8[]` as a list of ints).
    pub json: serde_json::Value,
    /// [`to_cdr`] of the value: encapsulation header and little-endian CDR.
    pub cdr: Vec<u8>,
}

impl Sample {
    /// The sample as one JSON line: `{"type": .., "fields": {..}, "cdr_hex": ".."}`.
    pub fn to_json_line(&self) -> String {
        let hex: String = self.cdr.iter().map(|b| format!("{b:02x}")).collect();
        serde_json::json!({ "type": self.type_name, "fields": self.json, "cdr_hex": hex })
            .to_string()
    }
}

/// One sample per type of [`crate::known_types`], in that order.
pub fn all() -> Vec<Sample> {
    vec![
        sample(time()),
        sample(duration()),
        sample(header()),
        sample(color(0.25)),
        sample(PointField::single("intensity", 12, PointField::FLOAT32)),
        sample(point_cloud2()),
        sample(compressed_image()),
        sample(point(1.5)),
        sample(Point32 {
            x: 1.5,
            y: -2.25,
            z: 3.125,
        }),
        sample(Vector3 {
            x: -0.5,
            y: 4.75,
            z: 1e-3,
        }),
        sample(quaternion()),
        sample(pose(2.0)),
        sample(pose_stamped(1.0)),
        sample(PointStamped {
            header: header(),
            point: point(-7.5),
        }),
        sample(twist()),
        sample(polygon()),
        sample(PolygonStamped {
            header: header(),
            polygon: polygon(),
        }),
        sample(pose_with_covariance()),
        sample(twist_with_covariance()),
        sample(transform()),
        sample(transform_stamped("base_link")),
        sample(TFMessage {
            transforms: vec![transform_stamped("base_link"), transform_stamped("sensor")],
        }),
        sample(Path {
            header: header(),
            poses: vec![pose_stamped(1.0), pose_stamped(2.0), pose_stamped(3.0)],
        }),
        sample(Odometry {
            header: header(),
            child_frame_id: "base_link".into(),
            pose: pose_with_covariance(),
            twist: twist_with_covariance(),
        }),
        sample(UVCoordinate { u: 0.25, v: 0.75 }),
        sample(mesh_file()),
        sample(marker(7)),
        sample(MarkerArray {
            markers: vec![marker(1), marker(2)],
        }),
        sample(key_value("ratio", "0.875")),
        sample(diagnostic_status(DiagnosticStatus::WARN)),
        sample(DiagnosticArray {
            header: header(),
            status: vec![
                diagnostic_status(DiagnosticStatus::WARN),
                diagnostic_status(DiagnosticStatus::STALE),
            ],
        }),
        sample(Clock { clock: time() }),
        sample(Log {
            stamp: time(),
            level: Log::WARN,
            name: "skyground.detector".into(),
            msg: "building 3: 41% seen".into(),
            file: "detector.rs".into(),
            function: "on_cloud".into(),
            line: 1234,
        }),
    ]
}

/// Builds the sample of one value.
///
/// Serializing these in-memory values cannot fail; were it ever to, the sample
/// would carry empty bytes (and null JSON), which the equality test reports.
fn sample<M: RosMessage>(message: M) -> Sample {
    Sample {
        type_name: M::TYPE_NAME,
        json: to_json(&message),
        cdr: to_cdr(&message).unwrap_or_default(),
    }
}

/// JSON field values of a message.
fn to_json<M: Serialize>(message: &M) -> serde_json::Value {
    serde_json::to_value(message).unwrap_or_default()
}

fn time() -> Time {
    Time {
        sec: 1_700_000_123,
        nanosec: 456_789_012,
    }
}

fn duration() -> Duration {
    Duration {
        sec: -3,
        nanosec: 250_000_000,
    }
}

fn header() -> Header {
    Header {
        stamp: time(),
        frame_id: "map".into(),
    }
}

fn color(r: f32) -> ColorRGBA {
    ColorRGBA {
        r,
        g: 0.5,
        b: 0.75,
        a: 1.0,
    }
}

fn point_cloud2() -> PointCloud2 {
    PointCloud2 {
        header: header(),
        height: 1,
        width: 2,
        fields: vec![
            PointField::single("x", 0, PointField::FLOAT32),
            PointField::single("y", 4, PointField::FLOAT32),
            PointField::single("z", 8, PointField::FLOAT32),
            PointField::single("label", 12, PointField::UINT8),
        ],
        is_bigendian: false,
        point_step: 13,
        row_step: 26,
        data: (1..=26).collect(),
        is_dense: true,
    }
}

fn compressed_image() -> CompressedImage {
    CompressedImage {
        header: header(),
        format: "png".into(),
        data: vec![0x89, b'P', b'N', b'G', 13],
    }
}

fn point(x: f64) -> Point {
    Point {
        x,
        y: -2.5,
        z: 0.125,
    }
}

fn quaternion() -> Quaternion {
    Quaternion {
        x: 0.5,
        y: -0.5,
        z: 0.5,
        w: 0.5,
    }
}

fn pose(x: f64) -> Pose {
    Pose {
        position: point(x),
        orientation: quaternion(),
    }
}

fn pose_stamped(x: f64) -> PoseStamped {
    PoseStamped {
        header: Header {
            stamp: time(),
            frame_id: "odom_1".into(),
        },
        pose: pose(x),
    }
}

fn transform() -> Transform {
    Transform {
        translation: Vector3 {
            x: 12.5,
            y: -3.25,
            z: 1.8,
        },
        rotation: quaternion(),
    }
}

fn transform_stamped(child: &str) -> TransformStamped {
    TransformStamped {
        header: header(),
        child_frame_id: child.into(),
        transform: transform(),
    }
}

fn twist() -> Twist {
    Twist {
        linear: Vector3 {
            x: 1.0,
            y: 0.5,
            z: -0.25,
        },
        angular: Vector3 {
            x: 0.125,
            y: -0.0625,
            z: 0.75,
        },
    }
}

fn polygon() -> Polygon {
    Polygon {
        points: vec![
            Point32 {
                x: 0.5,
                y: 1.5,
                z: 2.5,
            },
            Point32 {
                x: -4.0,
                y: 8.0,
                z: 1.0,
            },
            Point32 {
                x: 3.0,
                y: -1.0,
                z: 0.25,
            },
        ],
    }
}

fn covariance(scale: f64) -> [f64; 36] {
    let mut c = [0.0; 36];
    for (i, v) in c.iter_mut().enumerate() {
        *v = scale * (i as f64 + 1.0);
    }
    c
}

fn pose_with_covariance() -> PoseWithCovariance {
    PoseWithCovariance {
        pose: pose(4.0),
        covariance: covariance(0.5),
    }
}

fn twist_with_covariance() -> TwistWithCovariance {
    TwistWithCovariance {
        twist: twist(),
        covariance: covariance(-0.25),
    }
}

fn mesh_file() -> MeshFile {
    MeshFile {
        filename: "roof.stl".into(),
        data: vec![1, 2, 3, 250, 255],
    }
}

fn marker(id: i32) -> Marker {
    Marker {
        header: header(),
        ns: "regions".into(),
        id,
        r#type: Marker::LINE_STRIP,
        action: Marker::DELETE,
        pose: pose(-1.0),
        scale: Vector3 {
            x: 0.1,
            y: 0.2,
            z: 0.3,
        },
        color: color(0.125),
        lifetime: duration(),
        frame_locked: true,
        points: vec![point(1.0), point(2.0), point(3.0)],
        colors: vec![color(0.5), color(1.0)],
        texture_resource: "file:///tex.png".into(),
        texture: compressed_image(),
        uv_coordinates: vec![
            UVCoordinate { u: 0.5, v: 1.0 },
            UVCoordinate { u: 1.0, v: 0.0 },
        ],
        text: "Gebäude ✓".into(),
        mesh_resource: "package://m/a.dae".into(),
        mesh_file: mesh_file(),
        mesh_use_embedded_materials: true,
    }
}

fn key_value(key: &str, value: &str) -> KeyValue {
    KeyValue {
        key: key.into(),
        value: value.into(),
    }
}

fn diagnostic_status(level: u8) -> DiagnosticStatus {
    DiagnosticStatus {
        level,
        name: "building 12".into(),
        message: "completeness below target".into(),
        hardware_id: "sim".into(),
        values: vec![key_value("walls", "0.61"), key_value("roofs", "0.975")],
    }
}

#[cfg(test)]
mod tests {
    use serde::de::DeserializeOwned;

    use super::*;
    use crate::cdr::from_cdr;
    use crate::registry::known_types;

    #[test]
    fn one_sample_per_known_type_in_registry_order() {
        let names: Vec<_> = all().iter().map(|s| s.type_name).collect();
        assert_eq!(names, known_types());
    }

    /// Decodes `sample.cdr` as `M` and checks it re-encodes to the same JSON and bytes.
    fn check<M: RosMessage + PartialEq + std::fmt::Debug + DeserializeOwned>(sample: &Sample) {
        let decoded: M = from_cdr(&sample.cdr).unwrap();
        assert_eq!(to_json(&decoded), sample.json, "{}", sample.type_name);
        assert_eq!(
            to_cdr(&decoded).unwrap(),
            sample.cdr,
            "{}",
            sample.type_name
        );
        let from_json: M = serde_json::from_value(sample.json.clone()).unwrap();
        assert_eq!(from_json, decoded, "{}", sample.type_name);
    }

    macro_rules! check_all {
        ($sample:expr, $($ty:ty),* $(,)?) => {
            match $sample.type_name {
                $(name if name == <$ty as RosMessage>::TYPE_NAME => check::<$ty>($sample),)*
                other => panic!("no check for {other}"),
            }
        };
    }

    #[test]
    fn every_sample_round_trips_through_cdr_and_json() {
        for s in all() {
            assert!(s.cdr.len() > 4 && s.json.is_object(), "{}", s.type_name);
            check_all!(
                &s,
                Time,
                Duration,
                Header,
                ColorRGBA,
                PointField,
                PointCloud2,
                CompressedImage,
                Point,
                Point32,
                Vector3,
                Quaternion,
                Pose,
                PoseStamped,
                PointStamped,
                Twist,
                Polygon,
                PolygonStamped,
                PoseWithCovariance,
                TwistWithCovariance,
                Transform,
                TransformStamped,
                TFMessage,
                Path,
                Odometry,
                UVCoordinate,
                MeshFile,
                Marker,
                MarkerArray,
                KeyValue,
                DiagnosticStatus,
                DiagnosticArray,
                Clock,
                Log,
            );
        }
    }

    #[test]
    fn json_line_has_the_three_keys() {
        let line = all()[0].to_json_line();
        let v: serde_json::Value = serde_json::from_str(&line).unwrap();
        assert_eq!(v["type"], "builtin_interfaces/msg/Time");
        assert_eq!(v["fields"]["sec"], 1_700_000_123);
        assert!(v["cdr_hex"].as_str().unwrap().starts_with("00010000"));
    }
}
