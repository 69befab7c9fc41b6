//! What a finished run means: ok (exit 0 and the outputs a user is told
//! of), a clear error (names the file, says what is wrong, leaves nothing
//! behind), or a failure of the suite (panic, abort, hang, partial output,
//! unclear error, missing or wrong output).

use std::path::{Path, PathBuf};

use super::checks;
use super::plan::{Command, EARLIER, Layout};

/// How one run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Exit 0 and the outputs check out.
    Ok,
    /// A demo the suite's short `--timeout` stopped, its report written.
    Stopped,
    /// A refusal that names the file and the cause; nothing left behind.
    ClearError(String),
    /// Anything else, with why.
    Fail(Failure, String),
}

/// The ways a run fails the suite.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Failure {
    /// "panicked at", exit 101.
    Panic,
    /// Killed by a signal (abort on a failed allocation, segfault).
    Abort,
    /// Still running at the time limit.
    Hang,
    /// A `.part` file, or a new or changed output after a failure.
    Partial,
    /// An error that does not name the file or says nothing a user can act on.
    Unclear,
    /// Exit 0 but an output is missing or wrong.
    BadOutput,
}

/// What the process did.
pub struct Outcome {
    /// Exit code (`None`: killed by a signal).
    pub code: Option<i32>,
    /// True when the time limit killed it.
    pub timed_out: bool,
    pub stdout: String,
    pub stderr: String,
}

/// Messages that name a cause nobody can act on (seen before, fixed since).
const UNCLEAR: [&str; 5] = [
    "failed to fill whole buffer",
    "capacity overflow",
    "nothing to draw",
    "memory allocation of",
    "Error when dropping",
];

/// The verdict on `command` run on `file` with `layout`.
pub fn judge(file: &Path, command: Command, layout: &Layout, o: &Outcome) -> Verdict {
    if o.timed_out {
        return Verdict::Fail(Failure::Hang, "killed at the time limit".into());
    }
    if o.stderr.contains("panicked at") || o.code == Some(101) {
        return Verdict::Fail(Failure::Panic, last_words(&o.stderr));
    }
    let Some(code) = o.code else {
        return Verdict::Fail(Failure::Abort, last_words(&o.stderr));
    };
    let parts = files_under(&layout.dir)
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "part"))
        .collect::<Vec<_>>();
    if let Some(p) = parts.first() {
        return Verdict::Fail(Failure::Partial, format!("left {}", p.display()));
    }
    if command == Command::Demo && code != 0 && o.stderr.contains("(--timeout)") {
        return match checks::outputs(file, command, layout, &o.stdout) {
            Ok(()) => Verdict::Stopped,
            Err(why) => Verdict::Fail(Failure::BadOutput, why),
        };
    }
    if code == 0 {
        return match checks::outputs(file, command, layout, &o.stdout) {
            Ok(()) => Verdict::Ok,
            Err(why) => Verdict::Fail(Failure::BadOutput, why),
        };
    }
    if let Err(why) = untouched(layout) {
        return Verdict::Fail(Failure::Partial, why);
    }
    clear_error(file, &o.stderr)
}

/// The error line(s) of stderr: those the CLI prints as `skyground CMD: …`,
/// else the last non-empty line.
pub fn last_words(stderr: &str) -> String {
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    let errors: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| l.starts_with("skyground ") || l.contains("panicked at"))
        .collect();
    let picked = if errors.is_empty() {
        lines.last().copied().unwrap_or_default().to_string()
    } else {
        errors.join(" / ")
    };
    picked.chars().take(400).collect()
}

/// A refusal is clear when it names the file and none of the known
/// meaningless causes.
fn clear_error(file: &Path, stderr: &str) -> Verdict {
    let words = last_words(stderr);
    let name = file.file_name().map(|n| n.to_string_lossy().into_owned());
    if !name.is_some_and(|n| words.contains(&n)) {
        return Verdict::Fail(Failure::Unclear, format!("does not name the file: {words}"));
    }
    if let Some(u) = UNCLEAR.iter().find(|u| words.contains(*u)) {
        return Verdict::Fail(Failure::Unclear, format!("`{u}`: {words}"));
    }
    Verdict::ClearError(words)
}

/// After a failure: the seeded output as it was and no other file written.
fn untouched(layout: &Layout) -> Result<(), String> {
    if let Some(seed) = &layout.seeded {
        match std::fs::read(seed) {
            Ok(b) if b == EARLIER => {}
            _ => return Err(format!("the earlier {} was changed", seed.display())),
        }
    }
    let written: Vec<PathBuf> = files_under(&layout.outputs)
        .into_iter()
        .filter(|p| Some(p) != layout.seeded.as_ref())
        .collect();
    match written.first() {
        None => Ok(()),
        Some(p) => Err(format!(
            "failed but wrote {} ({} files)",
            p.display(),
            written.len()
        )),
    }
}

/// Every file below `dir` (or `dir` itself when it is a file).
pub fn files_under(dir: &Path) -> Vec<PathBuf> {
    if dir.is_file() {
        return vec![dir.to_path_buf()];
    }
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                todo.push(p);
            } else {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}
