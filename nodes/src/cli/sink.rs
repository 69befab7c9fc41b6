//! `skyground cloud-sink`: receive whole clouds and print one JSON line each
//! (for benchmarks and tests; `cloud_inspector` is the node for users).

use std::time::{SystemTime, UNIX_EPOCH};

use serde_json::json;
use skyground_core::cloud::synthetic;

use crate::runtime::{NodeRuntime, RuntimeError, qos};
use crate::transport::{CloudSubscription, Received};

/// What to receive.
#[derive(Debug, Clone, clap::Args)]
pub struct SinkArgs {
    /// Topic to subscribe to.
    #[arg(long, default_value = "/aerial_cloud")]
    pub topic: String,
    /// Stop after this many clouds (0: until SIGINT).
    #[arg(long, default_value_t = 1)]
    pub count: u64,
    /// latched, reliable or sensor.
    #[arg(long, default_value = "reliable")]
    pub qos: String,
    /// Tile size of the publisher.
    #[arg(long, default_value_t = crate::convert::pointcloud2::tiles::DEFAULT_TILE_POINTS)]
    pub tile_points: u32,
    /// Check every point against the synthetic cloud of the same size.
    #[arg(long)]
    pub check_synthetic: bool,
}

/// Runs the sink.
pub async fn run(rt: &mut NodeRuntime, a: SinkArgs) -> Result<(), RuntimeError> {
    let q = qos::by_name(&a.qos, 256)
        .ok_or_else(|| RuntimeError::Node(format!("unknown qos `{}`", a.qos)))?;
    let mut sub = CloudSubscription::new(rt, &a.topic, q, a.tile_points)?;
    println!("{}", json!({"ready": true}));
    let mut seen = 0u64;
    while a.count == 0 || seen < a.count {
        let got = rt.shutdown.or(sub.next()).await;
        let complete_ns = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        match got {
            None => break,
            Some(Received::Bad(reason)) => {
                println!("{}", json!({"error": reason, "complete_ns": complete_ns}));
            }
            Some(Received::Cloud { msg, decoded }) => {
                seen += 1;
                let valid = !a.check_synthetic || {
                    let expect = synthetic::tilted_plane(decoded.cloud.len());
                    expect.xyz == decoded.cloud.xyz && expect.label == decoded.cloud.label
                };
                println!(
                    "{}",
                    json!({
                        "points": decoded.cloud.len(),
                        "bytes": msg.data.len(),
                        "stamp": [msg.header.stamp.sec, msg.header.stamp.nanosec],
                        "complete_ns": complete_ns,
                        "valid": valid,
                        "abandoned": sub.abandoned(),
                    })
                );
            }
        }
    }
    Ok(())
}
