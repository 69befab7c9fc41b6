//! Why a `PointCloud2` could not be decoded.

/// A `PointCloud2` that cannot be read as a [`Cloud`](skyground_core::cloud::Cloud).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PointCloud2Error {
    /// A coordinate field is absent.
    #[error("PointCloud2 has no `{name}` field; x, y and z are required")]
    MissingField {
        /// `x`, `y` or `z`.
        name: &'static str,
    },
    /// A field's datatype code is unknown or not usable for that field.
    #[error("field `{field}` has datatype {datatype}; allowed: {}", allowed_datatypes(.field))]
    UnsupportedDatatype {
        /// Field name.
        field: &'static str,
        /// The datatype code found.
        datatype: u8,
    },
    /// A field holds more or fewer than one value per point.
    #[error("field `{field}` has count {count}; only count 1 is supported")]
    UnsupportedCount {
        /// Field name.
        field: &'static str,
        /// The count found.
        count: u32,
    },
    /// A field does not fit inside one point record.
    #[error(
        "field `{field}` at offset {offset} with {size} bytes does not fit in point_step {point_step}"
    )]
    FieldOutOfBounds {
        /// Field name.
        field: &'static str,
        /// Offset of the field in the point.
        offset: u32,
        /// Size of the field's datatype in bytes.
        size: usize,
        /// Bytes per point.
        point_step: u32,
    },
    /// A row is shorter than its points.
    #[error("row_step {row_step} is smaller than width {width} × point_step {point_step}")]
    RowStepTooSmall {
        /// Bytes per row.
        row_step: u32,
        /// Points per row.
        width: u32,
        /// Bytes per point.
        point_step: u32,
    },
    /// `data` is not `row_step × height` bytes.
    #[error("data holds {got} bytes but row_step × height = {expected}")]
    DataLength {
        /// `row_step × height`.
        expected: usize,
        /// `data.len()`.
        got: usize,
    },
    /// The data is big endian, which this decoder does not read.
    #[error("big-endian PointCloud2 data is not supported; publish little endian")]
    BigEndian,
    /// The sizes do not fit in this machine's address space.
    #[error("width {width} × height {height} (or the byte size it implies) overflows usize")]
    SizeOverflow {
        /// Points per row.
        width: u32,
        /// Rows.
        height: u32,
    },
    /// An integer attribute value does not fit the cloud's attribute type.
    #[error("field `{field}` of point {point} is {value}, outside {}", value_range(.field))]
    ValueOutOfRange {
        /// `label` (u8) or `building` (u32).
        field: &'static str,
        /// Index of the point (row-major over the whole message).
        point: usize,
        /// The value found.
        value: i64,
    },
}

/// The datatypes accepted for a field, for error messages.
fn allowed_datatypes(field: &str) -> &'static str {
    match field {
        "x" | "y" | "z" => "FLOAT32 (7) or FLOAT64 (8)",
        "intensity" => "any of INT8 (1) .. FLOAT64 (8)",
        _ => "an integer type, INT8 (1) .. UINT32 (6)",
    }
}

/// The value range of an integer attribute, for error messages.
fn value_range(field: &str) -> &'static str {
    match field {
        "label" => "0..=255 (u8)",
        _ => "0..=4294967295 (u32)",
    }
}
