//! The QoS profiles skyground topics use (docs/design.md topic table), said explicitly
//! because ros2-client's subscription default is best effort, depth 1.

use ros2_client::QosProfile;
use ros2_client::qos::{Durability, History, Reliability, WhenFull};

/// Publish-once data that late joiners must still get: reliable, transient local.
pub fn latched(depth: usize) -> QosProfile {
    QosProfile::publisher_default()
        .reliability(Reliability::Reliable {
            when_full: WhenFull::Block,
        })
        .durability(Durability::TransientLocal)
        .history(History::KeepLast {
            depth: depth.max(1),
        })
}

/// Commands and streams that must not be lost: reliable, volatile.
pub fn reliable(depth: usize) -> QosProfile {
    QosProfile::publisher_default()
        .reliability(Reliability::Reliable {
            when_full: WhenFull::Block,
        })
        .durability(Durability::Volatile)
        .history(History::KeepLast {
            depth: depth.max(1),
        })
}

/// Sensor streams where the newest sample matters: best effort, volatile.
pub fn sensor(depth: usize) -> QosProfile {
    QosProfile::subscription_default()
        .reliability(Reliability::BestEffort)
        .durability(Durability::Volatile)
        .history(History::KeepLast {
            depth: depth.max(1),
        })
}

/// Parses a QoS name used on command lines: latched | reliable | sensor.
pub fn by_name(name: &str, depth: usize) -> Option<QosProfile> {
    match name {
        "latched" | "transient_local" => Some(latched(depth)),
        "reliable" => Some(reliable(depth)),
        "sensor" | "best_effort" => Some(sensor(depth)),
        _ => None,
    }
}
