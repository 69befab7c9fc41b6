//! The conformance suite: other projects' test files
//! (`../shared/data/conformance`, `SKYGROUND_CONFORMANCE_DATA` overrides)
//! through every `skyground` command that applies to each. Every run must
//! end ok (exit 0, outputs that check out) or with a clear error (names the
//! file and the cause, leaves any earlier output as it was and writes
//! nothing); a panic, an abort (a failed allocation under the memory
//! limit), a hang, a partial file or an unclear message fails the test.
//! Files are found by listing the folder: a file dropped there is run with
//! no code. The files × commands table goes to `SKYGROUND_CONFORMANCE_TABLE`
//! (default `target/tmp/conformance/table.md`); tests/run_all.sh prints it.
//! Absent folder → `SKIPPED: ...`, the test passes.

mod checks;
mod plan;
mod run;
mod table;
mod verdict;

use std::path::PathBuf;

use plan::commands_for;
use verdict::Verdict;

fn data_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("SKYGROUND_CONFORMANCE_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/conformance"),
        PathBuf::from,
    );
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED: ../shared/data/conformance not found (looked in {})",
            dir.display()
        );
        None
    }
}

/// The folder's files, README aside (only those whose name contains
/// `SKYGROUND_CONFORMANCE_ONLY`, when set: to rerun one file).
fn corpus(dir: &std::path::Path) -> Vec<PathBuf> {
    let only = std::env::var("SKYGROUND_CONFORMANCE_ONLY").unwrap_or_default();
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .filter(|p| {
            !p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("README"))
        })
        .filter(|p| p.to_string_lossy().contains(&only))
        .collect();
    files.sort();
    files
}

/// CPU seconds of every reaped child (each run, and what it reaped in
/// turn: the demo's nodes), from /proc/self/stat (`cutime`, `cstime`, in
/// clock ticks of 1/100 s on Linux); `None` where it cannot be read.
fn children_cpu_s() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised name: state is field 3, cutime 16, cstime 17.
    let rest = stat.rsplit_once(')')?.1;
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| f.get(i - 3).and_then(|v| v.parse::<f64>().ok());
    Some((ticks(16)? + ticks(17)?) / 100.0)
}

#[test]
fn every_command_on_every_conformance_file() {
    let Some(dir) = data_dir() else { return };
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("conformance");
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).expect("scratch directory");
    let jobs: Vec<run::Job> = corpus(&dir)
        .into_iter()
        .flat_map(|f| commands_for(&f).into_iter().map(move |c| (f.clone(), c)))
        .map(|(file, command)| run::Job { file, command })
        .collect();
    assert!(!jobs.is_empty(), "{}: no files", dir.display());
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_skyground"));
    let started = std::time::Instant::now();
    let results = run::all(&bin, &root, jobs);
    let wall = started.elapsed().as_secs_f64();
    let text = table::markdown(&results, wall, children_cpu_s());
    let path = std::env::var_os("SKYGROUND_CONFORMANCE_TABLE")
        .map_or_else(|| root.join("table.md"), PathBuf::from);
    std::fs::write(&path, &text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    println!("{text}");
    let failed: Vec<String> = results
        .iter()
        .filter_map(|r| match &r.verdict {
            Verdict::Fail(kind, why) => Some(format!(
                "{} {}: {kind:?}: {why}",
                r.job.file.display(),
                r.job.command.name()
            )),
            _ => None,
        })
        .collect();
    assert!(
        failed.is_empty(),
        "{} of {} runs failed (table: {}):\n{}",
        failed.len(),
        results.len(),
        path.display(),
        failed.join("\n")
    );
}
