//! scene_classifier: /aerial_cloud → ground by CSF, vegetation vs building by
//! the Random Forest → /classified_cloud (label field, latched). docs/design.md step 1.

use crate::convert::pointcloud2::{EncodeOptions, encode};
use serde::Deserialize;
use skyground_core::classify::SceneClassifier;
use skyground_core::ground::CsfParams;

use crate::runtime::model::load_model;
use crate::runtime::{NodeRuntime, RuntimeError, qos};
use crate::transport::{CloudPublisher, CloudSubscription, Received, TransportConfig};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    input_topic: String,
    output_topic: String,
    model_path: String,
    csf: CsfParams,
    transport: TransportConfig,
    max_clouds: u64,
}

pub use crate::runtime::specs::SCENE_CLASSIFIER as SPEC;

/// Runs the node until it is done or asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    let classifier = SceneClassifier::new(p.csf.clone(), load_model(&p.model_path)?)
        .map_err(|e| RuntimeError::Node(e.to_string()))?;
    let classifier = std::sync::Arc::new(classifier);
    let mut sub = CloudSubscription::new(
        rt,
        &p.input_topic,
        qos::latched(256),
        p.transport.tile_points,
    )?;
    let publisher = CloudPublisher::new(rt, &p.output_topic, qos::latched(1), p.transport)?;
    rt.log.info(&format!(
        "classifying clouds from {} onto {}",
        p.input_topic, p.output_topic
    ));
    let mut done = 0u64;
    loop {
        let Some(got) = rt.shutdown.or(sub.next()).await else {
            break;
        };
        let (msg, decoded) = match got {
            Received::Bad(reason) => {
                rt.log
                    .error(&format!("rejected cloud on {}: {reason}", p.input_topic));
                continue;
            }
            Received::Cloud { msg, decoded } => (msg, decoded),
        };
        let c = classifier.clone();
        let result = tokio::task::spawn_blocking(move || {
            let r = c.classify_cloud(&decoded.cloud);
            (decoded.cloud, r)
        })
        .await
        .map_err(|e| RuntimeError::Node(format!("classifier task: {e}")))?;
        let mut cloud = result.0;
        let classified = match result.1 {
            Ok(c) => c,
            Err(e) => {
                rt.log.error(&format!(
                    "cannot classify the cloud on {}: {e}",
                    p.input_topic
                ));
                continue;
            }
        };
        rt.log.info(&format!(
            "classified {} points in {:.2} s (CSF {:.2} s): {}",
            cloud.len(),
            classified.seconds_total(),
            classified.seconds_csf,
            classified.summary()
        ));
        for m in classified.messages() {
            rt.log.info(&m);
        }
        if let Some(m) = classifier.echo_note(&cloud) {
            rt.log.info(m);
        }
        cloud.label = Some(classified.labels);
        let header = msg.header.clone();
        publisher
            .publish(encode(&cloud, header, &EncodeOptions { double: false }))
            .await?;
        done += 1;
        if p.max_clouds > 0 && done >= p.max_clouds {
            break;
        }
    }
    Ok(())
}
