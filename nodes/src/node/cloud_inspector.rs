//! cloud_inspector: PointCloud2 topic → per-cloud report on /rosout and a
//! DiagnosticArray; bad clouds are reported and the node keeps running.

use crate::convert::diagnostics::to_status;
use crate::runtime::{NodeRuntime, RuntimeError, qos};
use crate::transport::{CloudSubscription, Received};
use serde::Deserialize;
use skyground_core::mission::{CloudStatus, CloudSummary};
use skyground_msgs::diagnostic_msgs::DiagnosticArray;

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

pub use crate::runtime::specs::CLOUD_INSPECTOR as SPEC;

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
        let Some(got) = rt.shutdown.or(sub.next()).await else {
            break;
        };
        let result = match got {
            Received::Bad(reason) => {
                rt.log
                    .error(&format!("rejected cloud on {}: {reason}", p.topic));
                Err(reason)
            }
            Received::Cloud { msg, decoded } => {
                good += 1;
                let fields = msg.fields.iter().map(|f| f.name.clone()).collect();
                let s = CloudSummary {
                    stamp_sec: msg.header.stamp.sec,
                    stamp_nanosec: msg.header.stamp.nanosec,
                    ..CloudSummary::of(&decoded.cloud, decoded.dropped_non_finite, fields)
                };
                rt.log.info(&format!(
                    "cloud on {}: {} points, fields [{}], dropped {} non-finite, labels [{}]",
                    p.topic,
                    s.points,
                    s.fields.join(","),
                    s.dropped_non_finite,
                    s.labels
                        .iter()
                        .map(ToString::to_string)
                        .collect::<Vec<_>>()
                        .join(",")
                ));
                Ok(s)
            }
        };
        let status = to_status(
            CloudStatus {
                topic: p.topic.clone(),
                result,
            }
            .to_wire(),
        );
        let report = DiagnosticArray {
            header: rt.header(""),
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
