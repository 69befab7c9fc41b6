//! The explorer's inbox: every scan DDS delivered, written to disk by the
//! task that takes it from DDS, before it waits in the queue for the
//! explorer's loop. A SIGKILL while the loop was busy (publishing a round's
//! merge) lost the scans in that queue: up to 218 of 441 (issue 50).
//!
//! One record per scan, in the journal's format ([`super::journal`]): its id
//! and the points the merge takes from it. Records go to segments
//! `inbox-NNNNNN.bin`, each by one `write` (no fsync: a killed process
//! keeps it, a power cut may tear the tail, which reading drops). At every
//! prune the segment being written is closed, and a closed one whose every
//! scan is in a batch is deleted: the inbox holds the scans of about two
//! batch periods, and never more than its bound. Read back (a respawned
//! explorer, `demo --resume`, the report), the scans the store does not
//! hold yet are merged after the journal's.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::journal::{encode, for_each_record};
use crate::file::{self, FileError};

/// Bytes the inbox holds at most: beyond, a scan stays in memory only
/// (about 8,000 scans of a 16-beam LiDAR's building points).
pub const INBOX_MAX_BYTES: u64 = 256 << 20;

const PREFIX: &str = "inbox-";
const SUFFIX: &str = ".bin";

/// Writing to the inbox failed.
#[derive(Debug, thiserror::Error)]
pub enum InboxError {
    /// Writing, reading or removing a segment failed.
    #[error(transparent)]
    File(#[from] FileError),
    /// The scan would take the inbox past its bound.
    #[error("{}: scan {id} not kept on disk: the inbox holds {held} bytes, its bound is {max} (is the explorer's loop stuck?)", dir.display())]
    Full {
        /// The inbox's folder.
        dir: PathBuf,
        /// The scan's id.
        id: u64,
        /// Bytes held.
        held: u64,
        /// The bound.
        max: u64,
    },
}

/// One segment: its number, the ids of its records, its size.
#[derive(Debug, Default)]
struct Segment {
    n: u32,
    ids: Vec<u64>,
    bytes: u64,
}

/// The inbox in a folder, open for appending.
#[derive(Debug)]
pub struct Inbox {
    dir: PathBuf,
    max_bytes: u64,
    /// Segments written before (by this inbox or a killed one), oldest first.
    closed: Vec<Segment>,
    current: Segment,
    /// The current segment's file, made at its first record.
    file: Option<std::fs::File>,
}

fn segment_path(dir: &Path, n: u32) -> PathBuf {
    dir.join(format!("{PREFIX}{n:06}{SUFFIX}"))
}

/// The numbers of the segments in `dir`, in order.
fn segments(dir: &Path) -> Result<Vec<u32>, FileError> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(FileError::new(dir, e)),
    };
    let mut ns: Vec<u32> = entries
        .filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            name.strip_prefix(PREFIX)?
                .strip_suffix(SUFFIX)?
                .parse()
                .ok()
        })
        .collect();
    ns.sort_unstable();
    Ok(ns)
}

/// A scan as the inbox keeps it: its id and the points the merge takes from it.
pub type InboxScan = (u64, Vec<[f32; 3]>);

/// Every whole record of the inbox in `dir`, oldest first (nothing when
/// there is none; a torn segment tail is dropped).
pub fn read(dir: &Path) -> Result<Vec<InboxScan>, FileError> {
    let mut out = Vec::new();
    for n in segments(dir)? {
        let bytes = file::read(&segment_path(dir, n))?;
        for_each_record(&bytes, |ids, points| {
            out.extend(ids.into_iter().map(|id| (id, points.clone())));
        });
    }
    Ok(out)
}

impl Inbox {
    /// Opens the inbox in `dir` (an existing folder), holding at most
    /// `max_bytes`; the segments a former run left stay until pruned.
    pub fn open(dir: &Path, max_bytes: u64) -> Result<Inbox, FileError> {
        let mut closed = Vec::new();
        for n in segments(dir)? {
            let bytes = file::read(&segment_path(dir, n))?;
            let mut s = Segment {
                n,
                ..Segment::default()
            };
            s.bytes = for_each_record(&bytes, |ids, _| s.ids.extend(ids));
            closed.push(s);
        }
        let next = closed.last().map_or(0, |s| s.n + 1);
        Ok(Inbox {
            dir: dir.into(),
            max_bytes,
            closed,
            current: Segment {
                n: next,
                ..Segment::default()
            },
            file: None,
        })
    }

    /// Appends the scan `id` with the points the merge takes from it.
    pub fn append(&mut self, id: u64, points: &[[f32; 3]]) -> Result<(), InboxError> {
        let r = encode(&[id], points);
        let held = self.bytes();
        if held + r.len() as u64 > self.max_bytes {
            return Err(InboxError::Full {
                dir: self.dir.clone(),
                id,
                held,
                max: self.max_bytes,
            });
        }
        let path = segment_path(&self.dir, self.current.n);
        if self.file.is_none() {
            let f = std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(&path)
                .map_err(|e| FileError::new(&path, e))?;
            self.file = Some(f);
        }
        if let Some(f) = self.file.as_mut() {
            f.write_all(&r).map_err(|e| FileError::new(&path, e))?;
        }
        self.current.ids.push(id);
        self.current.bytes += r.len() as u64;
        Ok(())
    }

    /// After a batch: closes the segment being written and deletes every
    /// closed one whose scans are all `held` (in a batch); the segments deleted.
    pub fn prune(&mut self, held: impl Fn(u64) -> bool) -> Result<usize, FileError> {
        if !self.current.ids.is_empty() {
            let next = Segment {
                n: self.current.n + 1,
                ..Segment::default()
            };
            self.closed.push(std::mem::replace(&mut self.current, next));
            self.file = None;
        }
        let before = self.closed.len();
        let mut kept = Vec::with_capacity(before);
        for s in std::mem::take(&mut self.closed) {
            if !s.ids.iter().all(|&id| held(id)) {
                kept.push(s);
                continue;
            }
            let path = segment_path(&self.dir, s.n);
            match std::fs::remove_file(&path) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    kept.push(s);
                    self.closed = kept;
                    return Err(FileError::new(&path, e));
                }
                _ => {}
            }
        }
        self.closed = kept;
        Ok(before - self.closed.len())
    }

    /// Bytes the inbox holds.
    pub fn bytes(&self) -> u64 {
        self.closed.iter().map(|s| s.bytes).sum::<u64>() + self.current.bytes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("skyground-inbox-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn ids(dir: &Path) -> Vec<u64> {
        read(dir).unwrap().into_iter().map(|(id, _)| id).collect()
    }

    #[test]
    fn scans_read_back_in_order_with_their_points_across_segments() {
        let d = tmp("order");
        let mut b = Inbox::open(&d, INBOX_MAX_BYTES).unwrap();
        assert!(read(&d).unwrap().is_empty(), "no segment before a record");
        b.append(1, &[[1.0, 2.0, 3.0]]).unwrap();
        b.append(2, &[]).unwrap();
        assert_eq!(b.prune(|_| false).unwrap(), 0, "nothing in a batch yet");
        b.append(3, &[[4.0; 3], [5.0; 3]]).unwrap();
        let back = read(&d).unwrap();
        assert_eq!(
            back,
            [
                (1, vec![[1.0, 2.0, 3.0]]),
                (2, vec![]),
                (3, vec![[4.0; 3], [5.0; 3]])
            ]
        );
        // A second inbox (a respawned explorer) goes on after them.
        drop(b);
        let mut b = Inbox::open(&d, INBOX_MAX_BYTES).unwrap();
        b.append(4, &[]).unwrap();
        assert_eq!(ids(&d), [1, 2, 3, 4]);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_segment_goes_once_every_scan_in_it_is_in_a_batch() {
        let d = tmp("prune");
        let mut b = Inbox::open(&d, INBOX_MAX_BYTES).unwrap();
        b.append(1, &[[1.0; 3]]).unwrap();
        b.append(2, &[[2.0; 3]]).unwrap();
        // Scan 1 batched, 2 still queued: the segment stays, closed.
        assert_eq!(b.prune(|id| id == 1).unwrap(), 0);
        b.append(3, &[[3.0; 3]]).unwrap();
        assert_eq!(ids(&d), [1, 2, 3]);
        // 1 and 2 batched: their segment goes, 3's stays.
        assert_eq!(b.prune(|id| id <= 2).unwrap(), 1);
        assert_eq!(ids(&d), [3]);
        let left = b.bytes();
        assert_eq!(b.prune(|_| true).unwrap(), 1);
        assert_eq!((ids(&d), b.bytes()), (vec![], 0));
        assert!(left > 0);
        // Segments a killed inbox left are pruned by the next one.
        b.append(4, &[]).unwrap();
        drop(b);
        let mut b = Inbox::open(&d, INBOX_MAX_BYTES).unwrap();
        assert!(b.bytes() > 0);
        assert_eq!(b.prune(|id| id == 4).unwrap(), 1);
        assert_eq!(segments(&d).unwrap(), Vec::<u32>::new());
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_torn_tail_is_dropped_and_a_full_inbox_refuses_the_scan() {
        let d = tmp("torn");
        let mut b = Inbox::open(&d, INBOX_MAX_BYTES).unwrap();
        b.append(1, &[[1.0; 3]]).unwrap();
        b.append(2, &[[2.0; 3]; 4]).unwrap();
        drop(b);
        // As if the power went while record 2 was written.
        let path = segment_path(&d, 0);
        let all = std::fs::read(&path).unwrap();
        for cut in [all.len() - 1, all.len() - 30, 30] {
            std::fs::write(&path, &all[..cut]).unwrap();
            let want: &[u64] = if cut > 30 { &[1] } else { &[] };
            assert_eq!(ids(&d), want, "cut at {cut}");
            assert_eq!(
                Inbox::open(&d, INBOX_MAX_BYTES).unwrap().closed[0].ids,
                want
            );
        }
        // Bounded: a scan past the bound is refused, the inbox as it was.
        let mut b = Inbox::open(&tmp("full"), 100).unwrap();
        b.append(7, &[[0.0; 3]; 4]).unwrap();
        let e = b.append(8, &[[0.0; 3]; 4]).unwrap_err();
        assert!(
            matches!(
                e,
                InboxError::Full {
                    id: 8,
                    max: 100,
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains("bound is 100"), "{e}");
        assert_eq!(ids(&b.dir), [7]);
        std::fs::remove_dir_all(&d).unwrap();
        std::fs::remove_dir_all(&b.dir).unwrap();
    }
}
