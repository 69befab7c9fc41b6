//! PLY files: a strict reader (typed errors, no panics, fuzzed) and a writer.
//!
//! The reader accepts `ascii`, `binary_little_endian` and `binary_big_endian`
//! 1.0, any elements in any order, and keeps only the `vertex` element:
//! `x`, `y`, `z` (float or double), and optionally intensity (`intensity`,
//! `scalar_intensity`), label (`label`, `class`, `classification`,
//! `scalar_classification`, a whole number 0..=255 of any type) and building id
//! (`building`, `building_id`, a whole number fitting u32).
//!
//! Origin: a `comment skyground origin X Y Z` line (written by [`write_ply`])
//! gives it directly; otherwise it is [`crate::cloud::origin::local_origin`] of
//! the first vertex (0 per axis below 10 km, else floored to whole metres).
//!
//! Allocation is bounded by the input size, never by a header count alone.

mod ascii;
mod binary;
mod body;
mod error;
mod header;
mod rows;
mod scalar;
mod vertex;
mod write;

use std::io::{Read, Write};

pub use error::PlyError;
pub use header::PlyFormat;
use scalar::Scalar;
pub use write::write_ply_as;

/// The format-independent PLY reading blocks (header, scalar types, row
/// readers), shared with the mesh reader in [`crate::scene::ply_mesh`].
pub(crate) mod reader {
    pub(crate) use super::ascii::AsciiRows;
    pub(crate) use super::binary::BinaryRows;
    pub(crate) use super::header::{Element, Header, PlyFormat, PropertyKind, parse_header};
    pub(crate) use super::rows::{RowCtx, Rows, read_row};
}

use crate::cloud::Cloud;

/// Reads a whole PLY stream into a cloud.
pub fn read_ply<R: Read>(mut reader: R) -> Result<Cloud, PlyError> {
    let mut data = Vec::new();
    reader.read_to_end(&mut data)?;
    parse_ply(&data)
}

/// Decodes PLY bytes held in memory into a cloud.
pub fn parse_ply(data: &[u8]) -> Result<Cloud, PlyError> {
    let header = header::parse_header(data)?;
    let body = data.get(header.body_offset..).unwrap_or_default();
    body::read_body(&header, body)
}

/// Writes `cloud` as binary little-endian PLY (see [`write_ply_as`]).
pub fn write_ply<W: Write>(writer: W, cloud: &Cloud) -> Result<(), PlyError> {
    write_ply_as(writer, cloud, PlyFormat::BinaryLittleEndian)
}

#[cfg(test)]
mod tests;
