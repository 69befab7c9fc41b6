//! The merge store's journal: what each received scan added to the merge
//! (its id and its new voxel points), appended to `journal.bin` as it comes,
//! so a SIGKILL between two batches loses no scan that reached the explorer.
//! A batch written truncates it. New points only, not the raw scan: replayed
//! in order into the merge they give the same merge, and they are what the
//! next batch holds, so the journal stays as small as the batch it becomes.
//!
//! A record, little-endian: `SGJ1`, u32 ids, u32 points, the ids (u64), the
//! points (3 × f32), then FNV-1a 64 of everything before it in the record. A
//! record cut short or damaged (a kill while writing) ends the replay there.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::file::{self, FileError};

/// Name of the journal inside the store's folder.
pub const JOURNAL_FILE: &str = "journal.bin";

const MAGIC: &[u8; 4] = b"SGJ1";

/// What the journal holds: scan ids and their new points, in the order received.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Journaled {
    /// Scan ids, in the order merged.
    pub ids: Vec<u64>,
    /// Points they added to the merge, in that order.
    pub points: Vec<[f32; 3]>,
    /// Bytes of whole records (a torn tail after them is ignored).
    pub bytes: u64,
}

/// FNV-1a 64: enough to tell a torn or overwritten record from a whole one.
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// One record's bytes.
pub fn encode(ids: &[u64], points: &[[f32; 3]]) -> Vec<u8> {
    let mut b = Vec::with_capacity(20 + 8 * ids.len() + 12 * points.len());
    b.extend_from_slice(MAGIC);
    b.extend_from_slice(&(ids.len() as u32).to_le_bytes());
    b.extend_from_slice(&(points.len() as u32).to_le_bytes());
    ids.iter()
        .for_each(|i| b.extend_from_slice(&i.to_le_bytes()));
    points
        .iter()
        .flatten()
        .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    let sum = fnv(&b);
    b.extend_from_slice(&sum.to_le_bytes());
    b
}

/// The whole records at the start of `bytes`; the first torn or damaged one ends them.
pub fn decode(bytes: &[u8]) -> Journaled {
    let mut out = Journaled::default();
    out.bytes = for_each_record(bytes, |ids, points| {
        out.ids.extend(ids);
        out.points.extend(points);
    });
    out
}

/// Each whole record at the start of `bytes` as (ids, points), in order;
/// the first torn or damaged one ends them. Returns the bytes they fill.
pub(crate) fn for_each_record(bytes: &[u8], mut each: impl FnMut(Vec<u64>, Vec<[f32; 3]>)) -> u64 {
    let mut at = 0usize;
    while let Some(len) = record_len(&bytes[at..]) {
        let r = &bytes[at..at + len];
        let (ni, np) = (u32_at(r, 4) as usize, u32_at(r, 8) as usize);
        let ids = r[12..12 + 8 * ni]
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap_or_default()));
        let pts = r[12 + 8 * ni..12 + 8 * ni + 12 * np]
            .chunks_exact(12)
            .map(|c| {
                std::array::from_fn(|k| {
                    f32::from_le_bytes(c[4 * k..4 * k + 4].try_into().unwrap_or_default())
                })
            });
        each(ids.collect(), pts.collect());
        at += len;
    }
    at as u64
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// The length of the whole, intact record at the start of `b`, if there is one.
fn record_len(b: &[u8]) -> Option<usize> {
    if b.len() < 12 || &b[..4] != MAGIC {
        return None;
    }
    let (ni, np) = (u32_at(b, 4) as usize, u32_at(b, 8) as usize);
    let body = 12usize
        .checked_add(ni.checked_mul(8)?)?
        .checked_add(np.checked_mul(12)?)?;
    let len = body.checked_add(8)?;
    if b.len() < len {
        return None;
    }
    let sum = u64::from_le_bytes(b[body..len].try_into().ok()?);
    (sum == fnv(&b[..body])).then_some(len)
}

/// What the journal in `dir` holds (nothing when there is none).
pub fn read(dir: &Path) -> Result<Journaled, FileError> {
    let path = dir.join(JOURNAL_FILE);
    if !path.exists() {
        return Ok(Journaled::default());
    }
    Ok(decode(&file::read(&path)?))
}

/// The journal open for appending.
#[derive(Debug)]
pub struct Journal {
    path: PathBuf,
    file: std::fs::File,
    bytes: u64,
}

impl Journal {
    /// Opens the journal in `dir`, keeping its first `whole` bytes (a torn
    /// tail is cut off, so the next record follows the last whole one).
    pub fn open(dir: &Path, whole: u64) -> Result<Journal, FileError> {
        let path = dir.join(JOURNAL_FILE);
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .map_err(|e| FileError::new(&path, e))?;
        file.set_len(whole).map_err(|e| FileError::new(&path, e))?;
        Ok(Journal {
            path,
            file,
            bytes: whole,
        })
    }

    /// Appends one record (one `write`: in the kernel's hands when it returns,
    /// so a killed process keeps it).
    pub fn append(&mut self, ids: &[u64], points: &[[f32; 3]]) -> Result<(), FileError> {
        let r = encode(ids, points);
        self.file
            .write_all(&r)
            .map_err(|e| FileError::new(&self.path, e))?;
        self.bytes += r.len() as u64;
        Ok(())
    }

    /// Empties it (its records are in a batch now).
    pub fn truncate(&mut self) -> Result<(), FileError> {
        self.file
            .set_len(0)
            .map_err(|e| FileError::new(&self.path, e))?;
        self.bytes = 0;
        Ok(())
    }

    /// Bytes it holds.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_read_back_and_a_torn_or_damaged_tail_is_dropped() {
        let mut b = encode(&[7], &[[1.0, 2.0, 3.0]]);
        b.extend(encode(&[8, 9], &[]));
        let whole = b.len();
        b.extend(encode(&[10], &[[4.0; 3], [5.0; 3]]));
        let j = decode(&b);
        assert_eq!(j.ids, [7, 8, 9, 10]);
        assert_eq!(j.points, [[1.0, 2.0, 3.0], [4.0; 3], [5.0; 3]]);
        assert_eq!(j.bytes, b.len() as u64);
        // Cut anywhere inside the last record: the first two stand.
        for cut in whole..b.len() {
            let j = decode(&b[..cut]);
            assert_eq!((j.ids.len(), j.bytes), (3, whole as u64), "cut at {cut}");
        }
        // One byte of the last record changed: its checksum refuses it.
        let mut bad = b.clone();
        bad[whole + 14] ^= 1;
        assert_eq!(decode(&bad).ids, [7, 8, 9]);
        // A length that overflows is no record, not a panic.
        let mut huge = MAGIC.to_vec();
        huge.extend([0xff; 8]);
        assert_eq!(decode(&huge), Journaled::default());
    }

    #[test]
    fn an_opened_journal_cuts_a_torn_tail_appends_and_truncates() {
        let d = std::env::temp_dir().join(format!("skyground-journal-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let mut j = Journal::open(&d, 0).unwrap();
        j.append(&[1], &[[1.0; 3]]).unwrap();
        let one = j.bytes();
        j.append(&[2], &[[2.0; 3]]).unwrap();
        drop(j);
        // As if killed while writing record 2.
        let path = d.join(JOURNAL_FILE);
        let all = std::fs::read(&path).unwrap();
        std::fs::write(&path, &all[..all.len() - 3]).unwrap();
        let back = read(&d).unwrap();
        assert_eq!((back.ids.clone(), back.bytes), (vec![1], one));
        let mut j = Journal::open(&d, back.bytes).unwrap();
        j.append(&[3], &[[3.0; 3]]).unwrap();
        assert_eq!(read(&d).unwrap().ids, [1, 3]);
        j.truncate().unwrap();
        j.append(&[4], &[]).unwrap();
        assert_eq!(read(&d).unwrap().ids, [4]);
        std::fs::remove_dir_all(&d).unwrap();
    }
}
