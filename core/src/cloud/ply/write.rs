//! Writing a [`Cloud`] as PLY: float x, y, z plus the attributes the cloud has.

use std::io::{BufWriter, Write};

use super::PlyError;
use super::header::{ORIGIN_COMMENT, PlyFormat};
use crate::cloud::Cloud;

/// Writes `cloud` in `format`.
///
/// Vertex properties: `float x, y, z` (local frame), then `float intensity`,
/// `uchar classification`, `uint building` when present. A non-zero origin is
/// stored as `comment skyground origin X Y Z`, which [`super::read_ply`] restores;
/// other tools see local coordinates.
pub fn write_ply_as<W: Write>(writer: W, cloud: &Cloud, format: PlyFormat) -> Result<(), PlyError> {
    cloud.validate()?;
    if !cloud.origin.iter().all(|v| v.is_finite()) {
        return Err(PlyError::NonFiniteOrigin {
            origin: cloud.origin,
        });
    }
    let mut w = BufWriter::new(writer);
    write_header(&mut w, cloud, format)?;
    let mut row = Vec::with_capacity(64);
    for (i, p) in cloud.xyz.iter().enumerate() {
        row.clear();
        let mut enc = Encoder {
            row: &mut row,
            format,
        };
        for v in p {
            enc.f32(*v);
        }
        if let Some(v) = cloud.intensity.as_ref().and_then(|c| c.get(i)) {
            enc.f32(*v);
        }
        if let Some(v) = cloud.label.as_ref().and_then(|c| c.get(i)) {
            enc.u8(*v);
        }
        if let Some(v) = cloud.building.as_ref().and_then(|c| c.get(i)) {
            enc.u32(*v);
        }
        if format == PlyFormat::Ascii {
            row.pop();
            row.push(b'\n');
        }
        w.write_all(&row)?;
    }
    w.flush()?;
    Ok(())
}

fn write_header<W: Write>(w: &mut W, cloud: &Cloud, format: PlyFormat) -> std::io::Result<()> {
    writeln!(w, "ply")?;
    writeln!(w, "format {} 1.0", format.keyword())?;
    writeln!(w, "comment written by skyground")?;
    if cloud.origin != [0.0; 3] {
        let [x, y, z] = cloud.origin;
        writeln!(w, "comment {ORIGIN_COMMENT} {x} {y} {z}")?;
    }
    writeln!(w, "element vertex {}", cloud.len())?;
    for axis in ["x", "y", "z"] {
        writeln!(w, "property float {axis}")?;
    }
    if cloud.intensity.is_some() {
        writeln!(w, "property float intensity")?;
    }
    if cloud.label.is_some() {
        writeln!(w, "property uchar classification")?;
    }
    if cloud.building.is_some() {
        writeln!(w, "property uint building")?;
    }
    writeln!(w, "end_header")
}

/// Appends values to one row in the chosen encoding.
struct Encoder<'r> {
    row: &'r mut Vec<u8>,
    format: PlyFormat,
}

macro_rules! encode {
    ($name:ident, $t:ty) => {
        fn $name(&mut self, v: $t) {
            match self.format {
                // Display prints the shortest text that parses back to the same value.
                PlyFormat::Ascii => self.row.extend_from_slice(format!("{v} ").as_bytes()),
                PlyFormat::BinaryLittleEndian => self.row.extend_from_slice(&v.to_le_bytes()),
                PlyFormat::BinaryBigEndian => self.row.extend_from_slice(&v.to_be_bytes()),
            }
        }
    };
}

impl Encoder<'_> {
    encode!(f32, f32);
    encode!(u8, u8);
    encode!(u32, u32);
}
