//! A DDS entity whose creation never returns ends the node with a clear error
//! and exit code [`EXIT_STUCK`], so a launcher's respawn starts it again.
//! RustDDS 0.15.1 can deadlock there when its discovery thread is busy
//! (docs/design.md, "DDS"); a stuck node would otherwise wait in silence.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Weak};
use std::time::{Duration, Instant};

/// How long creating one DDS entity may take before the node gives up. A
/// normal creation takes milliseconds, also on a loaded machine.
pub const CREATE_LIMIT: Duration = Duration::from_secs(20);

/// The exit code of a node that gave up (sysexits' EX_TEMPFAIL: try again).
pub const EXIT_STUCK: i32 = 75;

/// The creation now under way: since when, what, and its number.
type Slot = Option<(Instant, String, u64)>;

/// Watches entity creations from a thread of its own; see [`Self::guard`].
pub struct CreationWatch {
    slot: Arc<Mutex<Slot>>,
    count: AtomicU64,
}

/// Marks a creation under way until dropped.
pub struct Armed<'a> {
    watch: &'a CreationWatch,
}

impl CreationWatch {
    /// Starts the watching thread: `on_stuck(what, waited)` runs once for a
    /// creation that has not returned after `limit`. The thread ends with
    /// the watch.
    pub fn start(limit: Duration, on_stuck: impl Fn(&str, Duration) + Send + 'static) -> Self {
        let slot = Arc::new(Mutex::new(None));
        let seen: Weak<Mutex<Slot>> = Arc::downgrade(&slot);
        let poll = (limit / 10).clamp(Duration::from_millis(5), Duration::from_millis(500));
        std::thread::spawn(move || {
            let mut said = None;
            while let Some(slot) = seen.upgrade() {
                let stuck = slot.lock().ok().and_then(|s| {
                    s.as_ref()
                        .filter(|(t, _, n)| t.elapsed() >= limit && said != Some(*n))
                        .map(|(t, what, n)| (what.clone(), t.elapsed(), *n))
                });
                drop(slot);
                if let Some((what, waited, n)) = stuck {
                    said = Some(n);
                    on_stuck(&what, waited);
                }
                std::thread::sleep(poll);
            }
        });
        Self {
            slot,
            count: AtomicU64::new(0),
        }
    }

    /// The production watch: on a stuck creation, says so on stderr as `node`
    /// and exits the process with [`EXIT_STUCK`].
    pub fn exiting(node: &str) -> Self {
        let node = node.to_string();
        Self::start(CREATE_LIMIT, move |what, waited| {
            super::log::stderr_line(
                super::log::Level::Error,
                &node,
                &format!(
                    "creating {what} has not returned in {:.0} s: the DDS library is deadlocked (a known RustDDS 0.15.1 fault, docs/design.md); exiting with code {EXIT_STUCK} so that a launcher's respawn starts this node again",
                    waited.as_secs_f64()
                ),
            );
            std::process::exit(EXIT_STUCK);
        })
    }

    /// Marks the creation of `what` as under way until the guard drops.
    pub fn guard(&self, what: &str) -> Armed<'_> {
        let n = self.count.fetch_add(1, Ordering::Relaxed) + 1;
        if let Ok(mut s) = self.slot.lock() {
            *s = Some((Instant::now(), what.to_string(), n));
        }
        Armed { watch: self }
    }
}

impl Drop for Armed<'_> {
    fn drop(&mut self) {
        if let Ok(mut s) = self.watch.slot.lock() {
            *s = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_creation_that_does_not_return_is_said_once_and_a_quick_one_never() {
        let said = Arc::new(Mutex::new(Vec::<String>::new()));
        let log = said.clone();
        let limit = Duration::from_millis(60);
        let watch = CreationWatch::start(limit, move |what, waited| {
            assert!(waited >= limit);
            log.lock().unwrap().push(what.to_string());
        });
        for _ in 0..20 {
            let _quick = watch.guard("publisher on /quick");
        }
        std::thread::sleep(limit * 2);
        assert!(said.lock().unwrap().is_empty());
        {
            let _stuck = watch.guard("subscription to /local_path");
            std::thread::sleep(limit * 4);
        }
        assert_eq!(*said.lock().unwrap(), ["subscription to /local_path"]);
        // A later creation that also hangs is said too.
        {
            let _stuck = watch.guard("publisher on /clock");
            std::thread::sleep(limit * 3);
        }
        assert_eq!(said.lock().unwrap().len(), 2);
        assert_eq!(said.lock().unwrap()[1], "publisher on /clock");
    }
}
