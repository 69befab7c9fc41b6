//! Reading body values, ASCII or binary, one at a time.

use super::error::{PlyMeshError, PlyPlace};
use super::header::{Format, Scalar};

/// A cursor over the body that yields values as `f64` (exact for every PLY
/// integer type).
pub struct Body<'a> {
    data: &'a [u8],
    pos: usize,
    format: Format,
    line: usize,
    element: String,
    row: usize,
}

impl<'a> Body<'a> {
    /// A cursor over `data`, whose first line is `first_line` (ASCII).
    pub fn new(data: &'a [u8], format: Format, first_line: usize) -> Self {
        Self {
            data,
            pos: 0,
            format,
            line: first_line,
            element: String::new(),
            row: 0,
        }
    }

    /// Records which row is being read (for error messages).
    pub fn at_row(&mut self, element: &str, row: usize) {
        if self.element != element {
            self.element = element.to_string();
        }
        self.row = row;
    }

    /// Where the cursor is, for messages.
    pub fn place(&self) -> PlyPlace {
        match self.format {
            Format::Ascii => PlyPlace::Line(self.line),
            _ => PlyPlace::Row {
                element: self.element.clone(),
                row: self.row,
            },
        }
    }

    /// Reads one value of type `ty`.
    pub fn value(&mut self, ty: Scalar) -> Result<f64, PlyMeshError> {
        match self.format {
            Format::Ascii => self.ascii(ty),
            Format::LittleEndian => self.binary(ty, true),
            Format::BigEndian => self.binary(ty, false),
        }
    }

    fn ascii(&mut self, ty: Scalar) -> Result<f64, PlyMeshError> {
        while let Some(&b) = self.data.get(self.pos) {
            if !b.is_ascii_whitespace() {
                break;
            }
            if b == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        let start = self.pos;
        while self
            .data
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(PlyMeshError::Truncated { at: self.place() });
        }
        let token = String::from_utf8_lossy(&self.data[start..self.pos]);
        let bad = || PlyMeshError::BadValue {
            at: self.place(),
            token: token.to_string(),
            ty: ty.name(),
        };
        if ty.is_integer() {
            let v: i64 = token.parse().map_err(|_| bad())?;
            let (lo, hi) = int_range(ty);
            if v < lo || v > hi {
                return Err(bad());
            }
            Ok(v as f64)
        } else {
            token.parse::<f64>().map_err(|_| bad())
        }
    }

    fn binary(&mut self, ty: Scalar, little: bool) -> Result<f64, PlyMeshError> {
        let n = ty.size();
        let Some(bytes) = self.data.get(self.pos..self.pos + n) else {
            return Err(PlyMeshError::Truncated { at: self.place() });
        };
        self.pos += n;
        let mut b = [0u8; 8];
        b[..n].copy_from_slice(bytes);
        if !little {
            b[..n].reverse();
        }
        Ok(match ty {
            Scalar::I8 => f64::from(i8::from_le_bytes([b[0]])),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }
}

fn int_range(ty: Scalar) -> (i64, i64) {
    match ty {
        Scalar::I8 => (i8::MIN.into(), i8::MAX.into()),
        Scalar::U8 => (0, u8::MAX.into()),
        Scalar::I16 => (i16::MIN.into(), i16::MAX.into()),
        Scalar::U16 => (0, u16::MAX.into()),
        Scalar::I32 => (i32::MIN.into(), i32::MAX.into()),
        _ => (0, u32::MAX.into()),
    }
}
