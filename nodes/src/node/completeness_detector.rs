//! completeness_detector: /classified_cloud (+ footprints, + /resampled_cloud
//! in later rounds) → per building, where the walls are missing (docs/design.md
//! steps 2–3) → /missing_points, /completeness, /detection_markers.

use std::sync::Arc;

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::footprint::Footprint;
use skyground_core::missing::{SceneParams, detect_scene};
use skyground_core::mission::PlannerStatus;
use skyground_core::mission::detector::Detector;
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::std_msgs::Header;
use skyground_msgs::visualization_msgs::MarkerArray;

use crate::convert::areas::load_logged;
use crate::convert::detection::{completeness_array, detection_markers, missing_message};
use crate::convert::diagnostics::statuses;
use crate::runtime::{NodeRuntime, RuntimeError, qos, work_beat};
use crate::transport::{CloudPublisher, CloudSubscription, Received, TransportConfig};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    input_topic: String,
    resampled_topic: String,
    /// A resumed mission: the first detection also waits for the kept merge.
    wait_resampled: bool,
    planner_status_topic: String,
    footprints: String,
    footprint_id: String,
    crs: String,
    origin: Vec<f64>,
    /// The sections `detect`, `split` and `derive`, as `skyground detect` reads them.
    #[serde(flatten)]
    scene: SceneParams,
    transport: TransportConfig,
}

pub use crate::runtime::specs::COMPLETENESS_DETECTOR as SPEC;

#[derive(Clone)]
struct Setup {
    footprints: Option<Vec<Footprint>>,
    scene: SceneParams,
}

/// Runs the node until asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    work_beat::beat(rt, "completeness_detector")?;
    p.scene.detect.validate()?;
    // Read before anything starts: a footprint file that cannot be used
    // stops the node with the reason, never a silent fall-back to deriving.
    let footprints = given_footprints(rt, &p)?;
    let tile = p.transport.tile_points;
    let mut aerial_sub = CloudSubscription::new(rt, &p.input_topic, qos::latched(256), tile)?;
    let mut resampled_sub = match p.resampled_topic.as_str() {
        "" => None,
        t => Some(CloudSubscription::new(rt, t, qos::latched(256), tile)?),
    };
    let planner_sub = if p.planner_status_topic.is_empty() {
        None
    } else {
        Some(rt.subscription::<DiagnosticArray>(&p.planner_status_topic, qos::latched(1))?)
    };
    let planner_s = match planner_sub.as_ref() {
        Some(s) => futures::future::Either::Left(s.async_stream()),
        None => futures::future::Either::Right(futures::stream::pending()),
    };
    futures::pin_mut!(planner_s);
    let mut det = Detector::<Header>::new(planner_sub.is_some());
    if p.wait_resampled {
        det = det.resuming();
    }
    let missing_pub = CloudPublisher::new(rt, "/missing_points", qos::latched(1), p.transport)?;
    let status_pub = rt.publisher::<DiagnosticArray>("/completeness", qos::latched(1))?;
    let marker_pub = rt.publisher::<MarkerArray>("/detection_markers", qos::latched(1))?;
    let setup = Arc::new(Setup {
        footprints,
        scene: p.scene,
    });
    rt.log.info(&format!("waiting for {}", p.input_topic));
    loop {
        let due = tokio::select! {
            r = aerial_sub.next() => match r {
                Some(Received::Cloud { decoded, .. }) if decoded.cloud.label.is_none() => {
                    rt.log.error(&format!("cloud on {} has no `label` field: run scene_classifier first", p.input_topic));
                    false
                }
                Some(Received::Cloud { msg, decoded }) => det.aerial(decoded.cloud, msg.header),
                Some(Received::Bad(reason)) => {
                    rt.log.error(&format!("rejected cloud on {}: {reason}", p.input_topic));
                    false
                }
                None => break,
            },
            r = async { match resampled_sub.as_mut() { Some(s) => s.next().await, None => std::future::pending().await } } => match r {
                Some(Received::Cloud { decoded, .. }) => det.merged(decoded.cloud),
                Some(Received::Bad(reason)) => {
                    rt.log.error(&format!("rejected cloud on {}: {reason}", p.resampled_topic));
                    false
                }
                None => break,
            },
            // Every route end goes through the gate, so none is lost to an earlier `any`.
            Some(m) = planner_s.next() => statuses(&rt.log, m, PlannerStatus::from_wire)
                .into_iter()
                .filter(|s| s.phase == "done")
                .fold(false, |due, s| det.route_done(s.round) | due),
            _ = rt.shutdown.wait() => break,
        };
        let Some((cloud, header, merged)) = det.inputs().filter(|_| due) else {
            continue;
        };
        let (round, t0) = (det.round(), std::time::Instant::now());
        let (s, c, extra) = (setup.clone(), cloud.clone(), merged.cloned());
        let result = tokio::task::spawn_blocking(move || {
            let f = s.footprints.as_deref();
            detect_scene(&c, extra.as_ref(), f, &s.scene)
        })
        .await
        .map_err(|e| RuntimeError::Node(format!("detection task: {e}")))?;
        let (detection, _footprints) = match result {
            Ok(v) => v,
            Err(e) => {
                rt.log.error(&format!("detection failed: {e}"));
                continue;
            }
        };
        let mut header = header.clone();
        header.stamp = rt.now();
        let n_missing: usize = detection.buildings.iter().map(|b| b.missing.len()).sum();
        rt.log.info(&format!(
            "round {round}: {} buildings, {n_missing} missing boundary points, R_missing {:.3} ({:.2} s)",
            detection.buildings.len(),
            detection.r_missing(),
            t0.elapsed().as_secs_f64()
        ));
        let msg = missing_message(&detection, cloud.origin, header.clone());
        missing_pub.publish(msg).await?;
        if let Err(e) = status_pub
            .async_publish(completeness_array(&header, &detection, round))
            .await
        {
            rt.log.warn(&format!("cannot publish /completeness: {e}"));
        }
        if let Err(e) = marker_pub
            .async_publish(detection_markers(&header, &detection))
            .await
        {
            rt.log
                .warn(&format!("cannot publish /detection_markers: {e}"));
        }
        det.detected();
    }
    Ok(())
}

/// The footprints named by the `footprints` param in the clouds' frame
/// (`origin`, `crs`), `None` without one; an error names the file and why.
fn given_footprints(rt: &NodeRuntime, p: &Params) -> Result<Option<Vec<Footprint>>, RuntimeError> {
    if p.footprints.trim().is_empty() {
        return Ok(None);
    }
    let frame = (p.footprint_id.as_str(), p.crs.as_str(), p.origin.as_slice());
    load_logged(&rt.log, "footprints", &p.footprints, frame).map(Some)
}

#[cfg(test)]
mod tests {
    use crate::runtime::params::ParamSet;

    // `scene` is flattened into a struct that denies unknown fields: its
    // three sections must still be read, and a stray key still refused.
    #[test]
    fn shipped_params_read_the_scene_sections_and_refuse_a_stray_key() {
        let mut set = ParamSet::default();
        set.merge_yaml(super::SPEC.default_params, super::SPEC.name, "config")
            .expect("shipped YAML");
        set.set("detect.theta", serde_json::json!(0.33));
        let p: super::Params = set.parse(super::SPEC.name).expect("parses");
        assert_eq!(p.scene.detect.theta, 0.33);
        set.set("detecc.theta", serde_json::json!(0.5));
        assert!(set.parse::<super::Params>(super::SPEC.name).is_err());
    }
}
