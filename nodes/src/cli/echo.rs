//! `skyground echo`: print a topic's messages as JSON lines (like `ros2 topic echo`).

use std::time::Duration;

use serde_json::{Value, json};

use super::resolve;
use crate::runtime::{NodeRuntime, RuntimeError};
use crate::tap::tap;

/// What to echo.
#[derive(Debug, Clone, clap::Args)]
pub struct EchoArgs {
    /// Topic, optionally with its type: /global_path or /global_path:nav_msgs/msg/Path.
    pub topic: String,
    /// Message type (pkg/msg/Type); default: from discovery.
    #[arg(long = "type")]
    pub type_name: Option<String>,
    /// auto (match the publishers), latched, reliable or sensor.
    #[arg(long, default_value = "auto")]
    pub qos: String,
    /// Stop after this many messages (0: until SIGINT).
    #[arg(long, default_value_t = 0)]
    pub count: u64,
    /// Seconds to wait for a publisher when the type or QoS must be discovered.
    #[arg(long, default_value_t = 30.0)]
    pub timeout: f64,
    /// Print long byte arrays in full (default: their length and a checksum).
    #[arg(long)]
    pub full: bool,
}

/// Runs the echo.
pub async fn run(rt: &mut NodeRuntime, a: EchoArgs) -> Result<(), RuntimeError> {
    let (topic, ty) = super::topic_and_type(&a.topic);
    let type_hint = a.type_name.clone().or(ty);
    let (type_name, qos) = resolve(
        rt,
        &topic,
        type_hint.as_deref(),
        &a.qos,
        100,
        Duration::from_secs_f64(a.timeout.max(0.0)),
    )
    .await?;
    let mut sub = tap(rt, &topic, &type_name, qos, true)?;
    let mut seen = 0u64;
    loop {
        let Some(m) = rt.shutdown.or(sub.next()).await else {
            break;
        };
        match m {
            Err(e) => rt.log.error(&format!("{topic}: {e}")),
            Ok(m) => {
                let mut msg = m.json.unwrap_or(Value::Null);
                if !a.full {
                    shorten_arrays(&mut msg);
                }
                println!(
                    "{}",
                    json!({"topic": topic, "type": type_name, "publish_time_ns": m.publish_time_ns, "msg": msg})
                );
                seen += 1;
                if a.count > 0 && seen >= a.count {
                    break;
                }
            }
        }
    }
    Ok(())
}

/// Replaces arrays of more than 64 small integers (byte blobs such as
/// PointCloud2 data) by `{"len": n, "fnv1a": hash}`.
fn shorten_arrays(v: &mut Value) {
    match v {
        Value::Array(items)
            if items.len() > 64 && items.iter().all(|x| x.as_u64().is_some_and(|n| n < 256)) =>
        {
            let mut h: u64 = 0xcbf2_9ce4_8422_2325;
            for x in items.iter() {
                h ^= x.as_u64().unwrap_or(0);
                h = h.wrapping_mul(0x0100_0000_01b3);
            }
            *v = json!({"len": items.len(), "fnv1a": format!("{h:016x}")});
        }
        Value::Array(items) => items.iter_mut().for_each(shorten_arrays),
        Value::Object(m) => m.values_mut().for_each(shorten_arrays),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_byte_arrays_are_summarised() {
        let mut v = json!({"data": (0..100).collect::<Vec<u32>>(), "poses": [1, 2]});
        shorten_arrays(&mut v);
        assert_eq!(v["data"]["len"], 100);
        assert_eq!(v["poses"], json!([1, 2]));
    }
}
