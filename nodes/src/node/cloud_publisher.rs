//! cloud_publisher: a LAS/LAZ/PLY file (or a synthetic cloud) → latched
//! sensor_msgs/PointCloud2 on /aerial_cloud, and the file's local frame and
//! CRS on /georeference (PointCloud2 carries local metres only).

use std::path::PathBuf;
use std::time::Duration;

use crate::convert::diagnostics::array;
use crate::convert::pointcloud2::{EncodeOptions, encode};
use crate::runtime::{NodeRuntime, RuntimeError, qos};
use crate::transport::{CloudPublisher, TransportConfig};
use ros2_client::Publisher;
use serde::Deserialize;
use skyground_core::cloud::{self, Cloud, synthetic};
use skyground_core::mission::Georeference;
use skyground_msgs::diagnostic_msgs::DiagnosticArray;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    file: String,
    synthetic_points: usize,
    topic: String,
    frame_id: String,
    georeference_topic: String,
    double: bool,
    count: u32,
    period_s: f64,
    wait_for_subscribers: usize,
    wait_timeout_s: f64,
    linger: bool,
    transport: TransportConfig,
}

pub use crate::runtime::specs::CLOUD_PUBLISHER as SPEC;

/// Runs the node until it is done or asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    let cloud = if p.file.is_empty() {
        synthetic::tilted_plane(p.synthetic_points)
    } else {
        cloud::read_cloud(&PathBuf::from(&p.file)).map_err(|e| RuntimeError::Node(e.to_string()))?
    };
    let source = if p.file.is_empty() {
        "synthetic cloud".to_string()
    } else {
        p.file.clone()
    };
    rt.log.info(&format!(
        "loaded {} points from {source} (origin {:?})",
        cloud.len(),
        cloud.origin
    ));
    let publisher = CloudPublisher::new(rt, &p.topic, qos::latched(1), p.transport)?;
    // Held for the node's life: a latched sample lives as long as its writer.
    let _georef = publish_georeference(rt, &p, &cloud).await?;
    if p.wait_for_subscribers > 0
        && !publisher
            .wait_for_subscriptions(
                p.wait_for_subscribers,
                Duration::from_secs_f64(p.wait_timeout_s.max(0.0)),
            )
            .await
    {
        rt.log.warn(&format!(
            "only {} of {} subscribers after {} s; publishing anyway",
            publisher.subscription_count(),
            p.wait_for_subscribers,
            p.wait_timeout_s
        ));
    }
    let opts = EncodeOptions { double: p.double };
    for k in 0..p.count {
        if rt.shutdown.requested() {
            break;
        }
        let header = rt.header(&p.frame_id);
        let stats = publisher.publish(encode(&cloud, header, &opts)).await?;
        rt.log.info(&format!(
            "published {} points on {} as {} message(s), {:.1} MB in {:.3} s ({:.1} MB/s){}",
            cloud.len(),
            p.topic,
            stats.tiles,
            stats.bytes as f64 / 1e6,
            stats.seconds,
            stats.bytes as f64 / 1e6 / stats.seconds.max(1e-9),
            if stats.acknowledged {
                ""
            } else {
                "; some readers did not acknowledge"
            }
        ));
        if k + 1 < p.count {
            tokio::select! {
                _ = tokio::time::sleep(Duration::from_secs_f64(p.period_s.max(0.0))) => {}
                _ = rt.shutdown.wait() => break,
            }
        }
    }
    if p.linger {
        rt.shutdown.wait().await;
    }
    Ok(())
}

/// The cloud's frame on `georeference_topic` (latched), so a subscriber or
/// a bag can take the clouds back to the survey's CRS and unit.
async fn publish_georeference(
    rt: &mut NodeRuntime,
    p: &Params,
    cloud: &Cloud,
) -> Result<Option<Publisher<DiagnosticArray>>, RuntimeError> {
    if p.georeference_topic.is_empty() {
        return Ok(None);
    }
    let georef = Georeference {
        frame_id: p.frame_id.clone(),
        frame: cloud.frame(),
    };
    let publisher = rt.publisher::<DiagnosticArray>(&p.georeference_topic, qos::latched(1))?;
    let msg = array(rt.header(&p.frame_id), georef.to_wire());
    match publisher.async_publish(msg).await {
        Ok(()) => rt.log.info(&format!(
            "{}: frame `{}` at origin {:?} m, {}",
            p.georeference_topic,
            p.frame_id,
            cloud.origin,
            cloud
                .crs
                .as_ref()
                .map_or("no CRS (metres assumed)".into(), |c| c.label())
        )),
        Err(e) => rt
            .log
            .warn(&format!("cannot publish {}: {e}", p.georeference_topic)),
    }
    Ok(Some(publisher))
}
