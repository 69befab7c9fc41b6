//! `PointField` datatype codes: sizes and little-endian reads of one value.

use skyground_msgs::sensor_msgs::PointField;

/// Size in bytes of a datatype, or `None` for an unknown code (0 or > 8).
pub(super) fn size(datatype: u8) -> Option<usize> {
    match datatype {
        PointField::INT8 | PointField::UINT8 => Some(1),
        PointField::INT16 | PointField::UINT16 => Some(2),
        PointField::INT32 | PointField::UINT32 | PointField::FLOAT32 => Some(4),
        PointField::FLOAT64 => Some(8),
        _ => None,
    }
}

/// True for the six integer datatypes.
pub(super) fn is_integer(datatype: u8) -> bool {
    (PointField::INT8..=PointField::UINT32).contains(&datatype)
}

/// True for FLOAT32 and FLOAT64.
pub(super) fn is_float(datatype: u8) -> bool {
    datatype == PointField::FLOAT32 || datatype == PointField::FLOAT64
}

/// The `N` bytes at `offset`, or `None` past the end.
fn bytes<const N: usize>(point: &[u8], offset: usize) -> Option<[u8; N]> {
    point.get(offset..offset.checked_add(N)?)?.try_into().ok()
}

/// Reads a FLOAT32 or FLOAT64 value as `f32` (FLOAT64 is rounded).
pub(super) fn read_coordinate(point: &[u8], offset: usize, datatype: u8) -> Option<f32> {
    match datatype {
        PointField::FLOAT64 => Some(f64::from_le_bytes(bytes(point, offset)?) as f32),
        _ => Some(f32::from_le_bytes(bytes(point, offset)?)),
    }
}

/// Reads a value of any numeric datatype as `f64`.
pub(super) fn read_f64(point: &[u8], offset: usize, datatype: u8) -> Option<f64> {
    match datatype {
        PointField::FLOAT32 => Some(f64::from(f32::from_le_bytes(bytes(point, offset)?))),
        PointField::FLOAT64 => Some(f64::from_le_bytes(bytes(point, offset)?)),
        _ => read_i64(point, offset, datatype).map(|v| v as f64),
    }
}

/// Reads a value of an integer datatype as `i64`; `None` for float types.
pub(super) fn read_i64(point: &[u8], offset: usize, datatype: u8) -> Option<i64> {
    match datatype {
        PointField::INT8 => Some(i64::from(i8::from_le_bytes(bytes(point, offset)?))),
        PointField::UINT8 => Some(i64::from(u8::from_le_bytes(bytes(point, offset)?))),
        PointField::INT16 => Some(i64::from(i16::from_le_bytes(bytes(point, offset)?))),
        PointField::UINT16 => Some(i64::from(u16::from_le_bytes(bytes(point, offset)?))),
        PointField::INT32 => Some(i64::from(i32::from_le_bytes(bytes(point, offset)?))),
        PointField::UINT32 => Some(i64::from(u32::from_le_bytes(bytes(point, offset)?))),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_kinds() {
        let sizes: Vec<_> = (0..=9).map(size).collect();
        assert_eq!(
            sizes,
            [
                None,
                Some(1),
                Some(1),
                Some(2),
                Some(2),
                Some(4),
                Some(4),
                Some(4),
                Some(8),
                None
            ]
        );
        assert!((1..=6).all(is_integer) && !is_integer(7) && !is_integer(0));
        assert!(is_float(7) && is_float(8) && !is_float(6));
    }

    #[test]
    fn reads_are_little_endian_and_bounded() {
        let p = [0xff, 0xfe, 0x01, 0x00, 0x00, 0x00, 0x80, 0x3f];
        assert_eq!(read_i64(&p, 0, PointField::INT8), Some(-1));
        assert_eq!(read_i64(&p, 0, PointField::UINT8), Some(255));
        assert_eq!(read_i64(&p, 0, PointField::INT16), Some(-257));
        assert_eq!(read_i64(&p, 1, PointField::UINT16), Some(0x01fe));
        assert_eq!(read_i64(&p, 2, PointField::UINT32), Some(1));
        assert_eq!(read_f64(&p, 4, PointField::FLOAT32), Some(1.0));
        assert_eq!(read_coordinate(&p, 4, PointField::FLOAT32), Some(1.0));
        assert_eq!(read_i64(&p, 4, PointField::FLOAT32), None);
        assert_eq!(read_f64(&p, 5, PointField::FLOAT32), None);
        assert_eq!(read_f64(&p, 1, PointField::FLOAT64), None);
        assert_eq!(read_f64(&p, usize::MAX, PointField::INT8), None);
    }
}
