//! /cloud_stats: what cloud_inspector says about each cloud it received,
//! typed like the mission's other statuses (see [`super::protocol`]).

use std::fmt;
use std::str::FromStr;

use super::protocol::{ERROR, OK, ProtocolError, Wire, join};
use crate::cloud::Cloud;

/// How many points carry one class label.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LabelCount {
    /// The class (LAS code).
    pub label: u8,
    /// Points with it.
    pub count: usize,
}

impl fmt::Display for LabelCount {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.label, self.count)
    }
}

impl FromStr for LabelCount {
    type Err = ();

    fn from_str(s: &str) -> Result<Self, ()> {
        let (l, n) = s.split_once(':').ok_or(())?;
        Ok(LabelCount {
            label: l.trim().parse().map_err(|_| ())?,
            count: n.trim().parse().map_err(|_| ())?,
        })
    }
}

/// A cloud that decoded: its size, columns, classes and stamp.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CloudSummary {
    /// Points kept.
    pub points: usize,
    /// Points dropped for a non-finite coordinate.
    pub dropped_non_finite: usize,
    /// The message's field names, in order.
    pub fields: Vec<String>,
    /// Points per class present (empty without a label column).
    pub labels: Vec<LabelCount>,
    /// Header stamp: seconds.
    pub stamp_sec: i32,
    /// Header stamp: nanoseconds.
    pub stamp_nanosec: u32,
}

impl CloudSummary {
    /// The summary of `cloud` as decoded from a message with `fields`.
    pub fn of(cloud: &Cloud, dropped_non_finite: usize, fields: Vec<String>) -> Self {
        let labels = cloud
            .label_histogram()
            .map(|h| {
                (0u8..=255)
                    .zip(h)
                    .filter(|(_, n)| *n > 0)
                    .map(|(label, count)| LabelCount { label, count })
                    .collect()
            })
            .unwrap_or_default();
        CloudSummary {
            points: cloud.len(),
            dropped_non_finite,
            fields,
            labels,
            ..CloudSummary::default()
        }
    }
}

/// One /cloud_stats status (named after the topic inspected): a cloud's
/// summary, or why it was rejected.
#[derive(Debug, Clone, PartialEq)]
pub struct CloudStatus {
    /// The topic inspected.
    pub topic: String,
    /// The summary, or the decoder's reason for rejecting the cloud.
    pub result: Result<CloudSummary, String>,
}

impl CloudStatus {
    /// As it goes on the wire (level ERROR for a rejected cloud).
    pub fn to_wire(&self) -> Wire {
        let s = match &self.result {
            Err(reason) => return Wire::new(ERROR, &self.topic, reason.clone()),
            Ok(s) => s,
        };
        let mut w = Wire::new(OK, &self.topic, "ok");
        w.put("points", s.points);
        w.put("dropped_non_finite", s.dropped_non_finite);
        w.put("fields", s.fields.join(","));
        w.put("labels", join(&s.labels, ","));
        w.put("stamp_sec", s.stamp_sec);
        w.put("stamp_nanosec", s.stamp_nanosec);
        w
    }

    /// Read from the wire.
    pub fn from_wire(w: &Wire) -> Result<Self, ProtocolError> {
        let result = if w.level == OK {
            Ok(CloudSummary {
                points: w.get("points")?,
                dropped_non_finite: w.get("dropped_non_finite")?,
                fields: w.list("fields", ',')?,
                labels: w.list("labels", ',')?,
                stamp_sec: w.get("stamp_sec")?,
                stamp_nanosec: w.get("stamp_nanosec")?,
            })
        } else {
            Err(w.message.clone())
        };
        Ok(CloudStatus {
            topic: w.name.clone(),
            result,
        })
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    prop_compose! {
        fn summary()(
            points in 0usize..10_000_000, dropped in 0usize..1000,
            fields in prop::collection::vec("[a-z_]{1,12}", 0..6),
            labels in prop::collection::vec((any::<u8>(), 1usize..1_000_000), 0..8),
            stamp_sec in any::<i32>(), stamp_nanosec in 0u32..1_000_000_000,
        ) -> CloudSummary {
            CloudSummary {
                points, dropped_non_finite: dropped, fields,
                labels: labels.into_iter().map(|(label, count)| LabelCount { label, count }).collect(),
                stamp_sec, stamp_nanosec,
            }
        }
    }

    proptest! {
        #[test]
        fn cloud_status_round_trips(
            result in prop_oneof![summary().prop_map(Ok), "[a-z][a-z :]{0,30}".prop_map(Err)],
        ) {
            let s = CloudStatus { topic: "/aerial_cloud".into(), result };
            prop_assert_eq!(CloudStatus::from_wire(&s.to_wire()), Ok(s));
        }
    }

    #[test]
    fn summary_counts_classes_and_bad_labels_are_errors() {
        let mut cloud = Cloud::from_xyz(vec![[0.0; 3]; 5]);
        cloud.label = Some(vec![2, 6, 6, 2, 6]);
        let s = CloudSummary::of(&cloud, 1, vec!["x".into()]);
        let counts: Vec<_> = s.labels.iter().map(|c| (c.label, c.count)).collect();
        assert_eq!((s.points, counts), (5, vec![(2, 2), (6, 3)]));
        let mut w = CloudStatus {
            topic: "/t".into(),
            result: Ok(s),
        }
        .to_wire();
        w.values[3].1 = "2:two".into();
        assert!(matches!(
            CloudStatus::from_wire(&w),
            Err(ProtocolError::Bad { key: "labels", .. })
        ));
    }
}
