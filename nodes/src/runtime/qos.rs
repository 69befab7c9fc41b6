//! The QoS profiles skyground topics use (docs/design.md topic table), said explicitly
//! because ros2-client's subscription default is best effort, depth 1.

use ros2_client::QosProfile;
use ros2_client::qos::{Durability, History, Reliability, WhenFull};

/// Publish-once data that late joiners must still get: reliable, transient
/// local; a write waits for room as long as it takes (a cloud's tiles are
/// paced by their own acknowledgements, `transport`, far below the window).
pub fn latched(depth: usize) -> QosProfile {
    kept(QosProfile::publisher_default(), depth)
        .reliability(Reliability::Reliable {
            when_full: WhenFull::Block,
        })
        .durability(Durability::TransientLocal)
}

/// Commands and statuses that must not be lost: reliable, volatile. A
/// write fails at once (the node logs it and goes on) when a reader holds
/// the send window full, 8192 samples unacknowledged: `Block` waited for
/// ever, and one starved reader (the recorder) stopped vehicle_sim for good
/// (issue 50; nodes/tests/stuck_reader.rs). Not `Wait(d)`: RustDDS 0.15.1's
/// async write is not woken at its deadline (a 1 s wait took 5 s there).
pub fn reliable(depth: usize) -> QosProfile {
    kept(QosProfile::publisher_default(), depth).reliability(Reliability::Reliable {
        when_full: WhenFull::Fail,
    })
}

/// /tf: reliable, as tf2's listeners (RViz) ask, but a write with the
/// window full fails at once: a transform is stale a step later.
pub fn tf() -> QosProfile {
    kept(QosProfile::publisher_default(), 100).reliability(Reliability::Reliable {
        when_full: WhenFull::Fail,
    })
}

/// Odometry: a stream whose newest sample matters, best effort (a reliable
/// subscriber of the robot's still matches it); never blocks its writer.
pub fn odometry() -> QosProfile {
    sensor(10)
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
        let wait = Reliability::Reliable {
            when_full: WhenFull::Fail,
        };
        assert_eq!(
            (r.reliability, r.durability, r.history),
            (wait, Durability::Volatile, keep(10))
        );
        assert_eq!(odometry().reliability, Reliability::BestEffort);
        let s = sensor(5);
        assert_eq!(
            (s.reliability, s.durability, s.history),
            (Reliability::BestEffort, Durability::Volatile, keep(5))
        );
    }
}
