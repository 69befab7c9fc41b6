//! Arbitrary `sensor_msgs/PointCloud2` messages → `skyground_nodes::convert::pointcloud2::decode`.
//!
//! The message is built with `arbitrary`, biased so that field names, sizes
//! and offsets are often plausible (the decoder's deep paths) while still
//! covering the full u32 range (its overflow checks).

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use skyground_msgs::sensor_msgs::{PointCloud2, PointField};
use skyground_msgs::std_msgs::Header;
use skyground_nodes::convert::pointcloud2::decode;

/// A size or offset: usually small, sometimes anything.
#[derive(Debug, Arbitrary)]
enum Num {
    Small(u8),
    Medium(u16),
    Any(u32),
}

impl Num {
    fn get(&self) -> u32 {
        match *self {
            Num::Small(v) => v.into(),
            Num::Medium(v) => v.into(),
            Num::Any(v) => v,
        }
    }
}

/// A field name: usually one the decoder looks for.
#[derive(Debug, Arbitrary)]
enum Name {
    X,
    Y,
    Z,
    Intensity,
    Label,
    Building,
    Rgb,
    Other(String),
}

impl Name {
    fn get(self) -> String {
        match self {
            Name::X => "x".into(),
            Name::Y => "y".into(),
            Name::Z => "z".into(),
            Name::Intensity => "intensity".into(),
            Name::Label => "label".into(),
            Name::Building => "building".into(),
            Name::Rgb => "rgb".into(),
            Name::Other(s) => s,
        }
    }
}

#[derive(Debug, Arbitrary)]
struct Field {
    name: Name,
    offset: Num,
    datatype: u8,
    count: Num,
}

#[derive(Debug, Arbitrary)]
struct Input {
    height: Num,
    width: Num,
    fields: Vec<Field>,
    is_bigendian: bool,
    point_step: Num,
    row_step: Num,
    is_dense: bool,
    data: Vec<u8>,
}

fuzz_target!(|input: Input| {
    let msg = PointCloud2 {
        header: Header::default(),
        height: input.height.get(),
        width: input.width.get(),
        fields: input
            .fields
            .into_iter()
            .map(|f| PointField {
                name: f.name.get(),
                offset: f.offset.get(),
                datatype: f.datatype,
                count: f.count.get(),
            })
            .collect(),
        is_bigendian: input.is_bigendian,
        point_step: input.point_step.get(),
        row_step: input.row_step.get(),
        data: input.data,
        is_dense: input.is_dense,
    };
    if let Ok(decoded) = decode(&msg) {
        assert_eq!(decoded.cloud.validate(), Ok(()));
    }
});
