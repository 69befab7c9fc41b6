//! The explorer's merge kept on disk (`merge_store`): the batches and the
//! journal of what it merged ([`KeptMerge`]), and the inbox of every scan
//! the feed took from DDS before it waited in the explorer's queue
//! ([`Inbox`]; issue 50: a SIGKILL lost the queued ones), with
//! `received.txt`, the ids the feed took, one a line.

use std::path::Path;
use std::sync::{Arc, Mutex};

use skyground_core::explore::{INBOX_MAX_BYTES, Inbox, KeptMerge};
use skyground_core::mission::explorer::{ExplorerEvent, ExplorerMachine, merged_points};
use skyground_core::mission::scan_ids::SentLog;

use crate::runtime::{Logger, RuntimeError};

/// Name of the log of received ids inside the store's folder.
pub const RECEIVED_FILE: &str = "received.txt";

/// The inbox and the log of received ids, shared by the feed (which
/// appends) and the explorer's loop (which prunes after each batch).
#[derive(Clone)]
pub struct ScanInbox {
    inbox: Arc<Mutex<Inbox>>,
    received: Arc<SentLog>,
    log: Logger,
}

impl ScanInbox {
    /// Keeps `e` (a scan) on disk: its merged points in the inbox, then its
    /// id in `received.txt`; a failure is logged (the scan goes on in memory).
    pub fn take(&self, e: &ExplorerEvent, failures: &mut u64) {
        let ExplorerEvent::Scan { id, xyz, labels } = e else {
            return;
        };
        let points = merged_points(xyz, labels.as_deref());
        let kept = self.lock().append(*id, &points).map_err(|e| e.to_string());
        let logged = kept.and_then(|()| self.received.sent(*id).map_err(|e| e.to_string()));
        if let Err(e) = logged {
            // Every failure counted, the first and every 100th said (a full inbox fails for each scan).
            if failures.is_multiple_of(100) {
                self.log
                    .warn(&format!("scan inbox ({} failures): {e}", *failures + 1));
            }
            *failures += 1;
        }
    }

    /// After a batch: the inbox's segments whose scans `ex` merged go.
    fn prune(&self, ex: &ExplorerMachine) {
        if let Err(e) = self.lock().prune(|id| ex.has(id)) {
            self.log.warn(&format!("scan inbox not pruned: {e}"));
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Inbox> {
        // A panic elsewhere while holding it leaves whole records: go on.
        self.inbox.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// The merge store and its inbox.
pub struct ScanStore {
    merge: KeptMerge,
    inbox: ScanInbox,
}

impl ScanStore {
    /// The store in `dir` (flushed every `every_s`), its merge (batches,
    /// journal, then inbox) taken into `ex`; `None` when `dir` is "".
    pub fn open(
        log: &Logger,
        (dir, every_s): (&str, f64),
        ex: &mut ExplorerMachine,
    ) -> Result<Option<ScanStore>, RuntimeError> {
        if dir.is_empty() {
            return Ok(None);
        }
        let err = |e: String| RuntimeError::Node(format!("merge store: {e}"));
        let path = Path::new(dir);
        let (merge, stored) = ex
            .keep_merge_in(path, every_s)
            .map_err(|e| err(e.to_string()))?;
        let inbox = Inbox::open(path, INBOX_MAX_BYTES).map_err(|e| err(e.to_string()))?;
        let received = SentLog::open(&path.join(RECEIVED_FILE)).map_err(|e| err(e.to_string()))?;
        let (n, scans) = (ex.resampled().len(), ex.scans());
        log.info(&format!(
            "merge store {dir}: going on from {n} points, {scans} scans ({} not merged before, from the inbox)",
            stored.inbox.ids.len()
        ));
        let inbox = ScanInbox {
            inbox: Arc::new(Mutex::new(inbox)),
            received: Arc::new(received),
            log: log.clone(),
        };
        // Everything read back is in a batch now: the former run's segments go.
        inbox.prune(ex);
        Ok(Some(ScanStore { merge, inbox }))
    }

    /// The inbox, for the feed.
    pub fn inbox(&self) -> ScanInbox {
        self.inbox.clone()
    }

    /// Journals what `ex` merged since the last call and writes a batch
    /// when due (or `force`); after a batch, prunes the inbox.
    pub fn keep(&mut self, log: &Logger, ex: &ExplorerMachine, now_s: f64, force: bool) {
        let before = self.merge.stored().1;
        match ex.keep(&mut self.merge, now_s, force) {
            Err(e) => log.error(&format!("merge store (kept, tried again): {e}")),
            Ok(_) if self.merge.stored().1 != before => self.inbox.prune(ex),
            Ok(_) => {}
        }
    }

    /// At shutdown: the last batch written, the inbox pruned; the line to log.
    pub fn stop(&mut self, ex: &ExplorerMachine) -> String {
        let said = ex.stop(Some(&mut self.merge));
        self.inbox.prune(ex);
        said
    }
}
