//! Binary PLY bodies (little or big endian).

use super::header::Element;
use super::rows::{RowCtx, Rows, list_length, skip_rows};
use super::{PlyError, Scalar};

/// A binary body: values packed back to back, no separators.
#[derive(Debug)]
pub struct BinaryRows<'a> {
    data: &'a [u8],
    pos: usize,
    big_endian: bool,
}

impl<'a> BinaryRows<'a> {
    /// Reads `data` with the given byte order.
    pub fn new(data: &'a [u8], big_endian: bool) -> Self {
        Self {
            data,
            pos: 0,
            big_endian,
        }
    }

    fn remaining(&self) -> usize {
        self.data.len().saturating_sub(self.pos)
    }

    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let end = self.pos.checked_add(n)?;
        let bytes = self.data.get(self.pos..end)?;
        self.pos = end;
        Some(bytes)
    }

    /// Reads a list's length prefix and returns the bytes of its items.
    fn list_bytes(
        &mut self,
        ctx: RowCtx<'_>,
        count: Scalar,
        item: Scalar,
        property: &str,
    ) -> Result<&'a [u8], PlyError> {
        let len = list_length(ctx, property, self.scalar(ctx, count, property)?)?;
        let bytes = len
            .checked_mul(item.size() as u64)
            .and_then(|b| usize::try_from(b).ok())
            .ok_or_else(|| ctx.truncated())?;
        self.take(bytes).ok_or_else(|| ctx.truncated())
    }
}

impl Rows for BinaryRows<'_> {
    fn max_rows(&self, element: &Element) -> u64 {
        (self.remaining() as u64) / element.min_row_bytes().max(1)
    }

    fn begin(&mut self, _ctx: RowCtx<'_>) -> Result<(), PlyError> {
        Ok(())
    }

    fn scalar(&mut self, ctx: RowCtx<'_>, ty: Scalar, _property: &str) -> Result<f64, PlyError> {
        let big_endian = self.big_endian;
        self.take(ty.size())
            .and_then(|bytes| ty.decode(bytes, big_endian))
            .ok_or_else(|| ctx.truncated())
    }

    fn list(
        &mut self,
        ctx: RowCtx<'_>,
        count: Scalar,
        item: Scalar,
        property: &str,
        out: Option<&mut Vec<f64>>,
    ) -> Result<(), PlyError> {
        let big_endian = self.big_endian;
        let bytes = self.list_bytes(ctx, count, item, property)?;
        let Some(out) = out else { return Ok(()) };
        for chunk in bytes.chunks_exact(item.size()) {
            out.push(
                item.decode(chunk, big_endian)
                    .ok_or_else(|| ctx.truncated())?,
            );
        }
        Ok(())
    }

    fn end(&mut self, _ctx: RowCtx<'_>) -> Result<(), PlyError> {
        Ok(())
    }

    fn finish(&self) -> Result<(), PlyError> {
        match self.remaining() {
            0 => Ok(()),
            bytes => Err(PlyError::TrailingData { bytes }),
        }
    }

    fn skip_element(&mut self, element: &Element) -> Result<(), PlyError> {
        let Some(row) = element.fixed_row_bytes() else {
            return skip_rows(self, element);
        };
        let available = self.remaining() as u64;
        let needed = element.count.checked_mul(row);
        match needed.and_then(|n| usize::try_from(n).ok()) {
            Some(n) if n as u64 <= available => {
                self.pos += n;
                Ok(())
            }
            _ => Err(PlyError::Truncated {
                element: element.name.clone(),
                index: available / row.max(1),
                count: element.count,
            }),
        }
    }
}
