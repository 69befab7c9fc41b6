//! [`TopicQos`] and the `offered_qos_profiles` channel metadata rosbag2 writes from it.

/// The QoS a topic was offered with, as far as recording and playback need it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TopicQos {
    /// Reliable (`true`) or best effort (`false`).
    pub reliable: bool,
    /// Transient local (`true`, latched) or volatile (`false`).
    pub transient_local: bool,
    /// History depth (keep last).
    pub depth: usize,
}

impl Default for TopicQos {
    /// rclcpp's default publisher QoS: reliable, volatile, keep last 10.
    fn default() -> Self {
        Self {
            reliable: true,
            transient_local: false,
            depth: 10,
        }
    }
}

/// rmw's infinite duration, as rosbag2 records an unset deadline, lifespan and lease.
const INFINITE: &str = "\n    sec: 9223372036\n    nsec: 854775807";

impl TopicQos {
    /// The channel metadata value rosbag2 (metadata version 9, Jazzy and later) stores under
    /// `offered_qos_profiles`: a YAML list holding this one profile, policies as names.
    pub fn offered_qos_profiles(&self) -> String {
        let reliability = if self.reliable {
            "reliable"
        } else {
            "best_effort"
        };
        let durability = if self.transient_local {
            "transient_local"
        } else {
            "volatile"
        };
        format!(
            "- history: keep_last\n  \
             depth: {depth}\n  \
             reliability: {reliability}\n  \
             durability: {durability}\n  \
             deadline:{INFINITE}\n  \
             lifespan:{INFINITE}\n  \
             liveliness: automatic\n  \
             liveliness_lease_duration:{INFINITE}\n  \
             avoid_ros_namespace_conventions: false",
            depth = self.depth,
        )
    }
}

impl TopicQos {
    /// Reads back the first profile of an `offered_qos_profiles` value
    /// (rosbag2's YAML); `None` when it names no reliability or durability.
    pub fn from_offered_qos_profiles(text: &str) -> Option<Self> {
        let field = |key: &str| {
            text.lines()
                .map(str::trim_start)
                .map(|l| l.trim_start_matches("- "))
                .find_map(|l| l.strip_prefix(key).map(str::trim))
        };
        let reliable = match field("reliability:")? {
            "reliable" => true,
            "best_effort" => false,
            _ => return None,
        };
        let transient_local = match field("durability:")? {
            "transient_local" => true,
            "volatile" => false,
            _ => return None,
        };
        let depth = field("depth:").and_then(|d| d.parse().ok()).unwrap_or(10);
        Some(Self {
            reliable,
            transient_local,
            depth,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_read_back() {
        for q in [
            TopicQos {
                reliable: false,
                transient_local: true,
                depth: 1,
            },
            TopicQos {
                reliable: true,
                transient_local: false,
                depth: 50,
            },
        ] {
            assert_eq!(
                TopicQos::from_offered_qos_profiles(&q.offered_qos_profiles()),
                Some(q)
            );
        }
        assert_eq!(TopicQos::from_offered_qos_profiles("nonsense"), None);
    }

    #[test]
    fn profile_names_each_policy() {
        let text = TopicQos {
            reliable: false,
            transient_local: true,
            depth: 1,
        }
        .offered_qos_profiles();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "- history: keep_last");
        assert!(lines.contains(&"  depth: 1"));
        assert!(lines.contains(&"  reliability: best_effort"));
        assert!(lines.contains(&"  durability: transient_local"));
        assert!(lines.contains(&"  liveliness: automatic"));
        assert!(lines.contains(&"  avoid_ros_namespace_conventions: false"));
        assert_eq!(text.matches("    nsec: 854775807").count(), 3);
        assert!(lines.iter().skip(1).all(|l| l.starts_with("  ")));
    }
}
