//! The files × commands table (Markdown): each cell ok, a clear error with
//! its message, or the failure; totals below.

use std::collections::BTreeMap;

use super::plan::{COMMANDS, DEMO_TIMEOUT_S};
use super::run::Done;
use super::verdict::Verdict;

/// The table, with the counts and the wall time of the whole run.
pub fn markdown(results: &[Done], wall_s: f64, cpu_s: Option<f64>) -> String {
    let mut rows: BTreeMap<String, BTreeMap<&str, String>> = BTreeMap::new();
    let (mut ok, mut clear, mut failed) = (0, 0, 0);
    for r in results {
        let cell = match &r.verdict {
            Verdict::Ok => {
                ok += 1;
                "ok".to_string()
            }
            Verdict::Stopped => {
                ok += 1;
                format!("ok: stopped at --timeout {DEMO_TIMEOUT_S} s, report written")
            }
            Verdict::ClearError(m) => {
                clear += 1;
                format!("error: {}", short(m, r))
            }
            Verdict::Fail(kind, why) => {
                failed += 1;
                format!("**FAIL {kind:?}**: {}", short(why, r))
            }
        };
        rows.entry(file_name(r))
            .or_default()
            .insert(r.job.command.name(), cell);
    }
    let mut s = String::from("| file |");
    for c in COMMANDS {
        s.push_str(&format!(" {} |", c.name()));
    }
    s.push_str("\n|---|");
    s.push_str(&"---|".repeat(COMMANDS.len()));
    s.push('\n');
    for (name, cells) in &rows {
        s.push_str(&format!("| {name} |"));
        for c in COMMANDS {
            let cell = cells.get(c.name()).map_or("", String::as_str);
            s.push_str(&format!(" {} |", cell.replace('|', "\\|")));
        }
        s.push('\n');
    }
    let slowest = results.iter().map(|r| r.seconds).fold(0.0, f64::max);
    let cpu = cpu_s.map_or_else(String::new, |c| format!(", {c:.0} CPU-s in the commands"));
    s.push_str(&format!(
        "\n{} files, {} runs: {ok} ok, {clear} clear errors, {failed} failures (panics, aborts, hangs, partial outputs, unclear errors, bad outputs); {wall_s:.0} s wall{cpu}, slowest run {slowest:.1} s\n",
        rows.len(),
        results.len()
    ));
    s
}

/// The message without the path the CLI puts before the file name (the row
/// names the file), cut to a cell's length.
fn short(m: &str, r: &Done) -> String {
    let full = r.job.file.display().to_string();
    let m = m.replace(&full, &file_name(r));
    let cut: String = m.chars().take(160).collect();
    if cut.len() < m.len() {
        format!("{cut}…")
    } else {
        cut
    }
}

/// The run's input file name, without its folder.
fn file_name(r: &Done) -> String {
    r.job
        .file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
