//! Ending a `las::Writer` without its `Drop`.
//!
//! The `las` crate closes a writer left open in `Drop` and panics when that
//! fails (a header it cannot write, an I/O error): a panic reachable from a
//! file's content. Every writer here is closed explicitly instead, and one
//! whose writing or closing failed is forgotten: its buffer and file handle
//! go with the failed command, whose caller removes the half-written file.

use std::io::{Seek, Write};

use ::las::Writer;

use super::LasError;

/// Closes `writer` after `written` (the points went in) and returns its
/// sink at the start; on any error the writer is forgotten, never dropped.
pub(super) fn finish<W: Write + Seek + Send + Sync + 'static>(
    mut writer: Writer<W>,
    written: Result<(), LasError>,
) -> Result<W, LasError> {
    match written.and_then(|()| writer.close().map_err(LasError::from)) {
        // Closed: `into_inner` only seeks, and its drop has nothing to do.
        Ok(()) => Ok(writer.into_inner()?),
        Err(e) => {
            std::mem::forget(writer);
            Err(e)
        }
    }
}
