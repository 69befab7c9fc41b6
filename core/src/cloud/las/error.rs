//! Everything that can go wrong reading or writing LAS/LAZ.

use crate::cloud::CloudError;
use crate::crs::CrsError;

/// A LAS/LAZ file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum LasError {
    /// The `las` crate rejected the file (corrupt header, unsupported format, ...).
    #[error("{0}")]
    Las(#[from] ::las::Error),
    /// Reading, seeking or writing the underlying stream failed.
    #[error("I/O error: {0}")]
    Io(#[from] std::io::Error),
    /// The header's point count times record length overflows a file offset.
    #[error("header declares {count} points of {record_len} bytes: impossibly large")]
    ImplausibleCount {
        /// Declared number of points.
        count: u64,
        /// Bytes per point record.
        record_len: u16,
    },
    /// An uncompressed file is shorter than its header's point count needs.
    #[error("truncated point data: header declares {count} points but the file holds {available}")]
    Truncated {
        /// Declared number of points.
        count: u64,
        /// Whole points present in the file.
        available: u64,
    },
    /// The header's VLR count is more than the records before the point data.
    #[error(
        "header declares {declared} VLRs but only {fit} fit before the point data at byte {offset}: the header is corrupt"
    )]
    VlrCount {
        /// VLRs the header declares.
        declared: u32,
        /// Whole VLRs found before the point data.
        fit: u32,
        /// Offset to the point data.
        offset: u32,
    },
    /// The LAZ chunks cannot be found (the decoder would fail part way or panic).
    #[error("LAZ point data cannot be decoded: {0}")]
    LazChunks(String),
    /// An extended VLR lies (partly) past the end of the file.
    #[error("extended VLR at byte {start} runs past the end of the file ({file_len} bytes)")]
    BadEvlr {
        /// Byte offset of the EVLR.
        start: u64,
        /// File length in bytes.
        file_len: u64,
    },
    /// Decoding the point records failed part way.
    #[error("point data ends at point {index} of {count}: {source}")]
    Points {
        /// Points decoded before the failure.
        index: u64,
        /// Declared number of points.
        count: u64,
        /// The `las` crate's error.
        #[source]
        source: ::las::Error,
    },
    /// The decoder panicked (caught): the point data is malformed in a way
    /// the checks before decoding did not see.
    #[error("the LAS/LAZ decoder failed at point {index}: {message} (the point data is malformed)")]
    DecoderPanic {
        /// Points decoded before the failure.
        index: u64,
        /// The decoder's message.
        message: String,
    },
    /// A point's coordinate is NaN/infinite or too far from the origin for `f32`.
    #[error("point {index}: {axis} = {value} is not a finite coordinate near the origin")]
    BadCoordinate {
        /// Point index.
        index: u64,
        /// `x`, `y` or `z`.
        axis: &'static str,
        /// The coordinate.
        value: f64,
    },
    /// The file's CRS records cannot be used.
    #[error("{0}")]
    Crs(#[from] CrsError),
    /// The cloud to write is inconsistent.
    #[error("cannot write cloud: {0}")]
    InvalidCloud(#[from] CloudError),
    /// The cloud to write has a NaN or infinite origin.
    #[error("origin {origin:?} is not finite")]
    NonFiniteOrigin {
        /// The origin.
        origin: [f64; 3],
    },
    /// A local coordinate does not fit LAS's 32-bit millimetre integers.
    #[error(
        "point {index}: {axis} = {value} m from the origin does not fit LAS's 32-bit mm integers (±2147 km)"
    )]
    CoordinateRange {
        /// Point index.
        index: usize,
        /// `x`, `y` or `z`.
        axis: &'static str,
        /// The local coordinate.
        value: f32,
    },
    /// Relabelling was given no file to copy.
    #[error("no LAS/LAZ file to copy the points from")]
    NoSource,
    /// The classes do not match the points one to one.
    #[error("{labels} classes for {points} points")]
    LabelCount {
        /// Points in the files.
        points: u64,
        /// Classes given.
        labels: usize,
    },
    /// A later file's point format is not the first's.
    #[error(
        "file {source_index} (from 0) has point format {format}, the first {first}: tiles written as one file must share one"
    )]
    SourceFormat {
        /// Which file.
        source_index: usize,
        /// Its point format.
        format: u8,
        /// The first file's.
        first: u8,
    },
    /// Point formats 0–5 hold classes 0–31 only.
    #[error("class {class} does not fit point formats 0–5 (classes 0–31)")]
    LegacyClass {
        /// The class.
        class: u8,
    },
    /// An intensity cannot be stored as LAS's u16.
    #[error("point {index}: intensity {value} is outside LAS's 0..=65535")]
    IntensityRange {
        /// Point index.
        index: usize,
        /// The intensity.
        value: f32,
    },
}
