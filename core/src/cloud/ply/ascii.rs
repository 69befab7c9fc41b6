//! ASCII PLY bodies: one row per line, values separated by whitespace.

use super::header::Element;
use super::rows::{RowCtx, Rows, list_length};
use super::{PlyError, Scalar};

/// An ASCII body. Blank lines are ignored; every other line is exactly one row.
#[derive(Debug)]
pub struct AsciiRows<'a> {
    data: &'a [u8],
    pos: usize,
    /// 1-based file line number of the current row.
    line: usize,
    tokens: Vec<&'a [u8]>,
    next: usize,
    /// Values the current row needs (grows as list lengths are read).
    needed: usize,
}

impl<'a> AsciiRows<'a> {
    /// Reads `data`, whose first line is file line `header_lines + 1`.
    pub fn new(data: &'a [u8], header_lines: usize) -> Self {
        Self {
            data,
            pos: 0,
            line: header_lines,
            tokens: Vec::new(),
            next: 0,
            needed: 0,
        }
    }

    fn remaining(&self) -> &'a [u8] {
        self.data.get(self.pos..).unwrap_or_default()
    }

    /// Loads the next non-blank line into `tokens`; false at the end of the data.
    fn next_line(&mut self) -> bool {
        loop {
            let rest = self.remaining();
            if rest.is_empty() {
                return false;
            }
            let len = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
            let line = rest.get(..len).unwrap_or_default();
            self.pos += (len + 1).min(rest.len());
            self.line += 1;
            self.tokens.clear();
            self.tokens.extend(
                line.split(u8::is_ascii_whitespace)
                    .filter(|t| !t.is_empty()),
            );
            if !self.tokens.is_empty() {
                return true;
            }
        }
    }

    fn row_length_error(&self, ctx: RowCtx<'_>) -> PlyError {
        PlyError::AsciiRowLength {
            line: self.line,
            element: ctx.element.name.clone(),
            index: ctx.index,
            expected: self.needed,
            found: self.tokens.len(),
        }
    }
}

impl Rows for AsciiRows<'_> {
    fn max_rows(&self, element: &Element) -> u64 {
        // Each value takes at least one character plus a separator or newline.
        let min_row = 2 * element.properties.len().max(1) as u64 - 1;
        self.remaining().len() as u64 / min_row
    }

    fn begin(&mut self, ctx: RowCtx<'_>) -> Result<(), PlyError> {
        if !self.next_line() {
            return Err(ctx.truncated());
        }
        self.next = 0;
        self.needed = ctx.element.properties.len();
        Ok(())
    }

    fn scalar(&mut self, ctx: RowCtx<'_>, ty: Scalar, property: &str) -> Result<f64, PlyError> {
        let token = *self
            .tokens
            .get(self.next)
            .ok_or_else(|| self.row_length_error(ctx))?;
        self.next += 1;
        ty.parse(token).ok_or_else(|| PlyError::BadAsciiNumber {
            line: self.line,
            token: String::from_utf8_lossy(token).chars().take(40).collect(),
            type_name: ty.name(),
            property: property.into(),
        })
    }

    fn list(
        &mut self,
        ctx: RowCtx<'_>,
        count: Scalar,
        item: Scalar,
        property: &str,
        mut out: Option<&mut Vec<f64>>,
    ) -> Result<(), PlyError> {
        let len = list_length(ctx, property, self.scalar(ctx, count, property)?)?;
        let len = usize::try_from(len).unwrap_or(usize::MAX);
        self.needed = self.needed.saturating_add(len);
        if self.tokens.len().saturating_sub(self.next) < len {
            return Err(self.row_length_error(ctx));
        }
        for _ in 0..len {
            let value = self.scalar(ctx, item, property)?;
            if let Some(out) = out.as_deref_mut() {
                out.push(value);
            }
        }
        Ok(())
    }

    fn line(&self) -> Option<usize> {
        Some(self.line)
    }

    fn end(&mut self, ctx: RowCtx<'_>) -> Result<(), PlyError> {
        if self.next == self.tokens.len() {
            Ok(())
        } else {
            Err(self.row_length_error(ctx))
        }
    }

    fn finish(&self) -> Result<(), PlyError> {
        let rest = self.remaining();
        match rest.iter().position(|b| !b.is_ascii_whitespace()) {
            None => Ok(()),
            Some(first) => Err(PlyError::TrailingData {
                bytes: rest.len() - first,
            }),
        }
    }
}
