//! cloud_inspector: PointCloud2 topic → per-cloud report on /rosout and a
//! DiagnosticArray; bad clouds are reported and the node keeps running.

use crate::runtime::{NodeRuntime, NodeSpec, RuntimeError, qos};
use crate::transport::{CloudSubscription, Received};
use serde::Deserialize;
use skyground_msgs::diagnostic_msgs::{DiagnosticArray, DiagnosticStatus, KeyValue};
use skyground_msgs::std_msgs::Header;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    topic: String,
    qos: String,
    depth: usize,
    tile_points: u32,
    stats_topic: String,
    max_clouds: u64,
}

/// Name and default params.
pub const SPEC: NodeSpec = NodeSpec {
    name: "cloud_inspector",
    default_params: include_str!("../../../config/cloud_inspector.yaml"),
    live: &["max_clouds"],
};

fn kv(key: &str, value: impl ToString) -> KeyValue {
    KeyValue {
        key: key.into(),
        value: value.to_string(),
    }
}

/// Runs the node until it is done or asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    let sub_qos = qos::by_name(&p.qos, p.depth).ok_or_else(|| {
        RuntimeError::Node(format!(
            "unknown qos `{}` (latched, reliable, sensor)",
            p.qos
        ))
    })?;
    let mut sub = CloudSubscription::new(rt, &p.topic, sub_qos, p.tile_points)?;
    let stats = rt.publisher::<DiagnosticArray>(&p.stats_topic, qos::reliable(10))?;
    rt.log.info(&format!("inspecting clouds on {}", p.topic));
    let mut good = 0u64;
    loop {
        let got = tokio::select! {
            r = sub.next() => r,
            _ = rt.shutdown.wait() => None,
        };
        let Some(got) = got else { break };
        let status = match got {
            Received::Bad(reason) => {
                rt.log
                    .error(&format!("rejected cloud on {}: {reason}", p.topic));
                DiagnosticStatus {
                    level: DiagnosticStatus::ERROR,
                    name: p.topic.clone(),
                    message: reason,
                    hardware_id: String::new(),
                    values: vec![],
                }
            }
            Received::Cloud { msg, decoded } => {
                good += 1;
                let c = &decoded.cloud;
                let labels = c
                    .label_histogram()
                    .map(|h| {
                        h.iter()
                            .enumerate()
                            .filter(|(_, n)| **n > 0)
                            .map(|(l, n)| format!("{l}:{n}"))
                            .collect::<Vec<_>>()
                            .join(",")
                    })
                    .unwrap_or_default();
                let fields: Vec<_> = msg.fields.iter().map(|f| f.name.as_str()).collect();
                rt.log.info(&format!(
                    "cloud on {}: {} points, fields [{}], dropped {} non-finite, labels [{labels}]",
                    p.topic,
                    c.len(),
                    fields.join(","),
                    decoded.dropped_non_finite
                ));
                DiagnosticStatus {
                    level: DiagnosticStatus::OK,
                    name: p.topic.clone(),
                    message: "ok".into(),
                    hardware_id: String::new(),
                    values: vec![
                        kv("points", c.len()),
                        kv("dropped_non_finite", decoded.dropped_non_finite),
                        kv("fields", fields.join(",")),
                        kv("labels", labels),
                        kv("stamp_sec", msg.header.stamp.sec),
                        kv("stamp_nanosec", msg.header.stamp.nanosec),
                    ],
                }
            }
        };
        let report = DiagnosticArray {
            header: Header {
                stamp: rt.now(),
                frame_id: String::new(),
            },
            status: vec![status],
        };
        if let Err(e) = stats.async_publish(report).await {
            rt.log.warn(&format!("cannot publish stats: {e:?}"));
        }
        // Read now, not at start-up: `ros2 param set` may have changed it.
        let max_clouds = rt
            .current_params::<Params>()
            .map_or(p.max_clouds, |c| c.max_clouds);
        if max_clouds > 0 && good >= max_clouds {
            break;
        }
    }
    Ok(())
}
