//! Everything that can go wrong reading or writing a PLY file.

use crate::cloud::CloudError;

/// A PLY file could not be read or written; messages name the line, element or row.
#[derive(Debug, thiserror::Error)]
pub enum PlyError {
    /// Reading from or writing to the underlying stream failed.
    #[error("I/O error: {0}")]
    Io(#[from] std::io::Error),
    /// The data does not start with the line `ply`.
    #[error("not a PLY file: the first line must be `ply`")]
    BadMagic,
    /// The header never reaches an `end_header` line.
    #[error("PLY header has no `end_header` line (file truncated or not PLY)")]
    MissingEndHeader,
    /// The header has no `format` line.
    #[error("PLY header has no `format` line")]
    MissingFormat,
    /// The `format` line names an unknown encoding.
    #[error(
        "line {line}: unknown PLY format '{found}' (expected ascii, binary_little_endian or binary_big_endian)"
    )]
    UnknownFormat {
        /// 1-based line number in the file.
        line: usize,
        /// The format name found.
        found: String,
    },
    /// The `format` line names a version other than 1.0.
    #[error("line {line}: unsupported PLY version '{found}' (only 1.0 is defined)")]
    UnsupportedVersion {
        /// 1-based line number in the file.
        line: usize,
        /// The version found.
        found: String,
    },
    /// A header line does not follow the PLY grammar.
    #[error("line {line}: malformed PLY header line: {reason}")]
    MalformedHeaderLine {
        /// 1-based line number in the file.
        line: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A property uses a type name PLY does not define.
    #[error(
        "line {line}: unknown PLY property type '{found}' (expected char, uchar, short, ushort, int, uint, float, double or int8 ... float64)"
    )]
    UnknownPropertyType {
        /// 1-based line number in the file.
        line: usize,
        /// The type name found.
        found: String,
    },
    /// The header declares no `vertex` element.
    #[error("PLY header declares no `vertex` element")]
    MissingVertexElement,
    /// The vertex element lacks one of x, y, z.
    #[error("PLY vertex element has no '{axis}' property")]
    MissingCoordinate {
        /// `x`, `y` or `z`.
        axis: &'static str,
    },
    /// A coordinate property is not `float` or `double`.
    #[error("PLY vertex property '{axis}' is {found}; coordinates must be float or double")]
    CoordinateType {
        /// `x`, `y` or `z`.
        axis: &'static str,
        /// The declared type (or `a list`).
        found: String,
    },
    /// An attribute we read (intensity, label, building) is declared as a list.
    #[error("PLY vertex property '{name}' is a list; it must be a scalar")]
    ListAttribute {
        /// The property name.
        name: String,
    },
    /// An element's row count is too large to address.
    #[error("element '{element}' declares {count} rows, more than any file can hold")]
    CountOverflow {
        /// The element name.
        element: String,
        /// The declared row count.
        count: u64,
    },
    /// The body ends before all declared rows were read.
    #[error("truncated {element} data: element '{element}' ends at index {index} of {count}")]
    Truncated {
        /// The element name.
        element: String,
        /// Index of the first row that is missing or incomplete.
        index: u64,
        /// The declared row count.
        count: u64,
    },
    /// A list length is negative.
    #[error("element '{element}' row {index}: list '{property}' has invalid length {value}")]
    BadListLength {
        /// The element name.
        element: String,
        /// The row index.
        index: u64,
        /// The list property.
        property: String,
        /// The length found.
        value: f64,
    },
    /// An ASCII token is not a number of the declared type.
    #[error("line {line}: '{token}' is not a valid {type_name} for property '{property}'")]
    BadAsciiNumber {
        /// 1-based line number in the file.
        line: usize,
        /// The offending token (lossy UTF-8, at most 40 characters).
        token: String,
        /// The declared type.
        type_name: &'static str,
        /// The property name.
        property: String,
    },
    /// An ASCII row has too few or too many values.
    #[error("line {line}: element '{element}' row {index} has {found} values but needs {expected}")]
    AsciiRowLength {
        /// 1-based line number in the file.
        line: usize,
        /// The element name.
        element: String,
        /// The row index.
        index: u64,
        /// Values needed (a lower bound when a list length is itself missing).
        expected: usize,
        /// Values on the line.
        found: usize,
    },
    /// A label or building id is not a whole number in its range.
    #[error("vertex {index}: '{property}' = {value} is not an integer in {range}")]
    AttributeRange {
        /// The vertex index.
        index: u64,
        /// The property name.
        property: String,
        /// The value found.
        value: f64,
        /// The allowed range.
        range: &'static str,
    },
    /// A coordinate is NaN/infinite or too far from the origin for `f32`.
    #[error("vertex {index}: {axis} = {value} is not a finite coordinate near the origin")]
    BadCoordinate {
        /// The vertex index.
        index: u64,
        /// `x`, `y` or `z`.
        axis: &'static str,
        /// The value found.
        value: f64,
    },
    /// The origin (in a `comment skyground origin` line, or of a cloud to write) is not finite.
    #[error("origin {origin:?} is not finite")]
    NonFiniteOrigin {
        /// The origin.
        origin: [f64; 3],
    },
    /// Bytes remain after the last declared element.
    #[error("{bytes} bytes of data after the last element (header counts too small?)")]
    TrailingData {
        /// Number of unread bytes.
        bytes: usize,
    },
    /// The cloud to write is inconsistent.
    #[error("cannot write cloud: {0}")]
    InvalidCloud(#[from] CloudError),
}
