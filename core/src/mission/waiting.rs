//! What global_planner says while it lacks an input
//! ([`super::planner::Planner::waiting_for`]): when (once the lack has
//! lasted a period, then again every period while it lasts) and which of
//! the inputs DDS matched to a publisher. A latched input that never
//! arrives (a publisher down, a sample lost to discovery) would otherwise
//! leave the planner silent for good.

use std::time::{Duration, Instant};

/// When a lack of input is said again.
#[derive(Debug, Clone)]
pub struct WaitingReminder {
    every: Duration,
    /// When the lack began (or the reminder started).
    since: Instant,
    /// How much of the wait has been said.
    said: Duration,
}

impl WaitingReminder {
    /// A reminder every `every`, counting from `now`.
    pub fn new(every: Duration, now: Instant) -> Self {
        Self {
            every,
            since: now,
            said: Duration::ZERO,
        }
    }

    /// At `now`, with an input `lacking` or none: the whole seconds the
    /// lack has lasted when it is time to say it again, else `None`. A lack
    /// that ends starts the count again.
    pub fn check(&mut self, lacking: bool, now: Instant) -> Option<u64> {
        if !lacking {
            (self.since, self.said) = (now, Duration::ZERO);
            return None;
        }
        let waited = now.saturating_duration_since(self.since);
        if waited < self.said + self.every {
            return None;
        }
        self.said += self.every;
        Some(waited.as_secs())
    }
}

/// How many publishers DDS matched to each input named in `what` (topics
/// joined by ", ", as `waiting_for` names them): none means discovery never
/// joined the two (another domain, a node down, a type or QoS that does not
/// match); some means they are joined and silent. Empty when `what` names
/// none of `matched`'s topics, else ` (…)` to append to the line.
pub fn publishers_said(what: &str, matched: &[(&str, usize)]) -> String {
    let said: Vec<String> = matched
        .iter()
        .filter(|(topic, _)| what.split(", ").any(|w| w == *topic))
        .map(|(topic, n)| match n {
            0 => format!("{topic}: no publisher matched"),
            n => format!("{topic}: {n} publisher(s) matched, nothing received"),
        })
        .collect();
    if said.is_empty() {
        String::new()
    } else {
        format!(" ({})", said.join("; "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_wait_says_which_inputs_have_a_publisher() {
        let matched = [("/classified_cloud", 1), ("/state_estimation", 0)];
        assert_eq!(
            publishers_said("/classified_cloud, /state_estimation", &matched),
            " (/classified_cloud: 1 publisher(s) matched, nothing received; /state_estimation: no publisher matched)"
        );
        assert_eq!(
            publishers_said("/state_estimation", &matched),
            " (/state_estimation: no publisher matched)"
        );
        assert_eq!(
            publishers_said("the other half of a target set", &matched),
            ""
        );
    }

    #[test]
    fn a_lack_is_said_each_period_it_lasts_and_counted_anew_after_it_ends() {
        let t0 = Instant::now();
        let at = |s: u64| t0 + Duration::from_secs(s);
        let mut r = WaitingReminder::new(Duration::from_secs(30), t0);
        assert_eq!(r.check(true, at(29)), None);
        assert_eq!(r.check(true, at(31)), Some(31));
        assert_eq!(r.check(true, at(59)), None, "said once a period");
        assert_eq!(r.check(true, at(60)), Some(60));
        assert_eq!(r.check(false, at(70)), None);
        assert_eq!(r.check(true, at(95)), None, "counted from the lack's end");
        assert_eq!(r.check(true, at(100)), Some(30));
    }
}
