//! `visualization_msgs`: markers for RViz and Foxglove.

use serde::{Deserialize, Serialize};

use crate::builtin_interfaces::Duration;
use crate::geometry_msgs::{Point, Pose, Vector3};
use crate::message::ros_message;
use crate::sensor_msgs::CompressedImage;
use crate::std_msgs::{ColorRGBA, Header};

/// `visualization_msgs/msg/UVCoordinate`: a texture coordinate of one marker vertex.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct UVCoordinate {
    /// Horizontal texture coordinate.
    pub u: f32,
    /// Vertical texture coordinate.
    pub v: f32,
}

/// `visualization_msgs/msg/MeshFile`: a mesh sent inline instead of by resource URI.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct MeshFile {
    /// File name; its extension tells the mesh format.
    pub filename: String,
    /// The file's bytes.
    #[serde(with = "serde_bytes")]
    pub data: Vec<u8>,
}

/// `visualization_msgs/msg/Marker`: one shape to draw (ROS 2 kilted layout).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Marker {
    /// Stamp and frame of the marker.
    pub header: Header,
    /// Namespace; with `id` it names the marker.
    pub ns: String,
    /// Id within the namespace.
    pub id: i32,
    /// Shape, one of the shape constants below.
    pub r#type: i32,
    /// What to do: [`Marker::ADD`], [`Marker::DELETE`] or [`Marker::DELETEALL`].
    pub action: i32,
    /// Pose of the marker.
    pub pose: Pose,
    /// Size along each axis (meaning depends on the shape).
    pub scale: Vector3,
    /// Colour of the whole marker.
    pub color: ColorRGBA,
    /// How long the marker lives; zero means forever.
    pub lifetime: Duration,
    /// True to re-transform the marker into its frame every update.
    pub frame_locked: bool,
    /// Vertices of list and strip shapes.
    pub points: Vec<Point>,
    /// Per-vertex colours (empty to use `color`).
    pub colors: Vec<ColorRGBA>,
    /// URI of a texture image.
    pub texture_resource: String,
    /// Inline texture image.
    pub texture: CompressedImage,
    /// Per-vertex texture coordinates.
    pub uv_coordinates: Vec<UVCoordinate>,
    /// Text of a [`Marker::TEXT_VIEW_FACING`] marker.
    pub text: String,
    /// URI of a mesh for a [`Marker::MESH_RESOURCE`] marker.
    pub mesh_resource: String,
    /// Inline mesh file.
    pub mesh_file: MeshFile,
    /// True to draw the mesh with its own materials.
    pub mesh_use_embedded_materials: bool,
}

impl Marker {
    /// Shape: arrow.
    pub const ARROW: i32 = 0;
    /// Shape: cube.
    pub const CUBE: i32 = 1;
    /// Shape: sphere.
    pub const SPHERE: i32 = 2;
    /// Shape: cylinder.
    pub const CYLINDER: i32 = 3;
    /// Shape: connected line through `points`.
    pub const LINE_STRIP: i32 = 4;
    /// Shape: one line per pair of `points`.
    pub const LINE_LIST: i32 = 5;
    /// Shape: one cube per point.
    pub const CUBE_LIST: i32 = 6;
    /// Shape: one sphere per point.
    pub const SPHERE_LIST: i32 = 7;
    /// Shape: one square per point.
    pub const POINTS: i32 = 8;
    /// Shape: text facing the viewer.
    pub const TEXT_VIEW_FACING: i32 = 9;
    /// Shape: mesh from `mesh_resource` or `mesh_file`.
    pub const MESH_RESOURCE: i32 = 10;
    /// Shape: one triangle per three `points`.
    pub const TRIANGLE_LIST: i32 = 11;
    /// Shape: arrows along `points`.
    pub const ARROW_STRIP: i32 = 12;
    /// Action: add or replace.
    pub const ADD: i32 = 0;
    /// Action: modify (same as add).
    pub const MODIFY: i32 = 0;
    /// Action: delete this marker.
    pub const DELETE: i32 = 2;
    /// Action: delete every marker (of this namespace, if set).
    pub const DELETEALL: i32 = 3;
}

/// `visualization_msgs/msg/MarkerArray`: several markers published together.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct MarkerArray {
    /// The markers.
    pub markers: Vec<Marker>,
}

ros_message!(
    UVCoordinate,
    "visualization_msgs/msg/UVCoordinate",
    [],
    ["float32 u", "float32 v"]
);
ros_message!(
    MeshFile,
    "visualization_msgs/msg/MeshFile",
    [],
    ["string filename", "uint8[] data"]
);
ros_message!(
    Marker,
    "visualization_msgs/msg/Marker",
    [
        Header,
        Pose,
        Vector3,
        ColorRGBA,
        Duration,
        Point,
        CompressedImage,
        UVCoordinate,
        MeshFile,
    ],
    [
        "int32 ARROW = 0",
        "int32 CUBE = 1",
        "int32 SPHERE = 2",
        "int32 CYLINDER = 3",
        "int32 LINE_STRIP = 4",
        "int32 LINE_LIST = 5",
        "int32 CUBE_LIST = 6",
        "int32 SPHERE_LIST = 7",
        "int32 POINTS = 8",
        "int32 TEXT_VIEW_FACING = 9",
        "int32 MESH_RESOURCE = 10",
        "int32 TRIANGLE_LIST = 11",
        "int32 ARROW_STRIP = 12",
        "int32 ADD = 0",
        "int32 MODIFY = 0",
        "int32 DELETE = 2",
        "int32 DELETEALL = 3",
        "std_msgs/Header header",
        "string ns",
        "int32 id",
        "int32 type",
        "int32 action",
        "geometry_msgs/Pose pose",
        "geometry_msgs/Vector3 scale",
        "std_msgs/ColorRGBA color",
        "builtin_interfaces/Duration lifetime",
        "bool frame_locked",
        "geometry_msgs/Point[] points",
        "std_msgs/ColorRGBA[] colors",
        "string texture_resource",
        "sensor_msgs/CompressedImage texture",
        "visualization_msgs/UVCoordinate[] uv_coordinates",
        "string text",
        "string mesh_resource",
        "visualization_msgs/MeshFile mesh_file",
        "bool mesh_use_embedded_materials",
    ]
);
ros_message!(
    MarkerArray,
    "visualization_msgs/msg/MarkerArray",
    [Marker],
    ["visualization_msgs/Marker[] markers"]
);
