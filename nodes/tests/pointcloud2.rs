//! PointCloud2 codec: encode→decode round trips and decoding of arbitrary messages.

use proptest::prelude::*;
use skyground_core::cloud::Cloud;
use skyground_msgs::sensor_msgs::{PointCloud2, PointField};
use skyground_msgs::std_msgs::Header;
use skyground_msgs::{from_cdr, to_cdr};
use skyground_nodes::convert::pointcloud2::{EncodeOptions, PointCloud2Error, decode, encode};

fn header() -> Header {
    Header {
        frame_id: "map".into(),
        ..Header::default()
    }
}

fn cloud(n: usize, intensity: bool, label: bool, building: bool) -> Cloud {
    let mut c = Cloud::from_xyz(
        (0..n)
            .map(|i| [i as f32 * 0.5, -(i as f32), 1e6 + i as f32])
            .collect(),
    );
    c.intensity = intensity.then(|| (0..n).map(|i| i as f32 * 0.25).collect());
    c.label = label.then(|| (0..n).map(|i| (i % 256) as u8).collect());
    c.building = building.then(|| (0..n).map(|i| u32::MAX - i as u32).collect());
    c
}

#[test]
fn round_trip_every_attribute_combination_f32_and_f64() {
    for double in [false, true] {
        for mask in 0..8 {
            let c = cloud(17, mask & 1 != 0, mask & 2 != 0, mask & 4 != 0);
            let msg = encode(&c, header(), &EncodeOptions { double });
            let d = decode(&msg).unwrap();
            assert_eq!(d.cloud, c, "double {double}, mask {mask}");
            assert_eq!(d.dropped_non_finite, 0);
        }
    }
}

#[test]
fn round_trip_through_cdr() {
    let c = cloud(5, true, true, true);
    let msg = encode(&c, header(), &EncodeOptions::default());
    let back: PointCloud2 = from_cdr(&to_cdr(&msg).unwrap()).unwrap();
    assert_eq!(back, msg);
    assert_eq!(decode(&back).unwrap().cloud, c);
}

#[test]
fn organized_cloud_with_row_padding_round_trips() {
    // Re-shape an encoded cloud into 3 rows of 4 points, with 7 bytes of row padding.
    let c = cloud(12, true, true, false);
    let mut msg = encode(&c, header(), &EncodeOptions { double: true });
    let row_bytes = 4 * msg.point_step as usize;
    let pad = [0xee; 7];
    msg.data = msg
        .data
        .chunks(row_bytes)
        .flat_map(|row| [row, &pad].concat())
        .collect();
    msg.width = 4;
    msg.height = 3;
    msg.row_step = (row_bytes + pad.len()) as u32;
    assert_eq!(decode(&msg).unwrap().cloud, c);
}

/// Points 0 and 2 of a column.
fn keep<T: Copy>(v: &[T]) -> Vec<T> {
    vec![v[0], v[2]]
}

#[test]
fn nan_points_dropped_with_their_attributes() {
    let mut c = cloud(4, true, true, true);
    c.xyz[1][2] = f32::NAN;
    c.xyz[3][0] = f32::NEG_INFINITY;
    let mut msg = encode(&c, header(), &EncodeOptions::default());
    msg.is_dense = false;
    let d = decode(&msg).unwrap();
    assert_eq!(d.dropped_non_finite, 2);
    assert_eq!(d.cloud.xyz, keep(&c.xyz));
    assert_eq!(d.cloud.intensity, c.intensity.as_deref().map(keep));
    assert_eq!(d.cloud.label, c.label.as_deref().map(keep));
    assert_eq!(d.cloud.building, c.building.as_deref().map(keep));
}

#[test]
fn error_messages_carry_the_numbers() {
    let e = PointCloud2Error::DataLength {
        expected: 48,
        got: 47,
    };
    assert_eq!(
        e.to_string(),
        "data holds 47 bytes but row_step × height = 48"
    );
    let e = PointCloud2Error::UnsupportedDatatype {
        field: "x",
        datatype: 3,
    };
    assert!(e.to_string().contains("FLOAT32 (7) or FLOAT64 (8)"));
}

fn arb_cloud() -> impl Strategy<Value = (Cloud, bool)> {
    let finite = -1e7f32..1e7f32;
    (
        prop::collection::vec([finite.clone(), finite.clone(), finite], 0..200),
        any::<(bool, bool, bool, bool)>(),
        any::<u64>(),
    )
        .prop_map(|(xyz, (i, l, b, double), seed)| {
            let n = xyz.len();
            let mut c = Cloud::from_xyz(xyz);
            let s = seed as usize;
            c.intensity = i.then(|| (0..n).map(|k| ((k ^ s) % 1000) as f32 / 7.0).collect());
            c.label = l.then(|| (0..n).map(|k| (k.wrapping_mul(s) % 256) as u8).collect());
            c.building = b.then(|| {
                (0..n)
                    .map(|k| (k as u32).wrapping_mul(seed as u32))
                    .collect()
            });
            (c, double)
        })
}

/// A field with a name the decoder cares about (or not), and any layout.
fn arb_field(max_offset: u32) -> impl Strategy<Value = PointField> {
    (
        prop::sample::select(vec!["x", "y", "z", "intensity", "label", "building", "rgb"]),
        prop_oneof![4 => 0..=max_offset, 1 => any::<u32>()],
        prop_oneof![4 => 1u8..=8, 1 => any::<u8>()],
        prop_oneof![8 => Just(1u32), 1 => any::<u32>()],
    )
        .prop_map(|(name, offset, datatype, count)| PointField {
            name: name.into(),
            offset,
            datatype,
            count,
        })
}

/// Fields that are mostly decodable: x, y, z as floats inside the record, plus others.
fn arb_fields(point_step: u32) -> impl Strategy<Value = Vec<PointField>> {
    let max_offset = point_step.saturating_sub(8);
    let coordinate = move |name: &'static str| {
        (
            0..=max_offset,
            prop_oneof![6 => prop::sample::select(vec![7u8, 8]), 1 => any::<u8>()],
        )
            .prop_map(move |(offset, datatype)| PointField {
                name: name.into(),
                offset,
                datatype,
                count: 1,
            })
    };
    (
        coordinate("x"),
        coordinate("y"),
        coordinate("z"),
        prop::collection::vec(arb_field(max_offset), 0..4),
        any::<prop::sample::Index>(),
    )
        .prop_map(|(x, y, z, mut rest, at)| {
            rest.extend([x, y, z]);
            let shift = at.index(rest.len());
            rest.rotate_left(shift);
            rest
        })
}

/// Messages whose sizes usually agree (so decoding reaches the point loop), sometimes not.
fn arb_message() -> impl Strategy<Value = PointCloud2> {
    (0u32..48)
        .prop_flat_map(|point_step| {
            (
                Just(point_step),
                prop_oneof![
                    1 => prop::collection::vec(arb_field(point_step), 0..9),
                    3 => arb_fields(point_step),
                ],
                0u32..6,
                0u32..5,
                0u32..9,
                any::<(bool, bool)>(),
                prop_oneof![6 => Just(true), 1 => Just(false)],
                prop::collection::vec(any::<u8>(), 0..2048),
                prop_oneof![12 => Just(None), 1 => any::<(u32, u32, u32)>().prop_map(Some)],
            )
        })
        .prop_map(
            |(point_step, fields, width, height, row_pad, (dense, big), fit, bytes, wild)| {
                let row_step = width * point_step + row_pad;
                let len = (row_step * height) as usize;
                let mut data = bytes;
                if fit {
                    data.resize(len, 0x7f);
                }
                let mut msg = PointCloud2 {
                    header: Header::default(),
                    height,
                    width,
                    fields,
                    is_bigendian: big && !fit,
                    point_step,
                    row_step,
                    data,
                    is_dense: dense,
                };
                if let Some((w, h, r)) = wild {
                    (msg.width, msg.height, msg.row_step) = (w, h, r);
                }
                msg
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    #[test]
    fn encode_decode_round_trips((c, double) in arb_cloud()) {
        let msg = encode(&c, header(), &EncodeOptions { double });
        prop_assert_eq!(msg.data.len(), (msg.row_step * msg.height) as usize);
        let d = decode(&msg).unwrap();
        prop_assert_eq!(d.dropped_non_finite, 0);
        prop_assert_eq!(d.cloud, c);
    }

    #[test]
    fn decode_never_panics(msg in arb_message()) {
        if let Ok(d) = decode(&msg) {
            let n = d.cloud.len() + d.dropped_non_finite;
            prop_assert_eq!(n, msg.width as usize * msg.height as usize);
            prop_assert!(d.cloud.validate().is_ok());
        }
    }

    #[test]
    fn decode_of_mutated_valid_message_never_panics(
        (c, double) in arb_cloud(),
        flips in prop::collection::vec((any::<usize>(), any::<u8>()), 0..8),
        step_delta in -8i64..8,
    ) {
        let mut msg = encode(&c, header(), &EncodeOptions { double });
        for (at, v) in flips {
            if !msg.data.is_empty() {
                let i = at % msg.data.len();
                msg.data[i] = v;
            }
        }
        msg.is_dense = false;
        msg.point_step = (i64::from(msg.point_step) + step_delta).clamp(0, u32::MAX.into()) as u32;
        let _ = decode(&msg);
    }
}
