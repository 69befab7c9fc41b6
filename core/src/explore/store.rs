//! The merged cloud kept on disk as it grows: one LAZ batch of new voxel
//! points at a time, then a small state file naming how many batches,
//! points and scans (by id) are whole. Both are written atomically, so a
//! mission killed at any moment leaves every batch its state names intact,
//! and the next run (a respawned explorer, `demo --resume`, the report)
//! reads them back in the order they were merged. Between two batches every
//! scan merged is in the journal ([`super::journal`]) at once, and every
//! scan received, merged or not yet, in the inbox ([`super::inbox`]): the
//! store read back is the batches, then the journal's records, then the
//! inbox's scans neither holds (merged here as the explorer would).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::inbox;
use super::journal::{self, Journal, Journaled};
use super::voxel_merge::VoxelMerge;
use crate::cloud::{Cloud, CloudIoError, class, read_cloud, write_cloud};
use crate::file::{self, FileError};

/// A journal this large is written out as a batch before its period is up,
/// so it stays bounded whatever the scans' rate and size.
const JOURNAL_MAX_BYTES: u64 = 64 << 20;

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
    /// Their ids (header stamps, see `mission::scan_ids`), in merge order.
    #[serde(default)]
    scan_ids: Vec<u64>,
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
    /// Scans whose points are all in the batches.
    pub scans: usize,
    /// Their ids, in merge order.
    pub ids: Vec<u64>,
    /// What the journal holds beyond the batches (scans received after the
    /// last one): merged after `points`.
    pub journal: Journaled,
    /// The inbox's scans neither the batches nor the journal hold (received
    /// but not merged when the explorer stopped) and the new points they
    /// add to the merge: merged after the journal's.
    pub inbox: Journaled,
}

impl Stored {
    /// Every scan id held: the batches', the journal's, then the inbox's.
    pub fn all_ids(&self) -> impl Iterator<Item = u64> + '_ {
        self.ids
            .iter()
            .chain(&self.journal.ids)
            .chain(&self.inbox.ids)
            .copied()
    }
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
            None => {
                let s = State {
                    format: FORMAT.into(),
                    voxel_m,
                    batches: Vec::new(),
                    scans: 0,
                    scan_ids: Vec::new(),
                };
                // Its voxel is what a reader merges the inbox with.
                write_state(dir, &s)?;
                s
            }
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
    /// and records that the scans `ids` are now whole in the store too.
    pub fn append(&mut self, new: &[[f32; 3]], ids: &[u64]) -> Result<(), StoreError> {
        if new.is_empty() && ids.is_empty() {
            return Ok(());
        }
        let mut next = self.state.clone();
        if !new.is_empty() {
            let c = batch_cloud(new.to_vec());
            write_cloud(&batch_path(&self.dir, next.batches.len()), &c)?;
            next.batches.push(new.len());
        }
        next.scans += ids.len();
        next.scan_ids.extend_from_slice(ids);
        write_state(&self.dir, &next)?;
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

/// A merge kept in its store: each scan's new points go to the journal as
/// it is merged, and what was merged since the last batch goes out as one
/// batch at most every `every_s` seconds unless forced (or the journal grew
/// past [`JOURNAL_MAX_BYTES`]).
#[derive(Debug)]
pub struct KeptMerge {
    store: MergeStore,
    journal: Journal,
    /// How many of the merge's points and ids are in the batches.
    flushed: (usize, usize),
    /// How many are in the batches or the journal.
    journaled: (usize, usize),
    last_s: f64,
    every_s: f64,
}

impl KeptMerge {
    /// Opens the store (see [`MergeStore::open`]) and what it holds (the
    /// batches, the journal, then the inbox), to be merged before any new
    /// scan; [`KeptMerge::resumed`] follows.
    pub fn open(dir: &Path, voxel_m: f32, every_s: f64) -> Result<(KeptMerge, Stored), StoreError> {
        let (store, mut stored) = MergeStore::open(dir, voxel_m)?;
        stored.journal = unflushed(dir, &stored.ids)?;
        stored.inbox = unmerged(dir, voxel_m, &stored, None)?;
        let journal = Journal::open(dir, stored.journal.bytes)?;
        let kept = KeptMerge {
            store,
            journal,
            flushed: (0, 0),
            journaled: (0, 0),
            last_s: f64::NEG_INFINITY,
            every_s,
        };
        Ok((kept, stored))
    }

    /// The merge now holds `batches` (points, ids) from the store's batches
    /// and `all` with the journal's too.
    pub fn resumed(&mut self, batches: (usize, usize), all: (usize, usize)) {
        self.flushed = batches;
        self.journaled = all;
    }

    /// Journals what `merged` and `ids` hold beyond the journal, then writes
    /// a batch of what is not in one when `every_s` has passed since the last
    /// at `now_s` (or `force`, or the journal is full); the points batched.
    pub fn flush(
        &mut self,
        merged: &[[f32; 3]],
        ids: &[u64],
        now_s: f64,
        force: bool,
    ) -> Result<usize, StoreError> {
        let new_pts = merged.get(self.journaled.0..).unwrap_or(&[]);
        let new_ids = ids.get(self.journaled.1..).unwrap_or(&[]);
        if !(new_pts.is_empty() && new_ids.is_empty()) {
            self.journal.append(new_ids, new_pts)?;
            self.journaled = (merged.len(), ids.len());
        }
        let full = self.journal.bytes() > JOURNAL_MAX_BYTES;
        if !(force || full || now_s - self.last_s >= self.every_s) {
            return Ok(0);
        }
        let new = merged.get(self.flushed.0..).unwrap_or(&[]);
        let new_ids = ids.get(self.flushed.1..).unwrap_or(&[]);
        self.store.append(new, new_ids)?;
        self.flushed = (merged.len(), ids.len());
        self.last_s = now_s;
        // After the state: a kill in between leaves a journal the state ends with (see `unflushed`).
        self.journal.truncate()?;
        Ok(new.len())
    }

    /// The store's counts: points and whole scans in its batches.
    pub fn stored(&self) -> (usize, usize) {
        (self.store.points(), self.store.scans())
    }
}

/// What the store in `dir` holds after its first `skip` points (a reader
/// that has those already; batches wholly before them are not read), or
/// `None` when there is none.
pub fn read_store(dir: &Path, skip: usize) -> Result<Option<Stored>, StoreError> {
    let Some(state) = read_state(dir)? else {
        return Ok(None);
    };
    let mut stored = read_batches(dir, &state, skip)?;
    stored.journal = unflushed(dir, &stored.ids)?;
    let all = (skip > 0).then_some(&state);
    stored.inbox = unmerged(dir, state.voxel_m, &stored, all)?;
    Ok(Some(stored))
}

/// The inbox's scans `stored` does not hold, merged after its points as the
/// explorer would: their ids and the new points they add. `all` is the
/// state to read every batch by when `stored` skipped some.
fn unmerged(
    dir: &Path,
    voxel_m: f32,
    stored: &Stored,
    all: Option<&State>,
) -> Result<Journaled, StoreError> {
    let mut seen: std::collections::HashSet<u64> = stored
        .ids
        .iter()
        .chain(&stored.journal.ids)
        .copied()
        .collect();
    let scans: Vec<_> = inbox::read(dir)?
        .into_iter()
        .filter(|(id, _)| seen.insert(*id))
        .collect();
    let mut out = Journaled::default();
    if scans.is_empty() {
        return Ok(out);
    }
    let mut merge = VoxelMerge::new(voxel_m).map_err(|e| StoreError::State {
        path: dir.join(STATE_FILE),
        reason: e.to_string(),
    })?;
    let skipped = all.map(|s| read_batches(dir, s, 0)).transpose()?;
    let batches = skipped.as_ref().map_or(&stored.points, |s| &s.points);
    for p in batches.iter().chain(&stored.journal.points) {
        merge.add(*p);
    }
    for (id, points) in scans {
        out.ids.push(id);
        out.points
            .extend(points.into_iter().filter(|p| merge.add(*p)));
    }
    Ok(out)
}

/// The journal's records not yet in a batch: a journal whose ids end the
/// state's was written out before a kill came between the state and its
/// truncation (it is all or nothing: truncated after every batch).
fn unflushed(dir: &Path, batch_ids: &[u64]) -> Result<Journaled, StoreError> {
    let j = journal::read(dir)?;
    if !j.ids.is_empty() && batch_ids.ends_with(&j.ids) {
        return Ok(Journaled {
            bytes: 0,
            ..Journaled::default()
        });
    }
    Ok(j)
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

fn write_state(dir: &Path, s: &State) -> Result<(), StoreError> {
    let json = serde_json::to_vec_pretty(s).map_err(|e| StoreError::State {
        path: dir.join(STATE_FILE),
        reason: e.to_string(),
    })?;
    Ok(file::write(&dir.join(STATE_FILE), json)?)
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
        ids: s.scan_ids.clone(),
        journal: Journaled::default(),
        inbox: Journaled::default(),
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
        s.append(&[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]], &[1, 2, 3])
            .unwrap();
        s.append(&[], &[4]).unwrap();
        s.append(&[[-7.25, 8.5, 0.125]], &[5, 6]).unwrap();
        assert_eq!((s.points(), s.scans()), (3, 6));
        let back = read_store(&d, 0).unwrap().unwrap();
        assert_eq!((back.scans, back.ids.clone()), (6, vec![1, 2, 3, 4, 5, 6]));
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
        s2.append(&[[0.0; 3]], &[7]).unwrap();
        assert_eq!(read_store(&d, 0).unwrap().unwrap().points.len(), 4);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_reader_that_has_the_first_points_gets_the_rest() {
        let d = tmp("skip");
        let (mut s, _) = MergeStore::open(&d, 0.05).unwrap();
        s.append(&[[1.0; 3], [2.0; 3]], &[1, 2]).unwrap();
        s.append(&[[3.0; 3]], &[3]).unwrap();
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
    fn a_kept_merge_journals_every_scan_and_batches_at_most_every_period_unless_forced() {
        let d = tmp("kept");
        let (mut k, _) = KeptMerge::open(&d, 0.05, 10.0).unwrap();
        let (mut merged, mut ids) = (vec![[1.0; 3]], vec![11]);
        assert_eq!(k.flush(&merged, &ids, 0.0, false).unwrap(), 1);
        merged.push([2.0; 3]);
        ids.push(12);
        assert_eq!(k.flush(&merged, &ids, 5.0, false).unwrap(), 0, "too soon");
        // Not in a batch, but in the journal: read back all the same.
        let back = read_store(&d, 0).unwrap().unwrap();
        assert_eq!(
            (back.ids.clone(), back.journal.ids.clone()),
            (vec![11], vec![12])
        );
        assert_eq!(back.journal.points, [[2.0; 3]]);
        assert_eq!(k.flush(&merged, &ids, 5.0, true).unwrap(), 1, "forced");
        assert_eq!(
            read_store(&d, 0).unwrap().unwrap().journal,
            Journaled::default(),
            "truncated"
        );
        merged.push([3.0; 3]);
        ids.push(13);
        assert_eq!(k.flush(&merged, &ids, 15.1, false).unwrap(), 1);
        assert_eq!(k.stored(), (3, 3));
        ids.push(14); // a scan with no new point
        assert_eq!(k.flush(&merged, &ids, 16.0, false).unwrap(), 0);
        drop(k);
        // Killed there: a respawned explorer gets the batches, then the journal.
        let (mut k, back) = KeptMerge::open(&d, 0.05, 10.0).unwrap();
        assert_eq!((back.points.len(), back.scans), (3, 3));
        assert_eq!(back.all_ids().collect::<Vec<_>>(), [11, 12, 13, 14]);
        k.resumed((3, 3), (3, 4));
        merged.push([4.0; 3]);
        ids.push(15);
        assert_eq!(
            k.flush(&merged, &ids, 0.0, true).unwrap(),
            1,
            "only the new point"
        );
        let all = read_store(&d, 0).unwrap().unwrap();
        assert_eq!((all.points.len(), all.ids), (4, vec![11, 12, 13, 14, 15]));
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_journal_already_batched_when_killed_is_not_replayed() {
        let d = tmp("replayed");
        let (mut k, _) = KeptMerge::open(&d, 0.05, 10.0).unwrap();
        k.flush(&[[1.0; 3]], &[1], 0.0, false).unwrap();
        k.flush(&[[1.0; 3], [2.0; 3]], &[1, 2], 1.0, false).unwrap();
        let journal = std::fs::read(d.join(crate::explore::JOURNAL_FILE)).unwrap();
        k.flush(&[[1.0; 3], [2.0; 3]], &[1, 2], 2.0, true).unwrap();
        // As if killed between the state naming the batch and the truncation.
        std::fs::write(d.join(crate::explore::JOURNAL_FILE), journal).unwrap();
        let back = read_store(&d, 0).unwrap().unwrap();
        assert_eq!((back.ids, back.journal.ids), (vec![1, 2], vec![]));
        let (_, back) = KeptMerge::open(&d, 0.05, 10.0).unwrap();
        assert_eq!(back.all_ids().count(), 2);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn scans_in_the_inbox_the_merge_never_took_are_read_back_after_the_journal() {
        let d = tmp("inbox");
        let (mut k, _) = KeptMerge::open(&d, 1.0, 10.0).unwrap();
        let mut inbox = super::inbox::Inbox::open(&d, 1 << 20).unwrap();
        // Scans 1 and 2 taken and merged (1 in a batch, 2 in the journal).
        inbox.append(1, &[[0.5; 3], [10.5; 3]]).unwrap();
        k.flush(&[[0.5; 3], [10.5; 3]], &[1], 0.0, true).unwrap();
        inbox.append(2, &[[20.5; 3]]).unwrap();
        k.flush(&[[0.5; 3], [10.5; 3], [20.5; 3]], &[1, 2], 1.0, false)
            .unwrap();
        // Scans 3 and 4 taken but still queued when killed: 3 has one point
        // in a voxel merged already (left out, as the merge would) and one
        // new; 4 repeats 3's new voxel.
        inbox.append(3, &[[0.6; 3], [30.5; 3]]).unwrap();
        inbox.append(4, &[[30.6; 3], [40.5; 3]]).unwrap();
        inbox.append(2, &[[50.5; 3]]).unwrap(); // a repeat: left out
        drop((k, inbox));
        for skip in [0, 1, 2] {
            let back = read_store(&d, skip).unwrap().unwrap();
            assert_eq!(
                back.all_ids().collect::<Vec<_>>(),
                [1, 2, 3, 4],
                "skip {skip}"
            );
            assert_eq!(back.inbox.points, [[30.5; 3], [40.5; 3]], "skip {skip}");
        }
        // A respawned explorer gets them too; the next batch holds them.
        let (mut k, back) = KeptMerge::open(&d, 1.0, 10.0).unwrap();
        assert_eq!(back.inbox.ids, [3, 4]);
        k.resumed((2, 1), (3, 2));
        let all = [[0.5; 3], [10.5; 3], [20.5; 3], [30.5; 3], [40.5; 3]];
        assert_eq!(k.flush(&all, &[1, 2, 3, 4], 2.0, true).unwrap(), 3);
        let mut inbox = super::inbox::Inbox::open(&d, 1 << 20).unwrap();
        assert_eq!(inbox.prune(|id| id <= 4).unwrap(), 1);
        let back = read_store(&d, 0).unwrap().unwrap();
        assert_eq!(
            (back.ids, back.inbox.ids, back.points.len()),
            (vec![1, 2, 3, 4], vec![], 5)
        );
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_batch_written_after_its_state_was_not_is_left_out() {
        let d = tmp("torn");
        let (mut s, _) = MergeStore::open(&d, 0.05).unwrap();
        s.append(&[[1.0; 3]], &[1]).unwrap();
        // As if killed between writing batch 1 and the state naming it.
        write_cloud(&batch_path(&d, 1), &batch_cloud(vec![[2.0; 3]; 5])).unwrap();
        let back = read_store(&d, 0).unwrap().unwrap();
        assert_eq!((back.points.len(), back.scans), (1, 1));
        // The next append overwrites the torn batch.
        let (mut s, _) = MergeStore::open(&d, 0.05).unwrap();
        s.append(&[[3.0; 3], [4.0; 3]], &[2]).unwrap();
        assert_eq!(read_store(&d, 0).unwrap().unwrap().points.len(), 3);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn another_voxel_a_bad_state_and_a_short_batch_are_refused() {
        let d = tmp("bad");
        let (mut s, _) = MergeStore::open(&d, 0.05).unwrap();
        s.append(&[[1.0; 3], [2.0; 3]], &[1]).unwrap();
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
