//! What the DDS integration tests that drive the real `skyground` binary share.

use std::path::PathBuf;
use std::process::{Child, Command};

/// The `skyground` binary under test (`SKYGROUND_BIN_DIR`, else the debug build).
pub fn bin() -> PathBuf {
    std::env::var_os("SKYGROUND_BIN_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/debug"))
        .join("skyground")
}

/// Sends `sig` (`-STOP`, `-CONT`, `-INT`) to `child`.
pub fn signal(child: &Child, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &child.id().to_string()])
        .status()
        .is_ok_and(|s| s.success());
    assert!(ok, "kill {sig} failed");
}
