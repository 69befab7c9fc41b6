//! `skyground play BAG`: republishes a recorded bag with its timing, like
//! `ros2 bag play`, each topic with the QoS it was recorded with.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Duration;

use skyground_msgs::sensor_msgs::PointCloud2;

use crate::bag::{BagError, TopicQos, read_intact_messages, read_topic_qos};
use crate::runtime::{NodeRuntime, RuntimeError, qos};
use crate::tap::{Emit, emitter};
use crate::transport::{CloudPublisher, TransportConfig};

/// Options of `skyground play`.
#[derive(Debug, Clone, clap::Args)]
pub struct PlayArgs {
    /// The bag (.mcap).
    pub bag: PathBuf,
    /// Playback speed: 2 plays twice as fast; 0 sends everything at once.
    #[arg(long, default_value_t = 1.0)]
    pub rate: f64,
    /// Only these topics (default: all).
    #[arg(long, num_args = 1..)]
    pub topics: Vec<String>,
    /// Seconds to wait for subscribers before the first message.
    #[arg(long, default_value_t = 1.0)]
    pub delay: f64,
    /// Keep running after the last message (latched topics stay available).
    #[arg(long)]
    pub linger: bool,
}

enum Out {
    Cloud(Box<CloudPublisher>),
    Other(Box<dyn Emit>),
}

fn profile(q: TopicQos) -> ros2_client::QosProfile {
    match (q.reliable, q.transient_local) {
        (true, true) => qos::latched(q.depth.max(1)),
        (true, false) => qos::reliable(q.depth.max(1)),
        _ => qos::sensor(q.depth.max(1)),
    }
}

/// Plays the bag; returns the messages sent per topic.
pub async fn run(rt: &mut NodeRuntime, a: PlayArgs) -> Result<(), RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    if !(a.rate >= 0.0 && a.rate.is_finite()) {
        return Err(err(format!("--rate {} must be ≥ 0", a.rate)));
    }
    let messages = read_intact_messages(&a.bag).map_err(|e: BagError| err(e.to_string()))?;
    let qos_of = read_topic_qos(&a.bag).unwrap_or_default();
    let wanted = |t: &str| a.topics.is_empty() || a.topics.iter().any(|w| w == t);
    let mut outs: BTreeMap<String, Out> = BTreeMap::new();
    for m in messages.iter().filter(|m| wanted(&m.topic)) {
        if outs.contains_key(&m.topic) {
            continue;
        }
        let q = profile(qos_of.get(&m.topic).copied().unwrap_or_default());
        let out = if m.type_name == "sensor_msgs/msg/PointCloud2" {
            // Recorded clouds are tiles already: send each as it is, paced.
            let config = TransportConfig {
                tile_points: u32::MAX,
                ..TransportConfig::default()
            };
            Out::Cloud(Box::new(CloudPublisher::new(rt, &m.topic, q, config)?))
        } else {
            Out::Other(emitter(rt, &m.topic, &m.type_name, q)?)
        };
        outs.insert(m.topic.clone(), out);
    }
    rt.log.info(&format!(
        "playing {} messages on {} topics from {}",
        messages.iter().filter(|m| wanted(&m.topic)).count(),
        outs.len(),
        a.bag.display()
    ));
    tokio::time::sleep(Duration::from_secs_f64(a.delay.max(0.0))).await;
    let t0 = tokio::time::Instant::now();
    let first = messages.first().map_or(0, |m| m.log_time_ns);
    let mut sent: BTreeMap<&str, u64> = BTreeMap::new();
    let mut failed = 0u64;
    for m in messages.iter().filter(|m| wanted(&m.topic)) {
        if rt.shutdown.requested() {
            break;
        }
        if a.rate > 0.0 {
            let at = Duration::from_secs_f64(
                (m.log_time_ns.saturating_sub(first)) as f64 * 1e-9 / a.rate,
            );
            tokio::select! {
                _ = tokio::time::sleep_until(t0 + at) => {}
                _ = rt.shutdown.wait() => break,
            }
        }
        let result = match outs.get(&m.topic) {
            Some(Out::Cloud(p)) => match skyground_msgs::from_cdr::<PointCloud2>(&m.cdr) {
                Ok(msg) => p.publish(msg).await.map(|_| ()).map_err(|e| e.to_string()),
                Err(e) => Err(format!("undecodable PointCloud2: {e}")),
            },
            Some(Out::Other(e)) => e.emit(&m.cdr).await,
            None => continue,
        };
        match result {
            Ok(()) => *sent.entry(m.topic.as_str()).or_default() += 1,
            Err(e) => {
                failed += 1;
                rt.log.warn(&format!("{}: {e}", m.topic));
            }
        }
    }
    let summary: Vec<String> = sent.iter().map(|(t, n)| format!("{t} {n}")).collect();
    rt.log.info(&format!(
        "played {} ({failed} failed): {}",
        a.bag.display(),
        summary.join(", ")
    ));
    if a.linger {
        rt.shutdown.wait().await;
    }
    if failed > 0 {
        return Err(err(format!("{failed} messages could not be sent")));
    }
    Ok(())
}
