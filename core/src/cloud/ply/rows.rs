//! Walking the rows of a PLY body, independent of its encoding.

use super::header::{Element, PropertyKind};
use super::{PlyError, Scalar};

/// The row being read, for error messages.
#[derive(Debug, Clone, Copy)]
pub struct RowCtx<'e> {
    /// The element the row belongs to.
    pub element: &'e Element,
    /// The row index within the element.
    pub index: u64,
}

impl RowCtx<'_> {
    /// The error for a row the body ends in the middle of (or before).
    pub fn truncated(&self) -> PlyError {
        PlyError::Truncated {
            element: self.element.name.clone(),
            index: self.index,
            count: self.element.count,
        }
    }

    /// The error for a negative list length.
    pub fn bad_list_length(&self, property: &str, value: f64) -> PlyError {
        PlyError::BadListLength {
            element: self.element.name.clone(),
            index: self.index,
            property: property.into(),
            value,
        }
    }
}

/// A PLY body in one encoding, read row by row, property by property.
pub trait Rows {
    /// Upper bound on how many rows of `element` the unread data can hold.
    fn max_rows(&self, element: &Element) -> u64;

    /// Starts a row.
    fn begin(&mut self, ctx: RowCtx<'_>) -> Result<(), PlyError>;

    /// Reads one scalar value of the current row.
    fn scalar(&mut self, ctx: RowCtx<'_>, ty: Scalar, property: &str) -> Result<f64, PlyError>;

    /// Reads one list value of the current row, appending its items to `out`
    /// (`None`: reads past it).
    fn list(
        &mut self,
        ctx: RowCtx<'_>,
        count: Scalar,
        item: Scalar,
        property: &str,
        out: Option<&mut Vec<f64>>,
    ) -> Result<(), PlyError>;

    /// The 1-based file line of the current row, for encodings that have lines.
    fn line(&self) -> Option<usize> {
        None
    }

    /// Ends a row.
    fn end(&mut self, ctx: RowCtx<'_>) -> Result<(), PlyError>;

    /// Checks that nothing but whitespace (ASCII) or nothing at all (binary) is left.
    fn finish(&self) -> Result<(), PlyError>;

    /// Reads past every row of an element whose values we do not keep.
    fn skip_element(&mut self, element: &Element) -> Result<(), PlyError> {
        skip_rows(self, element)
    }
}

/// Reads row `ctx` property by property, handing each property's index and
/// values to `take`: a scalar's one value, or a list's items when `items`
/// is given to collect them in (without it, lists are read past unseen).
pub fn read_row<R: Rows + ?Sized>(
    rows: &mut R,
    ctx: RowCtx<'_>,
    mut items: Option<&mut Vec<f64>>,
    mut take: impl FnMut(usize, &[f64]),
) -> Result<(), PlyError> {
    rows.begin(ctx)?;
    for (k, p) in ctx.element.properties.iter().enumerate() {
        match (p.kind, items.as_deref_mut()) {
            (PropertyKind::Scalar(ty), _) => take(k, &[rows.scalar(ctx, ty, &p.name)?]),
            (PropertyKind::List { count, item }, Some(out)) => {
                out.clear();
                rows.list(ctx, count, item, &p.name, Some(&mut *out))?;
                take(k, out);
            }
            (PropertyKind::List { count, item }, None) => {
                rows.list(ctx, count, item, &p.name, None)?;
            }
        }
    }
    rows.end(ctx)
}

/// Reads past every row of `element`, value by value.
pub fn skip_rows<R: Rows + ?Sized>(rows: &mut R, element: &Element) -> Result<(), PlyError> {
    if element.properties.is_empty() {
        return Ok(());
    }
    for index in 0..element.count {
        read_row(rows, RowCtx { element, index }, None, |_, _| {})?;
    }
    Ok(())
}

/// The length in a list's prefix, rejecting negative values.
pub fn list_length(ctx: RowCtx<'_>, property: &str, value: f64) -> Result<u64, PlyError> {
    if value < 0.0 {
        return Err(ctx.bad_list_length(property, value));
    }
    // Integer list-length types decode to whole f64 values below 2^32.
    Ok(value as u64)
}
