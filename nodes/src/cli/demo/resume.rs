//! Resuming: what a mission is and did so far, kept in its folder
//! (`command.json`, `progress.json`, beside the merge store), so that
//! `demo --resume DIR` goes on from it.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use skyground_core::mission::PlannerStatus;
use skyground_core::mission::kept_round::KeptRound;
use skyground_core::mission::progress::Totals;

use crate::runtime::RuntimeError;

/// The file in a mission's folder that holds its progress.
pub const PROGRESS_FILE: &str = "progress.json";

/// The file in a mission's folder that holds the planner's last status, for
/// a planner restarted while the mission runs and for a resumed run, which
/// finishes the round it was driving.
pub const PLANNER_FILE: &str = "planner.json";

/// The file in a mission's folder where the planner keeps its round's targets.
pub const ROUND_FILE: &str = "round.json";

/// The file in a mission's folder that holds its command line.
pub const COMMAND_FILE: &str = "command.json";

/// A mission's command line: every argument after `demo`, and the folder
/// they were given in (their relative paths' base).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct Command {
    pub argv: Vec<String>,
    pub cwd: Option<PathBuf>,
}

impl Command {
    /// This process's command line.
    pub fn now() -> Command {
        let all: Vec<String> = std::env::args().collect();
        let at = all
            .iter()
            .position(|s| s == "demo")
            .map_or(all.len(), |i| i + 1);
        Command {
            argv: all[at..].to_vec(),
            cwd: std::env::current_dir().ok(),
        }
    }

    /// The command line kept in `dir`; an error names the file.
    pub fn read(dir: &Path) -> Result<Command, String> {
        let path = dir.join(COMMAND_FILE);
        let bytes = skyground_core::file::read(&path)
            .map_err(|e| format!("--resume {e} (not a demo's output folder?)"))?;
        serde_json::from_slice(&bytes).map_err(|e| format!("--resume {}: {e}", path.display()))
    }

    /// Writes it into `dir`, atomically.
    pub fn write(&self, dir: &Path) -> Result<(), String> {
        let json = serde_json::to_vec_pretty(self).map_err(|e| e.to_string())?;
        skyground_core::file::write(&dir.join(COMMAND_FILE), json).map_err(|e| e.to_string())
    }
}

/// What a mission had done when its progress was last written: counted
/// over every run of it (the first and each resume).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub(super) struct Carried {
    /// Metres driven.
    pub odometer_m: f64,
    /// Robot (simulated) seconds.
    pub sim_s: f64,
    /// Rounds whose route was driven to its end.
    pub rounds: u32,
    /// The vehicle's last place, in the map frame.
    pub position: Option<[f32; 3]>,
    /// Runs of the mission so far (1: never resumed).
    pub runs: u32,
    /// Targets reached, given up, … over the finished rounds and the one
    /// being driven when the progress was written.
    #[serde(default)]
    pub targets: Totals,
    /// Of `targets`, the round being driven (a resumed run that finishes
    /// that round counts its stops again).
    #[serde(default)]
    pub open: Totals,
    /// The mean detected completeness (0–1) of the last detection, the one
    /// the round being driven was planned from: a resumed run that finishes
    /// that round measures its gain from it, not from the larger merge.
    #[serde(default)]
    pub planned_from: Option<f64>,
}

impl Carried {
    /// This run's figures added to what earlier runs carried.
    pub fn plus(
        &self,
        (odometer_m, sim_s): (f64, f64),
        rounds: u32,
        position: Option<[f32; 3]>,
        (targets, open): (&Totals, &Totals),
    ) -> Carried {
        Carried {
            odometer_m: self.odometer_m + odometer_m,
            sim_s: self.sim_s + sim_s,
            rounds: self.rounds + rounds,
            position: position.or(self.position),
            runs: self.runs,
            targets: self.targets.plus(targets),
            open: *open,
            planned_from: self.planned_from,
        }
    }

    /// What a run that finishes the interrupted round carries: that
    /// round's stops so far are counted again as it reports them.
    pub fn without_open_round(&self) -> Carried {
        Carried {
            targets: self.targets.minus(&self.open),
            open: Totals::default(),
            ..*self
        }
    }

    /// What a run that plans anew carries: no round's detection to go on from.
    pub fn planning_anew(&self) -> Carried {
        Carried {
            planned_from: None,
            ..*self
        }
    }
}

/// Before a resumed run: the round the kill interrupted (its status in
/// `planner.json`, its targets in `round.json`) renumbered as the run's first,
/// so its planner finishes that round's remaining stops rather than plan
/// one from a later detection. `Ok(None)`, both files removed, when no
/// round was being driven; an error names what could not be read.
pub(super) fn carry_round(dir: &Path) -> Result<Option<PlannerStatus>, String> {
    let (status_path, round_path) = (dir.join(PLANNER_FILE), dir.join(ROUND_FILE));
    let status = PlannerStatus::kept(&status_path).map_err(|e| e.to_string())?;
    let round = KeptRound::kept(&round_path).map_err(|e| e.to_string())?;
    let open = match (status, round) {
        (Some(s), Some(r)) if r.unfinished_in(&s) => Some((s, r)),
        _ => None,
    };
    let Some((mut s, mut r)) = open else {
        let _ = std::fs::remove_file(&status_path);
        let _ = std::fs::remove_file(&round_path);
        return Ok(None);
    };
    // The run's detections and rounds count from its start.
    (s.round, r.round) = (1, 1);
    s.keep(&status_path).map_err(|e| e.to_string())?;
    r.keep(&round_path).map_err(|e| e.to_string())?;
    Ok(Some(s))
}

/// What earlier runs of the mission in `dir` carried; an error names the file.
pub(super) fn read(dir: &Path) -> Result<Carried, RuntimeError> {
    let path = dir.join(PROGRESS_FILE);
    let err = |e: String| RuntimeError::Node(format!("--resume {}: {e}", path.display()));
    if !path.exists() {
        // Killed before the first progress was written: nothing driven yet.
        return Ok(Carried::default());
    }
    let bytes = skyground_core::file::read(&path).map_err(|e| err(e.to_string()))?;
    serde_json::from_slice(&bytes).map_err(|e| err(e.to_string()))
}

/// Writes the progress atomically (a kill leaves the last whole one).
pub(super) fn write(dir: &Path, c: &Carried) -> Result<(), String> {
    let json = serde_json::to_vec_pretty(c).map_err(|e| e.to_string())?;
    skyground_core::file::write(&dir.join(PROGRESS_FILE), json).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reached(reached: usize, given_up: usize) -> Totals {
        Totals {
            reached,
            given_up,
            ..Totals::default()
        }
    }

    #[test]
    fn progress_round_trips_and_adds_runs() {
        let d = std::env::temp_dir().join(format!("skyground-progress-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        assert_eq!(read(&d).unwrap(), Carried::default());
        let first = Carried {
            runs: 1,
            ..Carried::default()
        }
        .plus(
            (100.0, 50.0),
            1,
            Some([1.0, 2.0, 0.0]),
            (&reached(7, 1), &reached(2, 0)),
        );
        write(&d, &first).unwrap();
        let back = read(&d).unwrap();
        assert_eq!(back, first);
        assert_eq!(back.without_open_round().targets, reached(5, 1));
        let planned = Carried {
            planned_from: Some(0.9),
            ..back
        };
        assert_eq!(planned.without_open_round().planned_from, Some(0.9));
        assert_eq!(planned.planning_anew().planned_from, None);
        let second = back.plus((20.0, 5.0), 0, None, (&reached(3, 2), &reached(3, 2)));
        assert_eq!(
            (second.odometer_m, second.sim_s, second.rounds),
            (120.0, 55.0, 1)
        );
        assert_eq!(second.targets, reached(10, 3), "stops over both runs");
        assert_eq!(
            second.position,
            Some([1.0, 2.0, 0.0]),
            "the last known place stays"
        );
        std::fs::write(d.join(PROGRESS_FILE), b"[1]").unwrap();
        assert!(read(&d).unwrap_err().to_string().contains(PROGRESS_FILE));
        std::fs::remove_dir_all(&d).unwrap();
    }
}
