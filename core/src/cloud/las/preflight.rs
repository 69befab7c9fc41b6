//! Sanity checks on a LAS header before the `las` crate trusts its counts.
//!
//! The `las` crate computes the end of the point data as `offset + count ×
//! record_len` (which can overflow) and allocates an extended VLR's declared
//! length. We check both against the real stream length first, so a corrupt
//! header gives an error instead of a panic or an absurd allocation. The
//! VLRs the header counts must fit before the point data, and a LAZ file's
//! chunks must be findable: the `laz` crate panics on variable-size chunks
//! it has no table for.

use std::io::{Read, Seek, SeekFrom};

use ::laz::LazVlr;
use ::laz::laszip::ChunkTable;

use super::LasError;

/// Bytes of the LAS 1.4 header that hold every field we check.
const HEADER_LEN: usize = 255;
/// Size of an extended VLR's header.
const EVLR_HEADER_LEN: u64 = 60;
/// Size of a VLR's header.
const VLR_HEADER_LEN: u64 = 54;
/// The LASzip VLR: user id and record id.
const LASZIP: (&[u8], u16) = (b"laszip encoded", 22204);
/// The LASzip compressor type whose one chunk holds every point.
const POINT_WISE: u16 = 1;

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
    let laszip = walk_vlrs(source, &field, offset, file_len)?;
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
    if compressed && let Some(data) = laszip {
        check_chunk_count(source, offset, file_len)?;
        check_chunks(source, &data, offset, count)?;
    }
    let capacity = if compressed {
        count.min(file_len)
    } else {
        count
    };
    Ok(Preflight { capacity })
}

/// Walks the VLRs the header counts: each must fit before the point data.
/// Returns the LASzip VLR's data, if one is there.
fn walk_vlrs<R: Read + Seek>(
    source: &mut R,
    field: &Fields,
    offset: u32,
    file_len: u64,
) -> Result<Option<Vec<u8>>, LasError> {
    let (Some(header_size), Some(declared)) = (field.u16(94), field.u32(100)) else {
        return Ok(None);
    };
    let end = u64::from(offset).min(file_len);
    let mut at = u64::from(header_size);
    let mut laszip = None;
    for k in 0..declared {
        let bad = LasError::VlrCount {
            declared,
            fit: k,
            offset,
        };
        if at + VLR_HEADER_LEN > end {
            return Err(bad);
        }
        let mut head = [0u8; VLR_HEADER_LEN as usize];
        source.seek(SeekFrom::Start(at))?;
        source.read_exact(&mut head)?;
        let len = u64::from(u16::from_le_bytes([head[20], head[21]]));
        let data_at = at + VLR_HEADER_LEN;
        if data_at + len > end {
            return Err(bad);
        }
        let user = head[2..18].split(|&b| b == 0).next().unwrap_or_default();
        if (user, u16::from_le_bytes([head[18], head[19]])) == LASZIP {
            let mut data = vec![0u8; len as usize];
            source.read_exact(&mut data)?;
            laszip = Some(data);
        }
        at = data_at + len;
    }
    source.seek(SeekFrom::Start(0))?;
    Ok(laszip)
}

/// Checks that a LAZ file's chunks can be found: variable-size chunks need
/// a chunk table (the point-wise compressor has none), and the table must
/// hold every point the header counts.
fn check_chunks<R: Read + Seek>(
    source: &mut R,
    laszip: &[u8],
    offset: u32,
    count: u64,
) -> Result<(), LasError> {
    let bad = |why: String| LasError::LazChunks(why);
    let vlr = LazVlr::from_buffer(laszip).map_err(|e| bad(format!("LASzip record: {e}")))?;
    if vlr.items().is_empty() {
        // The laz crate needs one item to build its decompressor (it panics).
        return Err(bad("the LASzip record lists no compressed items".into()));
    }
    let compressor = laszip
        .get(..2)
        .map_or(0, |b| u16::from_le_bytes([b[0], b[1]]));
    if !vlr.uses_variable_size_chunks() {
        return Ok(());
    }
    if compressor == POINT_WISE {
        return Err(bad(
            "variable-size chunks with the point-wise compressor, which has no chunk table".into(),
        ));
    }
    source.seek(SeekFrom::Start(u64::from(offset)))?;
    let table = ChunkTable::read_from(&mut *source, &vlr);
    source.seek(SeekFrom::Start(0))?;
    // Layered chunks carry their own point counts, but the laz crate (0.13)
    // goes on reading from wherever its failed look for the table left the
    // file (`failed to fill whole buffer`): without a table, no compressor
    // can be read.
    let table = table.map_err(|e| {
        bad(format!(
            "variable-size chunks but no readable chunk table ({e})"
        ))
    })?;
    let held: u64 = table[..].iter().map(|c| c.point_count).sum();
    if held < count {
        return Err(bad(format!(
            "the chunk table holds {held} of the header's {count} points"
        )));
    }
    Ok(())
}

/// Checks that a LAZ chunk table does not count more chunks than the file
/// has bytes: the `laz` crate allocates the table from that count before it
/// reads an entry (a damaged count of 4e9 asks for 63 GB and aborts).
fn check_chunk_count<R: Read + Seek>(
    source: &mut R,
    offset: u32,
    file_len: u64,
) -> Result<(), LasError> {
    let mut read8 = |at: u64| -> Option<[u8; 8]> {
        let mut b = [0u8; 8];
        source.seek(SeekFrom::Start(at)).ok()?;
        source.read_exact(&mut b).ok()?;
        Some(b)
    };
    let mut table_at = read8(u64::from(offset)).map(i64::from_le_bytes);
    // -1: the writer put the table's offset in the file's last 8 bytes.
    if table_at == Some(-1) {
        table_at = read8(file_len.saturating_sub(8)).map(i64::from_le_bytes);
    }
    let chunks = table_at
        .and_then(|at| u64::try_from(at).ok())
        .filter(|&at| at > 0 && at.saturating_add(8) <= file_len)
        .and_then(&mut read8)
        .map(|b| u32::from_le_bytes([b[4], b[5], b[6], b[7]]));
    source.seek(SeekFrom::Start(0))?;
    match chunks {
        Some(n) if u64::from(n) > file_len => Err(LasError::LazChunks(format!(
            "the chunk table counts {n} chunks in a file of {file_len} bytes"
        ))),
        _ => Ok(()),
    }
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
