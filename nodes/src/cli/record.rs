//! `skyground record`: topics → a rosbag2-compatible MCAP file, valid even when
//! stopped by SIGINT/SIGTERM.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use tokio::task::JoinHandle;

use super::{qos_for, topic_and_type, wait_for_topic};
use crate::bag::{BagWriter, TopicQos};
use crate::runtime::{NodeRuntime, RuntimeError};
use crate::tap::{TopicInfo, tap};

/// What to record.
#[derive(Debug, Clone, clap::Args)]
pub struct RecordArgs {
    /// Output file (.mcap).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Stop after this many seconds (0: until SIGINT/SIGTERM).
    #[arg(long, default_value_t = 0.0)]
    pub duration: f64,
    /// Topics, each optionally with its type (/x:pkg/msg/Type, which wins over
    /// the discovered one); each is recorded from its first publisher's
    /// discovery on, with that publisher's reliability and durability.
    #[arg(required = true)]
    pub topics: Vec<String>,
    /// Keep one message in N of a topic (TOPIC=N, repeatable): dense sensor
    /// streams (a 10 Hz LiDAR is ~3 MB/s) would otherwise fill the disk.
    #[arg(long = "every", value_parser = parse_every)]
    pub every: Vec<(String, u64)>,
}

fn parse_every(s: &str) -> Result<(String, u64), String> {
    let (topic, n) = s
        .split_once('=')
        .ok_or_else(|| format!("`{s}`: expected TOPIC=N"))?;
    let n: u64 = n
        .parse()
        .ok()
        .filter(|&n| n >= 1)
        .ok_or_else(|| format!("`{s}`: N must be a whole number ≥ 1"))?;
    Ok((topic.to_string(), n))
}

struct Pending {
    topic: String,
    type_name: Option<String>,
}

/// The bag and what went into it, shared by the taps that write to it, the
/// loop that adds topics and the hook that closes it if the node must exit.
struct Recording {
    /// `None` once finished.
    writer: Option<BagWriter>,
    /// Messages written per channel.
    counts: BTreeMap<u16, u64>,
    /// The first write that failed; the recorder stops with it.
    failed: Option<crate::bag::BagError>,
}

type Shared = Arc<Mutex<Recording>>;

fn lock(r: &Shared) -> MutexGuard<'_, Recording> {
    r.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Writes one message a tap received; false once the bag is closed or failed.
fn store(r: &Shared, ch: u16, log_ns: u64, pub_ns: u64, cdr: &[u8]) -> bool {
    let mut r = lock(r);
    let Recording {
        writer,
        counts,
        failed,
    } = &mut *r;
    let Some(w) = writer.as_mut().filter(|_| failed.is_none()) else {
        return false;
    };
    match w.write(ch, log_ns, pub_ns, cdr) {
        Ok(()) => {
            *counts.entry(ch).or_default() += 1;
            true
        }
        Err(e) => {
            *failed = Some(e);
            false
        }
    }
}

/// Writes the bag's summary; `None` when it was closed already.
fn finish(r: &Shared) -> Option<Result<(), crate::bag::BagError>> {
    lock(r).writer.take().map(BagWriter::finish)
}

fn now_ns() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX))
}

fn bag_err(e: crate::bag::BagError) -> RuntimeError {
    RuntimeError::Node(e.to_string())
}

/// Subscribes to `p` once a publisher is discovered (its QoS decides the
/// reader's) and starts the task that writes its messages: the channel and
/// the task, or `None` while no publisher is known.
async fn start_topic(
    rt: &mut NodeRuntime,
    rec: &Shared,
    p: &Pending,
    every: u64,
) -> Result<Option<(u16, JoinHandle<()>)>, RuntimeError> {
    // No publisher yet, typed or not: the reader's QoS must follow the
    // writer's (a reliable reader never matches a best-effort sensor
    // stream), so wait for one.
    let Some(found) = wait_for_topic(rt, &p.topic, Duration::ZERO).await else {
        return Ok(None);
    };
    let q = qos_for(&found, 1000);
    let info = TopicInfo {
        type_name: p.type_name.clone().unwrap_or(found.type_name.clone()),
        ..found
    };
    let mut sub = tap(rt, &p.topic, &info.type_name, q, false)?;
    let ch = {
        let mut r = lock(rec);
        let ch = r
            .writer
            .as_mut()
            .ok_or_else(|| RuntimeError::Node("the bag was closed".into()))?
            .add_topic(
                &p.topic,
                &info.type_name,
                &TopicQos {
                    reliable: info.reliable,
                    transient_local: info.transient_local,
                    depth: 10,
                },
            )
            .map_err(bag_err)?;
        r.counts.insert(ch, 0);
        ch
    };
    rt.log
        .info(&format!("recording {} ({})", p.topic, info.type_name));
    let (rec, log, topic) = (rec.clone(), rt.log.clone(), p.topic.clone());
    let task = tokio::spawn(async move {
        let mut seen = 0u64;
        while let Some(m) = sub.next().await {
            match m {
                Ok(m) => {
                    seen += 1;
                    if !(seen - 1).is_multiple_of(every) {
                        continue;
                    }
                    let pub_ns = if m.publish_time_ns > 0 {
                        m.publish_time_ns
                    } else {
                        now_ns()
                    };
                    if !store(&rec, ch, now_ns(), pub_ns, &m.cdr) {
                        break;
                    }
                }
                Err(e) => log.error(&format!("{topic}: {e}")),
            }
        }
    });
    Ok(Some((ch, task)))
}

/// Stops the taps and writes the summary; a write that failed before is the
/// error (the summary of what came before it is still attempted).
fn close(rec: &Shared, tasks: &[JoinHandle<()>]) -> Result<(), RuntimeError> {
    for t in tasks {
        t.abort();
    }
    let failed = lock(rec).failed.take();
    let done = finish(rec);
    if let Some(e) = failed {
        return Err(bag_err(e));
    }
    done.unwrap_or(Ok(())).map_err(bag_err)
}

/// Runs the recorder.
pub async fn run(rt: &mut NodeRuntime, a: RecordArgs) -> Result<(), RuntimeError> {
    let rec: Shared = Arc::new(Mutex::new(Recording {
        writer: Some(BagWriter::create(&a.output).map_err(bag_err)?),
        counts: BTreeMap::new(),
        failed: None,
    }));
    {
        // A stuck DDS creation ends the process without unwinding: close the
        // bag first, with everything the taps wrote while it hung.
        let rec = rec.clone();
        let log = rt.log.stderr_only();
        rt.before_stuck_exit(move || match finish(&rec) {
            Some(Ok(())) => log.info("bag closed before exiting"),
            Some(Err(e)) => log.error(&format!("closing the bag before exiting: {e}")),
            None => {}
        });
    }
    let mut pending: Vec<Pending> = a
        .topics
        .iter()
        .map(|t| {
            let (topic, type_name) = topic_and_type(t);
            Pending { topic, type_name }
        })
        .collect();
    let mut tasks = Vec::new();
    // Each channel's topic.
    let mut names: BTreeMap<u16, String> = BTreeMap::new();
    let deadline = (a.duration > 0.0).then(|| Instant::now() + Duration::from_secs_f64(a.duration));
    let mut tick = tokio::time::interval(Duration::from_millis(100));
    rt.log.info(&format!(
        "recording {} topic(s) to {}",
        pending.len(),
        a.output.display()
    ));
    loop {
        tokio::select! {
            _ = rt.shutdown.wait() => break,
            _ = tick.tick() => {
                if lock(&rec).failed.is_some() || deadline.is_some_and(|d| Instant::now() > d) {
                    break;
                }
                let mut still = Vec::new();
                for p in pending.drain(..) {
                    let every = a.every.iter().find(|(t, _)| *t == p.topic).map_or(1, |(_, n)| *n);
                    match start_topic(rt, &rec, &p, every).await {
                        Ok(Some((ch, task))) => {
                            names.insert(ch, p.topic.clone());
                            tasks.push(task);
                        }
                        Ok(None) => still.push(p),
                        Err(e) => {
                            // What was recorded so far stays readable.
                            let _ = close(&rec, &tasks);
                            return Err(e);
                        }
                    }
                }
                pending = still;
            }
        }
    }
    close(&rec, &tasks)?;
    for p in &pending {
        rt.log
            .warn(&format!("{}: never discovered, not recorded", p.topic));
    }
    let counts = lock(&rec).counts.clone();
    let total: u64 = counts.values().sum();
    rt.log.info(&format!(
        "wrote {total} message(s) to {}: {}",
        a.output.display(),
        counts
            .iter()
            .map(|(ch, n)| format!("{} {n}", names.get(ch).map_or("?", String::as_str)))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bag::read_messages;

    #[test]
    fn the_shared_bag_counts_what_it_writes_and_takes_nothing_once_closed() {
        let path =
            std::env::temp_dir().join(format!("skyground-record-{}.mcap", std::process::id()));
        let mut writer = BagWriter::create(&path).expect("create");
        let qos = TopicQos {
            reliable: true,
            transient_local: false,
            depth: 10,
        };
        let ch = writer
            .add_topic("/odom", "nav_msgs/msg/Odometry", &qos)
            .expect("topic");
        let rec: Shared = Arc::new(Mutex::new(Recording {
            writer: Some(writer),
            counts: BTreeMap::new(),
            failed: None,
        }));
        let cdr = [0u8, 1, 0, 0, 7, 7, 7, 7];
        assert!(store(&rec, ch, 10, 10, &cdr));
        assert!(store(&rec, ch, 20, 20, &cdr));
        assert!(matches!(finish(&rec), Some(Ok(()))));
        // After the close (as by the stuck-exit hook) a tap's message is refused,
        // and a second close has nothing to do.
        assert!(!store(&rec, ch, 30, 30, &cdr));
        assert!(finish(&rec).is_none());
        assert_eq!(lock(&rec).counts.get(&ch), Some(&2));
        let read = read_messages(&path).expect("a closed bag reads whole");
        let _ = std::fs::remove_file(&path);
        assert_eq!(read.len(), 2);
        assert_eq!(read[1].cdr, cdr);
    }
}
