//! Where the demo's time and memory go: stage wall times, and each process's
//! CPU seconds and peak resident memory read from /proc while it runs.

use std::collections::BTreeMap;
use std::time::Instant;

use serde_json::{Value, json};

/// One process's figures at one moment.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ProcFigures {
    /// User + system CPU seconds so far.
    pub cpu_s: f64,
    /// Peak resident memory so far (VmHWM), MiB.
    pub peak_rss_mib: f64,
}

/// Reads a process's CPU seconds and peak resident memory; `None` when it
/// has gone or /proc is not there (not Linux).
pub fn read_proc(pid: u32) -> Option<ProcFigures> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    Some(ProcFigures {
        cpu_s: cpu_seconds(&stat)?,
        peak_rss_mib: peak_rss_mib(&status)?,
    })
}

/// Clock ticks per second of /proc/PID/stat's times: 100 on every Linux
/// configuration a user-space program can see (USER_HZ).
const TICKS_PER_S: f64 = 100.0;

/// utime + stime of a /proc/PID/stat line, in seconds.
fn cpu_seconds(stat: &str) -> Option<f64> {
    // The command name (field 2) may hold spaces: count fields after its ')'.
    let rest = &stat[stat.rfind(')')? + 1..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // Fields 14 and 15 of the line are 12 and 13 after the name.
    let utime: f64 = f.get(11)?.parse().ok()?;
    let stime: f64 = f.get(12)?.parse().ok()?;
    Some((utime + stime) / TICKS_PER_S)
}

/// VmHWM of a /proc/PID/status text, MiB.
fn peak_rss_mib(status: &str) -> Option<f64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// The mission's profile: named stages in order, and the last figures seen
/// of each process (kept after it exits).
#[derive(Debug)]
pub struct Profile {
    start: Instant,
    stage: (String, Instant),
    stages: Vec<(String, f64)>,
    /// Per name: the figures so far (CPU summed over respawns), the pid
    /// last read, and that pid's own CPU seconds at that read.
    procs: BTreeMap<String, (ProcFigures, u32, f64)>,
}

impl Profile {
    /// Starts the clock with a first stage.
    pub fn new(first_stage: &str) -> Self {
        let now = Instant::now();
        Self {
            start: now,
            stage: (first_stage.to_string(), now),
            stages: Vec::new(),
            procs: BTreeMap::new(),
        }
    }

    /// Ends the current stage and starts `name` (nothing when it is the current one).
    pub fn stage(&mut self, name: &str) {
        if self.stage.0 == name {
            return;
        }
        let now = Instant::now();
        let (prev, since) = std::mem::replace(&mut self.stage, (name.to_string(), now));
        self.stages.push((prev, (now - since).as_secs_f64()));
    }

    /// Samples a process (by the name it is reported under).
    pub fn sample(&mut self, name: &str, pid: Option<u32>) {
        let Some((pid, f)) = pid.and_then(|p| Some((p, read_proc(p)?))) else {
            return;
        };
        let (e, seen, last) =
            self.procs
                .entry(name.to_string())
                .or_insert((ProcFigures::default(), pid, 0.0));
        // A respawned process starts from zero: its predecessors' CPU stays
        // in the total, and each read adds what this pid used since the last.
        if *seen != pid {
            (*seen, *last) = (pid, 0.0);
        }
        e.cpu_s += (f.cpu_s - *last).max(0.0);
        *last = f.cpu_s;
        e.peak_rss_mib = e.peak_rss_mib.max(f.peak_rss_mib);
    }

    /// The profile as JSON: stages (the current one up to now), processes,
    /// total CPU and the sum of peak memories (an upper bound of the whole
    /// mission's peak: the processes do not all peak at once).
    pub fn to_json(&self) -> Value {
        let stages = self.stages_so_far();
        let (cpu, rss) = self.totals();
        json!({
            "wall_s": self.start.elapsed().as_secs_f64(),
            "stages": stages.iter().map(|(n, s)| json!({"stage": n, "wall_s": s})).collect::<Vec<_>>(),
            "processes": self.procs.iter().map(|(n, (f, _, _))| json!({"process": n, "cpu_s": f.cpu_s, "peak_rss_mib": f.peak_rss_mib})).collect::<Vec<_>>(),
            "cpu_s_total": cpu,
            "peak_rss_mib_sum": rss,
        })
    }

    /// A table for the terminal and report.md.
    pub fn to_markdown(&self) -> String {
        let mut s = String::from("| stage | wall s |\n|---|---|\n");
        for (name, wall) in self.stages_so_far() {
            s += &format!("| {name} | {wall:.1} |\n");
        }
        s += "\n| process | CPU s | peak RSS MiB |\n|---|---|---|\n";
        for (n, (f, _, _)) in &self.procs {
            s += &format!("| {n} | {:.1} | {:.0} |\n", f.cpu_s, f.peak_rss_mib);
        }
        let (cpu, rss) = self.totals();
        s += &format!("| all | {cpu:.1} | {rss:.0} (sum of peaks) |\n");
        s
    }

    /// The finished stages and the current one up to now.
    fn stages_so_far(&self) -> Vec<(String, f64)> {
        let mut stages = self.stages.clone();
        stages.push((self.stage.0.clone(), self.stage.1.elapsed().as_secs_f64()));
        stages
    }

    /// CPU seconds and peak memories (MiB) summed over the processes.
    fn totals(&self) -> (f64, f64) {
        let cpu = self.procs.values().map(|(f, _, _)| f.cpu_s).sum();
        let rss = self.procs.values().map(|(f, _, _)| f.peak_rss_mib).sum();
        (cpu, rss)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_with_spaces_in_the_name() {
        let stat = "42 (my node) S 1 42 42 0 -1 4194304 100 0 0 0 250 50 0 0 20 0 1 0 100 1000 10";
        assert_eq!(cpu_seconds(stat), Some(3.0));
    }

    #[test]
    fn status_peak_memory() {
        let status = "Name:\tx\nVmPeak:\t 9000 kB\nVmHWM:\t    2048 kB\nVmRSS:\t 1024 kB\n";
        assert_eq!(peak_rss_mib(status), Some(2.0));
        assert_eq!(peak_rss_mib("Name: x\n"), None);
    }

    #[test]
    fn own_process_is_read() {
        let f = read_proc(std::process::id()).expect("/proc/self");
        assert!(f.peak_rss_mib > 0.0);
    }

    #[test]
    fn stages_in_order_and_respawn_adds_up() {
        let mut p = Profile::new("a");
        p.stage("b");
        p.stage("b");
        let v = p.to_json();
        let names: Vec<&str> = v["stages"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["stage"].as_str().unwrap())
            .collect();
        assert_eq!(names, ["a", "b"]);
        let before = ProcFigures {
            cpu_s: 5.0,
            peak_rss_mib: 10.0,
        };
        // An earlier pid of the same node: its 5 s stay, once.
        p.procs.insert("n".into(), (before, u32::MAX, 0.0));
        p.sample("n", Some(std::process::id()));
        let once = p.procs["n"].0.cpu_s;
        p.sample("n", Some(std::process::id()));
        assert!(once >= 5.0 && p.procs["n"].0.cpu_s < once + 1.0);
        assert!(p.procs["n"].0.peak_rss_mib >= 10.0);
    }
}
