//! Sanity checks on a LAS header before the `las` crate trusts its counts.
//!
//! The `las` crate computes the end of the point data as `offset + count ×
//! record_len` (which can overflow) and allocates an extended VLR's declared
//! length. We check both against the real stream length first, so a corrupt
//! header gives an error instead of a panic or an absurd allocation.

use std::io::{Read, Seek, SeekFrom};

use super::LasError;

/// Bytes of the LAS 1.4 header that hold every field we check.
const HEADER_LEN: usize = 255;
/// Size of an extended VLR's header.
const EVLR_HEADER_LEN: u64 = 60;

/// What the checks learned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Preflight {
    /// How many points to pre-allocate for (the checked count when uncompressed).
    pub capacity: u64,
}

/// Checks the header at the start of `source`, then seeks back to the start.
///
/// Streams that are not LAS at all pass; the `las` crate reports those.
pub fn check<R: Read + Seek>(source: &mut R) -> Result<Preflight, LasError> {
    let file_len = source.seek(SeekFrom::End(0))?;
    source.seek(SeekFrom::Start(0))?;
    let mut head = Vec::with_capacity(HEADER_LEN);
    source
        .by_ref()
        .take(HEADER_LEN as u64)
        .read_to_end(&mut head)?;
    source.seek(SeekFrom::Start(0))?;
    let field = Fields(&head);
    let (Some(b"LASF"), Some(minor), Some(offset), Some(format), Some(record_len), Some(legacy)) = (
        head.get(..4),
        field.u8(25),
        field.u32(96),
        field.u8(104),
        field.u16(105),
        field.u32(107),
    ) else {
        return Ok(Preflight { capacity: 0 });
    };
    let large = if minor >= 4 { field.u64(247) } else { None };
    let count = match (legacy, large) {
        (0, Some(n)) => n,
        (n, _) => u64::from(n),
    };
    let end = count
        .checked_mul(u64::from(record_len))
        .and_then(|n| n.checked_add(u64::from(offset)))
        .ok_or(LasError::ImplausibleCount { count, record_len })?;
    let compressed = format & 0x80 != 0;
    if !compressed && end > file_len {
        let available = file_len.saturating_sub(u64::from(offset)) / u64::from(record_len.max(1));
        return Err(LasError::Truncated { count, available });
    }
    if minor >= 4
        && let (Some(start), Some(n)) = (field.u64(235), field.u32(243))
        && start > 0
        && n > 0
    {
        check_evlr(source, start, file_len)?;
    }
    let capacity = if compressed {
        count.min(file_len)
    } else {
        count
    };
    Ok(Preflight { capacity })
}

/// Checks that the first extended VLR (the only one the `las` crate reads) fits.
fn check_evlr<R: Read + Seek>(source: &mut R, start: u64, file_len: u64) -> Result<(), LasError> {
    let bad = LasError::BadEvlr { start, file_len };
    if start
        .checked_add(EVLR_HEADER_LEN)
        .is_none_or(|e| e > file_len)
    {
        return Err(bad);
    }
    source.seek(SeekFrom::Start(start + 20))?;
    let mut len = [0u8; 8];
    source.read_exact(&mut len)?;
    source.seek(SeekFrom::Start(0))?;
    let end = (start + EVLR_HEADER_LEN).checked_add(u64::from_le_bytes(len));
    if end.is_none_or(|e| e > file_len) {
        return Err(bad);
    }
    Ok(())
}

/// Little-endian fields of a header prefix; `None` past its end.
struct Fields<'a>(&'a [u8]);

impl Fields<'_> {
    fn bytes<const N: usize>(&self, at: usize) -> Option<[u8; N]> {
        self.0.get(at..at + N)?.try_into().ok()
    }
    fn u8(&self, at: usize) -> Option<u8> {
        self.0.get(at).copied()
    }
    fn u16(&self, at: usize) -> Option<u16> {
        self.bytes(at).map(u16::from_le_bytes)
    }
    fn u32(&self, at: usize) -> Option<u32> {
        self.bytes(at).map(u32::from_le_bytes)
    }
    fn u64(&self, at: usize) -> Option<u64> {
        self.bytes(at).map(u64::from_le_bytes)
    }
}
