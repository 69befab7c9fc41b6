//! A DDS entity whose creation never returns ends the node with a clear error
//! and exit code [`EXIT_STUCK`], so a launcher's respawn starts it again.
//! RustDDS 0.15.1 can deadlock there when its discovery thread is busy
//! (docs/design.md, "DDS"); a stuck node would otherwise wait in silence.

use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError, Weak};
use std::time::{Duration, Instant};

/// How long creating one DDS entity may take before the node gives up. A
/// normal creation takes milliseconds, also on a loaded machine.
pub const CREATE_LIMIT: Duration = Duration::from_secs(20);

/// Overrides [`CREATE_LIMIT`] (seconds): tests of the respawn path need not
/// wait 20 s.
pub const LIMIT_ENV: &str = "SKYGROUND_CREATE_LIMIT_S";

/// `[NODE:]TEXT[@MARKER][,…]`: the creation whose name contains TEXT (in the
/// node named NODE) hangs as the RustDDS deadlock does; with MARKER only while
/// that file does not exist (the hang creates it), so a respawned node starts
/// cleanly. For tests of the respawn path; nothing else reads it.
pub const STALL_ENV: &str = "SKYGROUND_STALL_CREATION";

/// How long the [`CreationWatch::before_exit`] hooks may take: one that
/// waits on the stuck library must not keep the node from exiting.
const HOOKS_LIMIT: Duration = Duration::from_secs(10);

/// The exit code of a node that gave up (sysexits' EX_TEMPFAIL: try again).
pub const EXIT_STUCK: i32 = 75;

/// The creation now under way: since when, what, and its number.
type Slot = Option<(Instant, String, u64)>;

/// What runs before a stuck node exits: the last chance to close files.
type ExitHooks = Arc<Mutex<Vec<Box<dyn FnOnce() + Send>>>>;

/// Watches entity creations from a thread of its own; see [`Self::guard`].
pub struct CreationWatch {
    slot: Arc<Mutex<Slot>>,
    count: AtomicU64,
    hooks: ExitHooks,
    /// The [`STALL_ENV`] entries for this node.
    stalls: Vec<Stall>,
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
            hooks: ExitHooks::default(),
            stalls: Vec::new(),
        }
    }

    /// The production watch: on a stuck creation, says so on stderr as `node`,
    /// runs the [`before_exit`](Self::before_exit) hooks and exits the process
    /// with [`EXIT_STUCK`]. The limit is [`CREATE_LIMIT`] unless [`LIMIT_ENV`]
    /// sets another.
    pub fn exiting(node: &str) -> Self {
        use super::log::{Level, stderr_line};
        let name = node.to_string();
        let say = move |level, msg: &str| {
            stderr_line(level, &name, msg);
        };
        let (limit, bad_limit) = limit_from(std::env::var(LIMIT_ENV).ok().as_deref());
        if let Some(bad) = bad_limit {
            let default = CREATE_LIMIT.as_secs();
            say(
                Level::Warn,
                &format!("{LIMIT_ENV}={bad} is not a number of seconds > 0; using {default} s"),
            );
        }
        let hooks = ExitHooks::default();
        let to_run = hooks.clone();
        let watch = Self::start(limit, move |what, waited| {
            say(
                Level::Error,
                &format!(
                    "creating {what} has not returned in {:.0} s: the DDS library is deadlocked (a known RustDDS 0.15.1 fault, docs/design.md); exiting with code {EXIT_STUCK} so that a launcher's respawn starts this node again",
                    waited.as_secs_f64()
                ),
            );
            let (done, finished) = std::sync::mpsc::channel();
            let hooks = to_run.clone();
            std::thread::spawn(move || {
                run_hooks(&hooks);
                let _ = done.send(());
            });
            if finished.recv_timeout(HOOKS_LIMIT).is_err() {
                let secs = HOOKS_LIMIT.as_secs();
                say(
                    Level::Error,
                    &format!(
                        "the work before exiting has not ended in {secs} s; exiting without it"
                    ),
                );
            }
            std::process::exit(EXIT_STUCK);
        });
        let stalls = std::env::var(STALL_ENV)
            .map(|v| parse_stalls(&v))
            .unwrap_or_default()
            .into_iter()
            .filter(|s| s.node.as_deref().is_none_or(|n| n == node))
            .collect();
        Self {
            hooks,
            stalls,
            ..watch
        }
    }

    /// Runs `f` before the process exits on a stuck creation (not on a
    /// normal exit): a recorder closes its bag there.
    pub fn before_exit(&self, f: impl FnOnce() + Send + 'static) {
        self.hooks
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(Box::new(f));
    }

    /// Marks the creation of `what` as under way until the guard drops.
    pub fn guard(&self, what: &str) -> Armed<'_> {
        let n = self.count.fetch_add(1, Ordering::Relaxed) + 1;
        if let Ok(mut s) = self.slot.lock() {
            *s = Some((Instant::now(), what.to_string(), n));
        }
        if self.stalls.iter().any(|s| s.hangs(what)) {
            // The caller's thread stays here, as in the library's deadlock.
            loop {
                std::thread::sleep(Duration::from_secs(3600));
            }
        }
        Armed { watch: self }
    }
}

/// The limit [`LIMIT_ENV`]'s value gives, and the value when it is not a
/// number of seconds > 0.
fn limit_from(value: Option<&str>) -> (Duration, Option<String>) {
    let Some(v) = value else {
        return (CREATE_LIMIT, None);
    };
    let limit = v.trim().parse::<f64>().ok().filter(|s| *s > 0.0);
    match limit.and_then(|s| Duration::try_from_secs_f64(s).ok()) {
        Some(d) => (d, None),
        None => (CREATE_LIMIT, Some(v.to_string())),
    }
}

/// Runs the hooks once each, in the order they were added.
fn run_hooks(hooks: &ExitHooks) {
    let hooks = std::mem::take(&mut *hooks.lock().unwrap_or_else(PoisonError::into_inner));
    for f in hooks {
        f();
    }
}

/// One entry of [`STALL_ENV`]: the node, the text to match and the marker file.
#[derive(Debug, PartialEq)]
struct Stall {
    node: Option<String>,
    text: String,
    marker: Option<PathBuf>,
}

fn parse_stalls(value: &str) -> Vec<Stall> {
    value
        .split(',')
        .filter(|e| !e.trim().is_empty())
        .map(|e| {
            let (what, marker) = match e.rsplit_once('@') {
                Some((what, marker)) => (what, Some(PathBuf::from(marker))),
                None => (e, None),
            };
            let (node, text) = match what.split_once(':') {
                Some((node, text)) => (Some(node.to_string()), text),
                None => (None, what),
            };
            Stall {
                node,
                text: text.to_string(),
                marker,
            }
        })
        .collect()
}

impl Stall {
    /// Whether creating `what` hangs: its text matches and, with a marker,
    /// this is the first to create the marker file (of the processes sharing
    /// it, one hangs).
    fn hangs(&self, what: &str) -> bool {
        what.contains(&self.text)
            && self.marker.as_ref().is_none_or(|m| {
                std::fs::OpenOptions::new()
                    .write(true)
                    .create_new(true)
                    .open(m)
                    .is_ok()
            })
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

    #[test]
    fn exit_hooks_run_once_in_order() {
        let watch = CreationWatch::start(Duration::from_secs(60), |_, _| {});
        let ran = Arc::new(Mutex::new(Vec::new()));
        for i in 0..3 {
            let ran = ran.clone();
            watch.before_exit(move || ran.lock().unwrap().push(i));
        }
        run_hooks(&watch.hooks);
        run_hooks(&watch.hooks);
        assert_eq!(*ran.lock().unwrap(), [0, 1, 2]);
    }

    #[test]
    fn the_limit_comes_from_the_environment_and_a_bad_value_is_named() {
        assert_eq!(limit_from(None), (CREATE_LIMIT, None));
        assert_eq!(limit_from(Some("2.5")), (Duration::from_millis(2500), None));
        for bad in ["0", "-3", "soon", "NaN", "inf", "1e300"] {
            assert_eq!(limit_from(Some(bad)), (CREATE_LIMIT, Some(bad.to_string())));
        }
    }

    #[test]
    fn stall_entries_name_a_text_and_maybe_a_marker() {
        assert_eq!(
            parse_stalls("publisher on /state_estimation@/tmp/a,rec:subscription to /x"),
            [
                Stall {
                    node: None,
                    text: "publisher on /state_estimation".into(),
                    marker: Some("/tmp/a".into())
                },
                Stall {
                    node: Some("rec".into()),
                    text: "subscription to /x".into(),
                    marker: None
                },
            ]
        );
        assert!(parse_stalls("").is_empty());
    }
}
