//! `PointCloud2` → `Cloud`, for any field order, offsets, steps and row padding.

use skyground_core::cloud::Cloud;

use super::datatype;
use super::error::PointCloud2Error;
use skyground_msgs::sensor_msgs::{PointCloud2, PointField};

/// A decoded cloud and what was left out of it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Decoded {
    /// The points (origin zero: PointCloud2 carries no origin).
    pub cloud: Cloud,
    /// Points dropped because x, y or z was NaN or infinite.
    pub dropped_non_finite: usize,
    /// Every other FLOAT32 field (count 1), by name, in field order: the
    /// named extra columns of [`super::encode_with`].
    pub extra: Vec<(String, Vec<f32>)>,
}

/// The fields [`decode`] reads into the cloud itself.
const KNOWN: [&str; 8] = [
    "x",
    "y",
    "z",
    "intensity",
    "label",
    "building",
    "return_number",
    "number_of_returns",
];

impl Decoded {
    /// The extra column called `name`, if the message had one.
    pub fn column(&self, name: &str) -> Option<&[f32]> {
        self.extra
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }
}

/// Where one field lives in a point record.
#[derive(Debug, Clone, Copy)]
struct Slot {
    /// The field's name, for errors.
    name: &'static str,
    /// Byte offset in the record.
    offset: usize,
    /// Datatype code.
    datatype: u8,
}

/// What values a field may hold.
#[derive(Clone, Copy)]
enum Kind {
    /// FLOAT32 or FLOAT64.
    Float,
    /// Any numeric datatype.
    Numeric,
    /// An integer datatype.
    Integer,
}

/// Decodes a `PointCloud2` into a [`Cloud`].
///
/// Needs `x`, `y`, `z` (FLOAT32 or FLOAT64, rounded to f32); reads
/// `intensity` (any numeric type, as f32), `label` (integer type, 0..=255)
/// `building` (integer type, 0..=u32::MAX), `return_number` and
/// `number_of_returns` (integer type, 0..=255) when present; ignores other
/// fields. Organized clouds (height > 1) are read row by row, skipping the
/// padding between `width × point_step` and `row_step`.
///
/// Points with a non-finite coordinate (after rounding to f32) are dropped
/// and counted, unless the message says `is_dense`: then the producer has
/// asserted there are none, and points are kept exactly as sent, so a
/// consumer sees what was published.
///
/// Every size is checked before any data is read, with checked arithmetic;
/// no input can make this panic.
pub fn decode(msg: &PointCloud2) -> Result<Decoded, PointCloud2Error> {
    if msg.is_bigendian {
        return Err(PointCloud2Error::BigEndian);
    }
    let x = slot(msg, "x", Kind::Float)?.ok_or(PointCloud2Error::MissingField { name: "x" })?;
    let y = slot(msg, "y", Kind::Float)?.ok_or(PointCloud2Error::MissingField { name: "y" })?;
    let z = slot(msg, "z", Kind::Float)?.ok_or(PointCloud2Error::MissingField { name: "z" })?;
    let intensity = slot(msg, "intensity", Kind::Numeric)?;
    let label = slot(msg, "label", Kind::Integer)?;
    let building = slot(msg, "building", Kind::Integer)?;
    let return_number = slot(msg, "return_number", Kind::Integer)?;
    let number_of_returns = slot(msg, "number_of_returns", Kind::Integer)?;

    let overflow = PointCloud2Error::SizeOverflow {
        width: msg.width,
        height: msg.height,
    };
    let (width, height) = (msg.width as usize, msg.height as usize);
    let (point_step, row_step) = (msg.point_step as usize, msg.row_step as usize);
    let points = width.checked_mul(height).ok_or(overflow.clone())?;
    let row_bytes = width.checked_mul(point_step).ok_or(overflow.clone())?;
    if row_step < row_bytes {
        return Err(PointCloud2Error::RowStepTooSmall {
            row_step: msg.row_step,
            width: msg.width,
            point_step: msg.point_step,
        });
    }
    let expected = row_step.checked_mul(height).ok_or(overflow)?;
    if msg.data.len() != expected {
        return Err(PointCloud2Error::DataLength {
            expected,
            got: msg.data.len(),
        });
    }

    let extra: Vec<(String, usize)> = msg
        .fields
        .iter()
        .filter(|f| f.datatype == PointField::FLOAT32 && f.count == 1)
        .filter(|f| !KNOWN.contains(&f.name.as_str()))
        .filter(|f| {
            (f.offset as usize)
                .checked_add(4)
                .is_some_and(|e| e <= point_step)
        })
        .map(|f| (f.name.clone(), f.offset as usize))
        .collect();
    let mut out = Decoded {
        extra: extra
            .iter()
            .map(|(n, _)| (n.clone(), Vec::with_capacity(points)))
            .collect(),
        ..Decoded::default()
    };
    let cloud = &mut out.cloud;
    cloud.xyz.reserve_exact(points);
    cloud.intensity = intensity.map(|_| Vec::with_capacity(points));
    cloud.label = label.map(|_| Vec::with_capacity(points));
    cloud.building = building.map(|_| Vec::with_capacity(points));
    cloud.return_number = return_number.map(|_| Vec::with_capacity(points));
    cloud.number_of_returns = number_of_returns.map(|_| Vec::with_capacity(points));
    if points == 0 {
        // Without this, width 0 and height 4e9 (data length 0 fits) would walk
        // four billion empty rows: found by fuzzing.
        return Ok(out);
    }
    // point_step ≥ 4 here (x fits in it); max(1) only keeps chunks_exact total.
    let rows = (0..height).filter_map(|r| {
        let start = r.checked_mul(row_step)?;
        msg.data.get(start..start.checked_add(row_bytes)?)
    });
    for (index, record) in rows
        .flat_map(|row| row.chunks_exact(point_step.max(1)))
        .enumerate()
    {
        let p = [
            coordinate(record, x, msg)?,
            coordinate(record, y, msg)?,
            coordinate(record, z, msg)?,
        ];
        if !msg.is_dense && !p.iter().all(|v| v.is_finite()) {
            out.dropped_non_finite += 1;
            continue;
        }
        cloud.xyz.push(p);
        if let (Some(values), Some(s)) = (cloud.intensity.as_mut(), intensity) {
            values.push(
                datatype::read_f64(record, s.offset, s.datatype)
                    .ok_or_else(|| out_of_record(s, msg))? as f32,
            );
        }
        if let (Some(values), Some(s)) = (cloud.label.as_mut(), label) {
            values.push(integer(record, s, index, msg)?);
        }
        if let (Some(values), Some(s)) = (cloud.building.as_mut(), building) {
            values.push(integer(record, s, index, msg)?);
        }
        if let (Some(values), Some(s)) = (cloud.return_number.as_mut(), return_number) {
            values.push(integer(record, s, index, msg)?);
        }
        if let (Some(values), Some(s)) = (cloud.number_of_returns.as_mut(), number_of_returns) {
            values.push(integer(record, s, index, msg)?);
        }
        for ((_, values), (_, o)) in out.extra.iter_mut().zip(&extra) {
            let v = datatype::read_f64(record, *o, PointField::FLOAT32).unwrap_or(f64::NAN);
            values.push(v as f32);
        }
    }
    Ok(out)
}

/// Finds the first field called `name` and checks datatype, count and fit.
fn slot(
    msg: &PointCloud2,
    name: &'static str,
    kind: Kind,
) -> Result<Option<Slot>, PointCloud2Error> {
    let Some(field) = msg.fields.iter().find(|f| f.name == name) else {
        return Ok(None);
    };
    let unsupported = PointCloud2Error::UnsupportedDatatype {
        field: name,
        datatype: field.datatype,
    };
    let size = datatype::size(field.datatype).ok_or(unsupported.clone())?;
    let allowed = match kind {
        Kind::Float => datatype::is_float(field.datatype),
        Kind::Numeric => true,
        Kind::Integer => datatype::is_integer(field.datatype),
    };
    if !allowed {
        return Err(unsupported);
    }
    if field.count != 1 {
        return Err(PointCloud2Error::UnsupportedCount {
            field: name,
            count: field.count,
        });
    }
    let offset = field.offset as usize;
    if offset
        .checked_add(size)
        .is_none_or(|end| end > msg.point_step as usize)
    {
        return Err(PointCloud2Error::FieldOutOfBounds {
            field: name,
            offset: field.offset,
            size,
            point_step: msg.point_step,
        });
    }
    Ok(Some(Slot {
        name,
        offset,
        datatype: field.datatype,
    }))
}

/// Reads one coordinate of a record.
fn coordinate(record: &[u8], s: Slot, msg: &PointCloud2) -> Result<f32, PointCloud2Error> {
    datatype::read_coordinate(record, s.offset, s.datatype).ok_or_else(|| out_of_record(s, msg))
}

/// Reads an integer attribute and converts it to `T` (u8 or u32), range-checked.
fn integer<T: TryFrom<i64>>(
    record: &[u8],
    s: Slot,
    point: usize,
    msg: &PointCloud2,
) -> Result<T, PointCloud2Error> {
    let value =
        datatype::read_i64(record, s.offset, s.datatype).ok_or_else(|| out_of_record(s, msg))?;
    T::try_from(value).map_err(|_| PointCloud2Error::ValueOutOfRange {
        field: s.name,
        point,
        value,
    })
}

/// The error for a read past a record (unreachable after [`slot`]'s checks).
fn out_of_record(s: Slot, msg: &PointCloud2) -> PointCloud2Error {
    PointCloud2Error::FieldOutOfBounds {
        field: s.name,
        offset: s.offset as u32,
        size: datatype::size(s.datatype).unwrap_or(0),
        point_step: msg.point_step,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use skyground_msgs::sensor_msgs::PointField;

    /// An xyz FLOAT32 cloud of `width` × `height` points, 12 bytes each, no row padding.
    fn xyz_msg(width: u32, height: u32) -> PointCloud2 {
        let n = (width * height) as usize;
        let mut data = Vec::new();
        for i in 0..n {
            for k in 0..3 {
                data.extend_from_slice(&((i * 3 + k) as f32).to_le_bytes());
            }
        }
        PointCloud2 {
            height,
            width,
            fields: vec![
                PointField::single("x", 0, PointField::FLOAT32),
                PointField::single("y", 4, PointField::FLOAT32),
                PointField::single("z", 8, PointField::FLOAT32),
            ],
            point_step: 12,
            row_step: 12 * width,
            data,
            ..PointCloud2::default()
        }
    }

    #[test]
    fn empty_rows_return_at_once() {
        let mut msg = crate::convert::pointcloud2::encode(
            &skyground_core::cloud::Cloud::from_xyz(vec![]),
            skyground_msgs::std_msgs::Header::default(),
            &crate::convert::pointcloud2::EncodeOptions::default(),
        );
        msg.height = u32::MAX;
        msg.width = 0;
        msg.row_step = 0;
        assert_eq!(decode(&msg).map(|d| d.cloud.len()), Ok(0));
    }

    #[test]
    fn reads_plain_xyz() {
        let d = decode(&xyz_msg(2, 1)).unwrap();
        assert_eq!(d.cloud.xyz, [[0.0, 1.0, 2.0], [3.0, 4.0, 5.0]]);
        assert_eq!(d.dropped_non_finite, 0);
        assert_eq!(d.cloud.intensity, None);
    }

    #[test]
    fn empty_cloud_with_attributes_gives_empty_columns() {
        let mut m = xyz_msg(0, 0);
        m.fields
            .push(PointField::single("label", 12, PointField::UINT8));
        m.point_step = 13;
        let d = decode(&m).unwrap();
        assert!(d.cloud.is_empty());
        assert_eq!(d.cloud.label, Some(vec![]));
    }

    #[test]
    fn missing_coordinate() {
        let mut m = xyz_msg(1, 1);
        m.fields.retain(|f| f.name != "y");
        assert_eq!(
            decode(&m),
            Err(PointCloud2Error::MissingField { name: "y" })
        );
    }

    #[test]
    fn unknown_datatype() {
        for bad in [0, 9, 255] {
            let mut m = xyz_msg(1, 1);
            m.fields[2].datatype = bad;
            assert_eq!(
                decode(&m),
                Err(PointCloud2Error::UnsupportedDatatype {
                    field: "z",
                    datatype: bad
                })
            );
        }
    }

    #[test]
    fn datatype_not_allowed_for_field() {
        let mut m = xyz_msg(1, 1);
        m.fields[0].datatype = PointField::INT32;
        assert_eq!(
            decode(&m),
            Err(PointCloud2Error::UnsupportedDatatype {
                field: "x",
                datatype: PointField::INT32
            })
        );
        let mut m = xyz_msg(1, 1);
        m.fields
            .push(PointField::single("label", 8, PointField::FLOAT32));
        assert_eq!(
            decode(&m),
            Err(PointCloud2Error::UnsupportedDatatype {
                field: "label",
                datatype: PointField::FLOAT32
            })
        );
    }

    #[test]
    fn count_other_than_one() {
        let mut m = xyz_msg(1, 1);
        m.fields[1].count = 3;
        assert_eq!(
            decode(&m),
            Err(PointCloud2Error::UnsupportedCount {
                field: "y",
                count: 3
            })
        );
    }

    #[test]
    fn field_past_point_step() {
        let mut m = xyz_msg(1, 1);
        m.point_step = 10;
        assert_eq!(
            decode(&m),
            Err(PointCloud2Error::FieldOutOfBounds {
                field: "z",
                offset: 8,
                size: 4,
                point_step: 10
            })
        );
        let mut m = xyz_msg(1, 1);
        m.fields[0].offset = u32::MAX;
        assert!(matches!(
            decode(&m),
            Err(PointCloud2Error::FieldOutOfBounds { field: "x", .. })
        ));
    }

    #[test]
    fn row_step_smaller_than_row() {
        let mut m = xyz_msg(2, 1);
        m.row_step = 20;
        assert_eq!(
            decode(&m),
            Err(PointCloud2Error::RowStepTooSmall {
                row_step: 20,
                width: 2,
                point_step: 12
            })
        );
    }

    #[test]
    fn data_length_mismatch() {
        let mut m = xyz_msg(2, 2);
        m.data.pop();
        assert_eq!(
            decode(&m),
            Err(PointCloud2Error::DataLength {
                expected: 48,
                got: 47
            })
        );
    }

    #[test]
    fn big_endian_is_refused() {
        let mut m = xyz_msg(1, 1);
        m.is_bigendian = true;
        assert_eq!(decode(&m), Err(PointCloud2Error::BigEndian));
    }

    #[test]
    fn huge_sizes_overflow_or_mismatch_without_panic() {
        let mut m = xyz_msg(1, 1);
        m.width = u32::MAX;
        m.height = u32::MAX;
        m.row_step = u32::MAX;
        let err = decode(&m).unwrap_err();
        if usize::BITS < 64 {
            assert!(matches!(err, PointCloud2Error::SizeOverflow { .. }));
        } else {
            // u32 × u32 always fits a 64-bit usize (SizeOverflow is a 32-bit
            // case), so here the row is simply too long for row_step.
            assert!(matches!(err, PointCloud2Error::RowStepTooSmall { .. }));
        }
        m.width = 1;
        m.row_step = u32::MAX;
        assert!(matches!(
            decode(&m),
            Err(PointCloud2Error::SizeOverflow { .. } | PointCloud2Error::DataLength { .. })
        ));
    }

    #[test]
    fn label_out_of_range() {
        let mut m = xyz_msg(2, 1);
        m.fields
            .push(PointField::single("label", 0, PointField::INT32));
        // x of point 0 is 0.0 (bits 0: in range); x of point 1 is 3.0 (bits 0x40400000).
        assert_eq!(
            decode(&m),
            Err(PointCloud2Error::ValueOutOfRange {
                field: "label",
                point: 1,
                value: 0x4040_0000
            })
        );
        let mut m = xyz_msg(1, 1);
        m.data[0] = 0xff;
        m.fields
            .push(PointField::single("building", 0, PointField::INT8));
        assert!(matches!(
            decode(&m),
            Err(PointCloud2Error::ValueOutOfRange {
                field: "building",
                value: -1,
                ..
            })
        ));
    }

    #[test]
    fn reads_any_order_types_and_extra_fields() {
        // 24-byte record: label u32 @0, intensity u16 @4, rgb (unknown) @6,
        // x f64 @8, y f32 @16, z f32 @20; fields listed out of order.
        let mut data = Vec::new();
        data.extend_from_slice(&7u32.to_le_bytes());
        data.extend_from_slice(&300u16.to_le_bytes());
        data.extend_from_slice(&[0xaa, 0xbb]);
        data.extend_from_slice(&1.5f64.to_le_bytes());
        data.extend_from_slice(&(-2.0f32).to_le_bytes());
        data.extend_from_slice(&4.25f32.to_le_bytes());
        let m = PointCloud2 {
            height: 1,
            width: 1,
            fields: vec![
                PointField::single("z", 20, PointField::FLOAT32),
                PointField::single("rgb", 6, PointField::UINT16),
                PointField::single("label", 0, PointField::UINT32),
                PointField::single("y", 16, PointField::FLOAT32),
                PointField::single("intensity", 4, PointField::UINT16),
                PointField::single("x", 8, PointField::FLOAT64),
            ],
            point_step: 24,
            row_step: 24,
            data,
            ..PointCloud2::default()
        };
        let d = decode(&m).unwrap();
        assert_eq!(d.cloud.xyz, [[1.5, -2.0, 4.25]]);
        assert_eq!(d.cloud.intensity, Some(vec![300.0]));
        assert_eq!(d.cloud.label, Some(vec![7]));
        assert_eq!(d.cloud.building, None);
    }

    #[test]
    fn organized_rows_skip_row_padding() {
        let mut m = xyz_msg(2, 1);
        let row: Vec<u8> = m.data.clone();
        m.height = 3;
        m.row_step = 24 + 5;
        m.data = [row.as_slice(), &[9; 5]].concat().repeat(3);
        let d = decode(&m).unwrap();
        assert_eq!(d.cloud.len(), 6);
        assert_eq!(d.cloud.xyz[4], [0.0, 1.0, 2.0]);
        assert_eq!(d.cloud.xyz[5], [3.0, 4.0, 5.0]);
    }

    #[test]
    fn non_finite_points_are_dropped_unless_dense() {
        let mut m = xyz_msg(3, 1);
        m.data[12..16].copy_from_slice(&f32::NAN.to_le_bytes());
        m.is_dense = false;
        let d = decode(&m).unwrap();
        assert_eq!(d.dropped_non_finite, 1);
        assert_eq!(d.cloud.xyz, [[0.0, 1.0, 2.0], [6.0, 7.0, 8.0]]);
        m.is_dense = true;
        let d = decode(&m).unwrap();
        assert_eq!((d.dropped_non_finite, d.cloud.len()), (0, 3));
        assert!(d.cloud.xyz[1][0].is_nan());
    }

    #[test]
    fn float64_too_large_for_f32_counts_as_non_finite() {
        let mut m = xyz_msg(1, 1);
        m.fields[0] = PointField::single("x", 0, PointField::FLOAT64);
        m.fields[1].offset = 8;
        m.fields[2].offset = 12;
        m.point_step = 16;
        m.row_step = 16;
        m.data = [1e300f64.to_le_bytes().as_slice(), &[0; 8]].concat();
        let d = decode(&m).unwrap();
        assert_eq!((d.dropped_non_finite, d.cloud.len()), (1, 0));
    }
}
