//! The building id as a LAS 1.4 "extra bytes" dimension.
//!
//! Our writer appends 4 bytes to every point record and declares them in an
//! Extra Bytes VLR (`LASF_Spec`, record 4) as one `unsigned long` (u32, type 5)
//! named `building`, with no scale/offset. Other LAS tools (PDAL, LAStools)
//! see it as a named dimension. The reader finds that descriptor again (in
//! any file, among other extra-bytes dimensions) and its byte offset.

use ::las::{Header, Vlr};

/// User id of the ASPRS-defined VLRs.
const USER_ID: &str = "LASF_Spec";
/// Record id of the Extra Bytes VLR.
const RECORD_ID: u16 = 4;
/// Size of one extra-bytes descriptor.
const DESCRIPTOR_LEN: usize = 192;
/// Data type code of `unsigned long` (u32).
const TYPE_U32: u8 = 5;
/// Option bits saying scale (bit 3) or offset (bit 4) apply.
const SCALED: u8 = 0b1_1000;
/// Name of the dimension.
pub const NAME: &str = "building";
/// Bytes the dimension adds to each point record.
pub const LEN: u16 = 4;

/// The Extra Bytes VLR declaring the `building` dimension.
pub fn building_vlr() -> Vlr {
    let mut d = [0u8; DESCRIPTOR_LEN];
    d[2] = TYPE_U32;
    put(&mut d[4..36], NAME);
    put(&mut d[160..192], "building id, 0 = none");
    Vlr {
        user_id: USER_ID.into(),
        record_id: RECORD_ID,
        description: "skyground building id".into(),
        data: d.to_vec(),
    }
}

fn put(field: &mut [u8], text: &str) {
    for (f, b) in field.iter_mut().zip(text.bytes()) {
        *f = b;
    }
}

/// Byte offset of our `building` u32 inside each point record, if the file declares it.
pub fn building_offset(header: &Header) -> Option<usize> {
    let format = header.point_format();
    let extra = usize::from(format.extra_bytes);
    let first_extra = usize::from(format.len()).checked_sub(extra)?;
    let vlr = header
        .all_vlrs()
        .find(|v| v.user_id == USER_ID && v.record_id == RECORD_ID)?;
    let mut offset = 0usize;
    for d in vlr.data.chunks_exact(DESCRIPTOR_LEN) {
        let (&data_type, &options, name) = (d.get(2)?, d.get(3)?, d.get(4..36)?);
        let name = name.split(|&b| b == 0).next().unwrap_or_default();
        if name == NAME.as_bytes() && data_type == TYPE_U32 && options & SCALED == 0 {
            let end = offset.checked_add(usize::from(LEN))?;
            return (end <= extra).then_some(first_extra + offset);
        }
        offset = offset.checked_add(value_size(data_type, options)?)?;
    }
    None
}

/// Bytes one value of an extra-bytes data type takes (`None` for unknown types).
fn value_size(data_type: u8, options: u8) -> Option<usize> {
    let scalar = |t: u8| {
        let sizes = [1, 1, 2, 2, 4, 4, 8, 8, 4, 8];
        sizes.get(usize::from(t).checked_sub(1)?).copied()
    };
    match data_type {
        // "Undocumented extra bytes": the options field holds the byte count.
        0 => Some(usize::from(options)),
        1..=10 => scalar(data_type),
        // Deprecated 2- and 3-element arrays of the ten scalar types.
        11..=20 => scalar(data_type - 10).map(|s| 2 * s),
        21..=30 => scalar(data_type - 20).map(|s| 3 * s),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_follow_the_spec_table() {
        assert_eq!(value_size(0, 3), Some(3));
        assert_eq!(value_size(5, 0), Some(4));
        assert_eq!(value_size(10, 0), Some(8));
        assert_eq!(value_size(13, 0), Some(4));
        assert_eq!(value_size(30, 0), Some(24));
        assert_eq!(value_size(31, 0), None);
    }

    #[test]
    fn descriptor_has_name_and_type() {
        let vlr = building_vlr();
        assert_eq!(vlr.data.len(), DESCRIPTOR_LEN);
        assert_eq!(vlr.data[2], TYPE_U32);
        assert!(vlr.data[4..36].starts_with(b"building\0"));
    }
}
