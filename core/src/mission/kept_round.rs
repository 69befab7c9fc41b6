//! The target set of the round being driven, kept in a file beside the
//! planner's status, so that a resumed mission finishes the round a kill
//! interrupted instead of planning a new one from a later detection.

use serde::{Deserialize, Serialize};

use crate::targets::TargetSet;

use super::protocol::{KeptStatusError, Phase, PlannerStatus};

/// A round's targets as the planner took them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KeptRound {
    /// The round, as the planner counted it.
    pub round: u32,
    /// The stamp both halves of the set carried.
    pub stamp: u64,
    /// The targets.
    pub targets: TargetSet,
}

impl KeptRound {
    /// Whether `status` was driving this round and had not finished it
    /// (same round, same target counts, route not done).
    pub fn unfinished_in(&self, status: &PlannerStatus) -> bool {
        status.round == self.round
            && status.phase != Phase::Done.word()
            && status.target_points == self.targets.points.len()
            && status.target_regions == self.targets.regions.len()
    }

    /// Keeps it in `path` as JSON, atomically (a kill leaves the last whole one).
    pub fn keep(&self, path: &std::path::Path) -> Result<(), KeptStatusError> {
        let json = serde_json::to_vec(self).map_err(|e| KeptStatusError::Round {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        Ok(crate::file::write(path, json)?)
    }

    /// The round kept in `path`; `None` when there is no such file.
    pub fn kept(path: &std::path::Path) -> Result<Option<KeptRound>, KeptStatusError> {
        if !path.is_file() {
            return Ok(None);
        }
        let bytes = crate::file::read(path)?;
        serde_json::from_slice(&bytes)
            .map(Some)
            .map_err(|e| KeptStatusError::Round {
                path: path.to_path_buf(),
                reason: e.to_string(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::targets::TargetPoint;

    #[test]
    fn a_kept_round_reads_back_and_a_bad_file_is_named() {
        let dir = std::env::temp_dir().join(format!("skyground-kept-round-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("round.json");
        assert!(KeptRound::kept(&path).unwrap().is_none());
        let k = KeptRound {
            round: 2,
            stamp: 77,
            targets: TargetSet {
                points: vec![TargetPoint {
                    xyz: [1.0, 2.0, 0.0],
                    building: 3,
                }],
                regions: Vec::new(),
            },
        };
        k.keep(&path).unwrap();
        assert_eq!(KeptRound::kept(&path).unwrap(), Some(k));
        std::fs::write(&path, b"{\"round\": 1}").unwrap();
        let e = KeptRound::kept(&path).unwrap_err().to_string();
        assert!(
            e.contains("round.json") && e.contains("round's targets"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
