//! The merged cloud kept on disk as it grows: one LAZ batch of new voxel
//! points at a time, then a small state file naming how many batches,
//! points and scans are whole. Both are written atomically, so a mission
//! killed at any moment leaves every batch its state names intact, and the
//! next run (a respawned explorer, `demo --resume`, the report) reads them
//! back in the order they were merged.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::cloud::{Cloud, CloudIoError, class, read_cloud, write_cloud};
use crate::file::{self, FileError};

/// Name of the state file inside the store's folder.
pub const STATE_FILE: &str = "state.json";

/// Reading or writing the merge store failed.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// Creating the folder or writing the state failed.
    #[error(transparent)]
    File(#[from] FileError),
    /// A batch could not be written or read back.
    #[error(transparent)]
    Cloud(#[from] CloudIoError),
    /// The state file is not one this version writes.
    #[error("{}: not a merge store state ({reason})", path.display())]
    State {
        /// The state file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// The store was merged with another voxel than the one asked for.
    #[error("{}: merged with {stored} m voxels, asked to go on with {asked} m; use the same --merge-voxel or a new output folder", dir.display())]
    Voxel {
        /// The store's folder.
        dir: PathBuf,
        /// The voxel the store was made with, m.
        stored: f32,
        /// The voxel asked for now, m.
        asked: f32,
    },
    /// A batch holds another number of points than the state says.
    #[error("{}: {found} points where the state says {expected}", path.display())]
    Batch {
        /// The batch file.
        path: PathBuf,
        /// Points the state counts for it.
        expected: usize,
        /// Points read.
        found: usize,
    },
}

/// What the state file holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct State {
    format: String,
    voxel_m: f32,
    /// Points of each whole batch, in merge order.
    batches: Vec<usize>,
    /// Scans whose every point is in the batches.
    scans: usize,
}

const FORMAT: &str = "skyground-merge-1";

/// The merged points read back, and how many scans they hold.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Stored {
    /// Points in the map frame, in the order they were merged (after the
    /// ones the reader already had, see [`read_store`]).
    pub points: Vec<[f32; 3]>,
    /// Points the store holds in all.
    pub total: usize,
    /// Scans whose points are all in the store.
    pub scans: usize,
}

/// An append-only store of merged points in a folder of its own.
#[derive(Debug)]
pub struct MergeStore {
    dir: PathBuf,
    state: State,
}

impl MergeStore {
    /// Opens the store in `dir` (made if missing) and reads back what it
    /// holds; a store made with another voxel is refused.
    pub fn open(dir: &Path, voxel_m: f32) -> Result<(MergeStore, Stored), StoreError> {
        std::fs::create_dir_all(dir).map_err(|e| FileError::new(dir, e))?;
        let state = match read_state(dir)? {
            Some(s) if s.voxel_m != voxel_m => {
                return Err(StoreError::Voxel {
                    dir: dir.into(),
                    stored: s.voxel_m,
                    asked: voxel_m,
                });
            }
            Some(s) => s,
            None => State {
                format: FORMAT.into(),
                voxel_m,
                batches: Vec::new(),
                scans: 0,
            },
        };
        let stored = read_batches(dir, &state, 0)?;
        Ok((
            MergeStore {
                dir: dir.into(),
                state,
            },
            stored,
        ))
    }

    /// Appends `new` points (those merged since the last call) as one batch
    /// and records that `scans` scans are now whole in the store.
    pub fn append(&mut self, new: &[[f32; 3]], scans: usize) -> Result<(), StoreError> {
        if new.is_empty() && scans == self.state.scans {
            return Ok(());
        }
        let mut next = self.state.clone();
        if !new.is_empty() {
            let c = batch_cloud(new.to_vec());
            write_cloud(&batch_path(&self.dir, next.batches.len()), &c)?;
            next.batches.push(new.len());
        }
        next.scans = scans;
        let json = serde_json::to_vec_pretty(&next).map_err(|e| StoreError::State {
            path: self.dir.join(STATE_FILE),
            reason: e.to_string(),
        })?;
        file::write(&self.dir.join(STATE_FILE), json)?;
        self.state = next;
        Ok(())
    }

    /// Points held.
    pub fn points(&self) -> usize {
        self.state.batches.iter().sum()
    }

    /// Scans whose points are all held.
    pub fn scans(&self) -> usize {
        self.state.scans
    }
}

/// A merge kept in its store: what was merged since the last flush goes
/// out as one batch, at most every `every_s` seconds unless forced.
#[derive(Debug)]
pub struct KeptMerge {
    store: MergeStore,
    /// How many of the merge's points are in the store.
    flushed: usize,
    last_s: f64,
    every_s: f64,
}

impl KeptMerge {
    /// Opens the store (see [`MergeStore::open`]) and what it holds, to be
    /// merged before any new scan; `merged_after_resume` follows.
    pub fn open(dir: &Path, voxel_m: f32, every_s: f64) -> Result<(KeptMerge, Stored), StoreError> {
        let (store, stored) = MergeStore::open(dir, voxel_m)?;
        let kept = KeptMerge {
            store,
            flushed: 0,
            last_s: f64::NEG_INFINITY,
            every_s,
        };
        Ok((kept, stored))
    }

    /// The merge now holds `len` points, all of them from the store.
    pub fn merged_after_resume(&mut self, len: usize) {
        self.flushed = len;
    }

    /// Writes the points of `merged` not yet stored when `every_s` has
    /// passed since the last write at `now_s` (or `force`); the number written.
    pub fn flush(
        &mut self,
        merged: &[[f32; 3]],
        scans: usize,
        now_s: f64,
        force: bool,
    ) -> Result<usize, StoreError> {
        let new = merged.get(self.flushed..).unwrap_or(&[]);
        if !(force || now_s - self.last_s >= self.every_s) {
            return Ok(0);
        }
        self.store.append(new, scans)?;
        self.flushed += new.len();
        self.last_s = now_s;
        Ok(new.len())
    }

    /// The store's counts: points and whole scans.
    pub fn stored(&self) -> (usize, usize) {
        (self.store.points(), self.store.scans())
    }
}

/// What the store in `dir` holds after its first `skip` points (a reader
/// that has those already; batches wholly before them are not read), or
/// `None` when there is none.
pub fn read_store(dir: &Path, skip: usize) -> Result<Option<Stored>, StoreError> {
    match read_state(dir)? {
        Some(s) => read_batches(dir, &s, skip).map(Some),
        None => Ok(None),
    }
}

/// A batch as written: merged points are building points.
fn batch_cloud(points: Vec<[f32; 3]>) -> Cloud {
    let mut c = Cloud::from_xyz(points);
    c.label = Some(vec![class::BUILDING; c.len()]);
    c
}

fn batch_path(dir: &Path, n: usize) -> PathBuf {
    dir.join(format!("batch-{n:06}.laz"))
}

fn read_state(dir: &Path) -> Result<Option<State>, StoreError> {
    let path = dir.join(STATE_FILE);
    if !path.exists() {
        return Ok(None);
    }
    let bad = |reason: String| StoreError::State {
        path: path.clone(),
        reason,
    };
    let s: State = serde_json::from_slice(&file::read(&path)?).map_err(|e| bad(e.to_string()))?;
    if s.format != FORMAT {
        return Err(bad(format!("format {:?}, expected {FORMAT:?}", s.format)));
    }
    Ok(Some(s))
}

fn read_batches(dir: &Path, s: &State, skip: usize) -> Result<Stored, StoreError> {
    let total = s.batches.iter().sum();
    let mut points = Vec::with_capacity(total - skip.min(total));
    let mut start = 0;
    for (n, &expected) in s.batches.iter().enumerate() {
        let end = start + expected;
        let first = skip.saturating_sub(start);
        start = end;
        if first >= expected {
            continue;
        }
        let path = batch_path(dir, n);
        let c = read_cloud(&path)?;
        if c.len() != expected {
            return Err(StoreError::Batch {
                path,
                expected,
                found: c.len(),
            });
        }
        let o = c.origin;
        points.extend(c.xyz[first..].iter().map(|p| {
            // Batches are written in the map frame; a reader that moved the
            // origin for precision is undone here.
            std::array::from_fn(|k| (f64::from(p[k]) + o[k]) as f32)
        }));
    }
    Ok(Stored {
        points,
        total,
        scans: s.scans,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("skyground-store-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn batches_read_back_in_order_with_their_scans() {
        let d = tmp("order");
        let (mut s, first) = MergeStore::open(&d, 0.05).unwrap();
        assert_eq!(first, Stored::default());
        s.append(&[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]], 3).unwrap();
        s.append(&[], 4).unwrap();
        s.append(&[[-7.25, 8.5, 0.125]], 6).unwrap();
        assert_eq!((s.points(), s.scans()), (3, 6));
        let back = read_store(&d, 0).unwrap().unwrap();
        assert_eq!(back.scans, 6);
        let want = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [-7.25, 8.5, 0.125]];
        assert_eq!(back.points.len(), 3);
        for (a, b) in back.points.iter().zip(want) {
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() < 2e-3, "{a:?} vs {b:?}");
            }
        }
        // Opened again (a respawned explorer), it goes on after what it holds.
        let (mut s2, again) = MergeStore::open(&d, 0.05).unwrap();
        assert_eq!(again, back);
        s2.append(&[[0.0; 3]], 7).unwrap();
        assert_eq!(read_store(&d, 0).unwrap().unwrap().points.len(), 4);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_reader_that_has_the_first_points_gets_the_rest() {
        let d = tmp("skip");
        let (mut s, _) = MergeStore::open(&d, 0.05).unwrap();
        s.append(&[[1.0; 3], [2.0; 3]], 2).unwrap();
        s.append(&[[3.0; 3]], 3).unwrap();
        for (skip, want) in [(0, 3), (1, 2), (2, 1), (3, 0), (9, 0)] {
            let back = read_store(&d, skip).unwrap().unwrap();
            assert_eq!(
                (back.points.len(), back.total, back.scans),
                (want, 3, 3),
                "skip {skip}"
            );
        }
        let tail = read_store(&d, 1).unwrap().unwrap().points;
        assert!(
            (tail[0][0] - 2.0).abs() < 2e-3 && (tail[1][0] - 3.0).abs() < 2e-3,
            "{tail:?}"
        );
        // A batch wholly skipped is not read: a damaged one there goes unnoticed.
        std::fs::write(batch_path(&d, 0), b"not a LAZ").unwrap();
        assert_eq!(read_store(&d, 2).unwrap().unwrap().points.len(), 1);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_kept_merge_writes_at_most_every_period_unless_forced() {
        let d = tmp("kept");
        let (mut k, _) = KeptMerge::open(&d, 0.05, 10.0).unwrap();
        let mut merged = vec![[1.0; 3]];
        assert_eq!(k.flush(&merged, 1, 0.0, false).unwrap(), 1);
        merged.push([2.0; 3]);
        assert_eq!(k.flush(&merged, 2, 5.0, false).unwrap(), 0, "too soon");
        assert_eq!(k.flush(&merged, 2, 5.0, true).unwrap(), 1, "forced");
        merged.push([3.0; 3]);
        assert_eq!(k.flush(&merged, 3, 15.1, false).unwrap(), 1);
        assert_eq!(k.stored(), (3, 3));
        let (mut k, back) = KeptMerge::open(&d, 0.05, 10.0).unwrap();
        assert_eq!((back.points.len(), back.scans), (3, 3));
        k.merged_after_resume(back.points.len());
        merged.push([4.0; 3]);
        assert_eq!(
            k.flush(&merged, 4, 0.0, true).unwrap(),
            1,
            "only the new point"
        );
        assert_eq!(read_store(&d, 0).unwrap().unwrap().points.len(), 4);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_batch_written_after_its_state_was_not_is_left_out() {
        let d = tmp("torn");
        let (mut s, _) = MergeStore::open(&d, 0.05).unwrap();
        s.append(&[[1.0; 3]], 1).unwrap();
        // As if killed between writing batch 1 and the state naming it.
        write_cloud(&batch_path(&d, 1), &batch_cloud(vec![[2.0; 3]; 5])).unwrap();
        let back = read_store(&d, 0).unwrap().unwrap();
        assert_eq!((back.points.len(), back.scans), (1, 1));
        // The next append overwrites the torn batch.
        let (mut s, _) = MergeStore::open(&d, 0.05).unwrap();
        s.append(&[[3.0; 3], [4.0; 3]], 2).unwrap();
        assert_eq!(read_store(&d, 0).unwrap().unwrap().points.len(), 3);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn another_voxel_a_bad_state_and_a_short_batch_are_refused() {
        let d = tmp("bad");
        let (mut s, _) = MergeStore::open(&d, 0.05).unwrap();
        s.append(&[[1.0; 3], [2.0; 3]], 1).unwrap();
        let e = MergeStore::open(&d, 0.02).unwrap_err().to_string();
        assert!(e.contains("0.05") && e.contains("0.02"), "{e}");
        write_cloud(&batch_path(&d, 0), &batch_cloud(vec![[2.0; 3]])).unwrap();
        let e = read_store(&d, 0).unwrap_err().to_string();
        assert!(e.contains("1 points where the state says 2"), "{e}");
        std::fs::write(d.join(STATE_FILE), b"{\"format\": 3}").unwrap();
        let e = read_store(&d, 0).unwrap_err().to_string();
        assert!(e.contains("not a merge store state"), "{e}");
        assert!(read_store(&d.join("none"), 0).unwrap().is_none());
        std::fs::remove_dir_all(&d).unwrap();
    }
}
