//! The outside tools some commands need (the rclpy venv, `cjval`), checked
//! before they are used, with what to do when one is missing.

use std::path::Path;
use std::process::{Command, Stdio};

use super::RuntimeError;

/// How a user gets the rclpy venv (the test command makes it).
pub const VENV_HINT: &str = "run tests/setup_venv.sh from the repository root (it makes .venv with the pinned ros-kilted rclpy wheels from PyPI; tests/run_all.sh runs it too), or give --python a Python that imports rclpy";

/// Checks that `python` runs and imports every module of `modules`, for
/// `what` (the command that needs it).
pub fn require_python(python: &Path, modules: &[&str], what: &str) -> Result<(), RuntimeError> {
    let script = modules
        .iter()
        .map(|m| format!("import {m}"))
        .collect::<Vec<_>>()
        .join("; ");
    let run = Command::new(python)
        .args(["-c", &script])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output();
    let why = match run {
        Err(e) => format!("cannot run {}: {e}", python.display()),
        Ok(o) if o.status.success() => return Ok(()),
        Ok(o) => {
            let err = String::from_utf8_lossy(&o.stderr);
            let last = err.lines().last().unwrap_or("it failed").trim().to_string();
            format!(
                "{} cannot import {}: {last}",
                python.display(),
                modules.join(", ")
            )
        }
    };
    Err(RuntimeError::Node(format!(
        "{what} needs Python with {}: {why}; {VENV_HINT}",
        modules.join(", ")
    )))
}

/// Checks that the script `path` that `what` runs exists.
pub fn require_file(path: &Path, what: &str, flag: &str) -> Result<(), RuntimeError> {
    if path.is_file() {
        return Ok(());
    }
    Err(RuntimeError::Node(format!(
        "{what} needs {}, which does not exist here: run it from the repository root, or give {flag} PATH",
        path.display()
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_python_says_how_to_make_the_venv() {
        let e = require_python(
            Path::new("/nonexistent/.venv/bin/python"),
            &["rclpy"],
            "bench",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("bench needs Python with rclpy"), "{e}");
        assert!(e.contains("tests/setup_venv.sh"), "{e}");
    }

    #[test]
    fn a_python_without_the_module_names_it() {
        let e = require_python(Path::new("python3"), &["no_such_module_skyground"], "bench")
            .unwrap_err()
            .to_string();
        assert!(e.contains("cannot import no_such_module_skyground"), "{e}");
        assert!(e.contains("ModuleNotFoundError"), "{e}");
        assert!(require_python(Path::new("python3"), &["json"], "bench").is_ok());
    }

    #[test]
    fn a_missing_script_says_where_to_run_from() {
        let e = require_file(Path::new("/nonexistent/peer.py"), "bench", "--peer")
            .unwrap_err()
            .to_string();
        assert!(e.contains("repository root") && e.contains("--peer"), "{e}");
    }
}
