//! The QoS profiles skyground topics use (docs/design.md topic table), said explicitly
//! because ros2-client's subscription default is best effort, depth 1.

use ros2_client::QosProfile;
use ros2_client::qos::{Durability, History, Reliability, WhenFull};

/// Publish-once data that late joiners must still get: reliable, transient local.
pub fn latched(depth: usize) -> QosProfile {
    reliable(depth).durability(Durability::TransientLocal)
}

/// Commands and streams that must not be lost: reliable, volatile.
pub fn reliable(depth: usize) -> QosProfile {
    kept(QosProfile::publisher_default(), depth).reliability(Reliability::Reliable {
        when_full: WhenFull::Block,
    })
}

/// Sensor streams where the newest sample matters: best effort, volatile.
pub fn sensor(depth: usize) -> QosProfile {
    kept(QosProfile::subscription_default(), depth).reliability(Reliability::BestEffort)
}

/// `base`, volatile, keeping the last `depth` samples (at least one).
fn kept(base: QosProfile, depth: usize) -> QosProfile {
    base.durability(Durability::Volatile)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_say_what_their_names_promise() {
        let keep = |depth| History::KeepLast { depth };
        let block = Reliability::Reliable {
            when_full: WhenFull::Block,
        };
        let l = latched(0);
        assert_eq!(
            (l.reliability, l.durability, l.history),
            (block, Durability::TransientLocal, keep(1))
        );
        let r = reliable(10);
        assert_eq!(
            (r.reliability, r.durability, r.history),
            (block, Durability::Volatile, keep(10))
        );
        let s = sensor(5);
        assert_eq!(
            (s.reliability, s.durability, s.history),
            (Reliability::BestEffort, Durability::Volatile, keep(5))
        );
    }
}
