//! `geometry_msgs`: points, vectors, poses, twists and polygons.

use serde::{Deserialize, Serialize};

use crate::message::ros_message;
use crate::std_msgs::Header;

/// `geometry_msgs/msg/Point`: a position, metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct Point {
    /// X coordinate.
    pub x: f64,
    /// Y coordinate.
    pub y: f64,
    /// Z coordinate.
    pub z: f64,
}

/// `geometry_msgs/msg/Point32`: a single-precision position, metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct Point32 {
    /// X coordinate.
    pub x: f32,
    /// Y coordinate.
    pub y: f32,
    /// Z coordinate.
    pub z: f32,
}

/// `geometry_msgs/msg/Vector3`: a direction or magnitude in free space.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct Vector3 {
    /// X component.
    pub x: f64,
    /// Y component.
    pub y: f64,
    /// Z component.
    pub z: f64,
}

/// `geometry_msgs/msg/Quaternion`: an orientation; the default is the identity (w = 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    /// X component.
    pub x: f64,
    /// Y component.
    pub y: f64,
    /// Z component.
    pub z: f64,
    /// W (scalar) component.
    pub w: f64,
}

impl Default for Quaternion {
    fn default() -> Self {
        Self {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        }
    }
}

/// `geometry_msgs/msg/Pose`: position and orientation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct Pose {
    /// Position.
    pub position: Point,
    /// Orientation.
    pub orientation: Quaternion,
}

/// `geometry_msgs/msg/PoseStamped`: a pose with stamp and frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct PoseStamped {
    /// Stamp and frame.
    pub header: Header,
    /// The pose.
    pub pose: Pose,
}

/// `geometry_msgs/msg/PointStamped`: a point with stamp and frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct PointStamped {
    /// Stamp and frame.
    pub header: Header,
    /// The point.
    pub point: Point,
}

/// `geometry_msgs/msg/Twist`: linear and angular velocity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct Twist {
    /// Linear velocity, m/s.
    pub linear: Vector3,
    /// Angular velocity, rad/s.
    pub angular: Vector3,
}

/// `geometry_msgs/msg/Transform`: where a child frame sits in its parent.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct Transform {
    /// Translation, metres.
    pub translation: Vector3,
    /// Rotation.
    pub rotation: Quaternion,
}

/// `geometry_msgs/msg/TransformStamped`: one edge of the tf tree (header frame → child frame).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct TransformStamped {
    /// Stamp and parent frame.
    pub header: Header,
    /// The child frame.
    pub child_frame_id: String,
    /// Child pose in the parent frame.
    pub transform: Transform,
}

/// `geometry_msgs/msg/Polygon`: a closed polygon given by its vertices.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Polygon {
    /// Vertices in order.
    pub points: Vec<Point32>,
}

/// `geometry_msgs/msg/PolygonStamped`: a polygon with stamp and frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct PolygonStamped {
    /// Stamp and frame.
    pub header: Header,
    /// The polygon.
    pub polygon: Polygon,
}

/// `geometry_msgs/msg/PoseWithCovariance`: a pose with its 6×6 row-major covariance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PoseWithCovariance {
    /// The pose.
    pub pose: Pose,
    /// Covariance of (x, y, z, rot x, rot y, rot z), row-major.
    #[serde(with = "crate::fixed_array")]
    pub covariance: [f64; 36],
}

impl Default for PoseWithCovariance {
    fn default() -> Self {
        Self {
            pose: Pose::default(),
            covariance: [0.0; 36],
        }
    }
}

/// `geometry_msgs/msg/TwistWithCovariance`: a twist with its 6×6 row-major covariance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TwistWithCovariance {
    /// The twist.
    pub twist: Twist,
    /// Covariance of (x, y, z, rot x, rot y, rot z), row-major.
    #[serde(with = "crate::fixed_array")]
    pub covariance: [f64; 36],
}

impl Default for TwistWithCovariance {
    fn default() -> Self {
        Self {
            twist: Twist::default(),
            covariance: [0.0; 36],
        }
    }
}

ros_message!(
    Point,
    "geometry_msgs/msg/Point",
    [],
    ["float64 x", "float64 y", "float64 z"]
);
ros_message!(
    Point32,
    "geometry_msgs/msg/Point32",
    [],
    ["float32 x", "float32 y", "float32 z"]
);
ros_message!(
    Vector3,
    "geometry_msgs/msg/Vector3",
    [],
    ["float64 x", "float64 y", "float64 z"]
);
ros_message!(
    Quaternion,
    "geometry_msgs/msg/Quaternion",
    [],
    ["float64 x 0", "float64 y 0", "float64 z 0", "float64 w 1"]
);
ros_message!(
    Pose,
    "geometry_msgs/msg/Pose",
    [Point, Quaternion],
    [
        "geometry_msgs/Point position",
        "geometry_msgs/Quaternion orientation"
    ]
);
ros_message!(
    PoseStamped,
    "geometry_msgs/msg/PoseStamped",
    [Header, Pose],
    ["std_msgs/Header header", "geometry_msgs/Pose pose"]
);
ros_message!(
    PointStamped,
    "geometry_msgs/msg/PointStamped",
    [Header, Point],
    ["std_msgs/Header header", "geometry_msgs/Point point"]
);
ros_message!(
    Twist,
    "geometry_msgs/msg/Twist",
    [Vector3],
    [
        "geometry_msgs/Vector3 linear",
        "geometry_msgs/Vector3 angular"
    ]
);
ros_message!(
    Polygon,
    "geometry_msgs/msg/Polygon",
    [Point32],
    ["geometry_msgs/Point32[] points"]
);
ros_message!(
    PolygonStamped,
    "geometry_msgs/msg/PolygonStamped",
    [Header, Polygon],
    ["std_msgs/Header header", "geometry_msgs/Polygon polygon"]
);
ros_message!(
    PoseWithCovariance,
    "geometry_msgs/msg/PoseWithCovariance",
    [Pose],
    ["geometry_msgs/Pose pose", "float64[36] covariance"]
);
ros_message!(
    TwistWithCovariance,
    "geometry_msgs/msg/TwistWithCovariance",
    [Twist],
    ["geometry_msgs/Twist twist", "float64[36] covariance"]
);
ros_message!(
    Transform,
    "geometry_msgs/msg/Transform",
    [Vector3, Quaternion],
    [
        "geometry_msgs/Vector3 translation",
        "geometry_msgs/Quaternion rotation"
    ]
);
ros_message!(
    TransformStamped,
    "geometry_msgs/msg/TransformStamped",
    [Header, Transform],
    [
        "std_msgs/Header header",
        "string child_frame_id",
        "geometry_msgs/Transform transform"
    ]
);
