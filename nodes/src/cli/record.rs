//! `skyground record`: topics → a rosbag2-compatible MCAP file, valid even when
//! stopped by SIGINT/SIGTERM.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use tokio::sync::mpsc;

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

/// One message a tap handed over: channel, receive time, publish time, CDR.
type Received = (u16, u64, u64, Vec<u8>);

fn store(
    writer: &mut BagWriter,
    counts: &mut BTreeMap<u16, u64>,
    m: Received,
) -> Result<(), crate::bag::BagError> {
    let (ch, log_ns, pub_ns, cdr) = m;
    writer.write(ch, log_ns, pub_ns, &cdr)?;
    *counts.entry(ch).or_default() += 1;
    Ok(())
}

fn now_ns() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX))
}

/// Runs the recorder.
pub async fn run(rt: &mut NodeRuntime, a: RecordArgs) -> Result<(), RuntimeError> {
    let bag_err = |e: crate::bag::BagError| RuntimeError::Node(e.to_string());
    let mut writer = BagWriter::create(&a.output).map_err(bag_err)?;
    let mut pending: Vec<Pending> = a
        .topics
        .iter()
        .map(|t| {
            let (topic, type_name) = topic_and_type(t);
            Pending { topic, type_name }
        })
        .collect();
    let (tx, mut rx) = mpsc::channel::<Received>(256);
    let mut tasks = Vec::new();
    // Messages written per channel; `names` gives each channel's topic.
    let mut counts: BTreeMap<u16, u64> = BTreeMap::new();
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
            Some(m) = rx.recv() => store(&mut writer, &mut counts, m).map_err(bag_err)?,
            _ = tick.tick() => {
                if deadline.is_some_and(|d| Instant::now() > d) {
                    break;
                }
                let mut still = Vec::new();
                for p in pending.drain(..) {
                    let found = wait_for_topic(rt, &p.topic, Duration::ZERO).await;
                    let (info, q) = match (found, p.type_name.clone()) {
                        (Some(info), ty) => {
                            let q = qos_for(&info, 1000);
                            (TopicInfo { type_name: ty.unwrap_or(info.type_name.clone()), ..info }, q)
                        }
                        // No publisher yet, typed or not: the reader's QoS must
                        // follow the writer's (a reliable reader never matches a
                        // best-effort sensor stream), so wait for one.
                        (None, _) => {
                            still.push(p);
                            continue;
                        }
                    };
                    let mut sub = tap(rt, &p.topic, &info.type_name, q, false)?;
                    let ch = writer
                        .add_topic(&p.topic, &info.type_name, &TopicQos {
                            reliable: info.reliable,
                            transient_local: info.transient_local,
                            depth: 10,
                        })
                        .map_err(bag_err)?;
                    names.insert(ch, p.topic.clone());
                    counts.insert(ch, 0);
                    rt.log.info(&format!("recording {} ({})", p.topic, info.type_name));
                    let tx = tx.clone();
                    let log = rt.log.clone();
                    let topic = p.topic.clone();
                    let every = a.every.iter().find(|(t, _)| *t == p.topic).map_or(1, |(_, n)| *n);
                    tasks.push(tokio::spawn(async move {
                        let mut seen = 0u64;
                        while let Some(m) = sub.next().await {
                            match m {
                                Ok(m) => {
                                    seen += 1;
                                    if !(seen - 1).is_multiple_of(every) {
                                        continue;
                                    }
                                    let pub_ns = if m.publish_time_ns > 0 { m.publish_time_ns } else { now_ns() };
                                    if tx.send((ch, now_ns(), pub_ns, m.cdr)).await.is_err() {
                                        break;
                                    }
                                }
                                Err(e) => log.error(&format!("{topic}: {e}")),
                            }
                        }
                    }));
                }
                pending = still;
            }
        }
    }
    for t in &tasks {
        t.abort();
    }
    // Keep what the taps already handed over.
    while let Ok(m) = rx.try_recv() {
        store(&mut writer, &mut counts, m).map_err(bag_err)?;
    }
    writer.finish().map_err(bag_err)?;
    for p in &pending {
        rt.log
            .warn(&format!("{}: never discovered, not recorded", p.topic));
    }
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
