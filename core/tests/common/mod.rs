//! What the integration tests share: where the real data is.

use std::path::PathBuf;

/// `name` in the real-data folder (`SKYGROUND_REAL_DATA`, else
/// `../shared/data/real`); `None`, said plainly, when the folder is absent.
pub fn real_file(name: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("SKYGROUND_REAL_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/real"),
        PathBuf::from,
    );
    if !dir.is_dir() {
        eprintln!(
            "SKIPPED: ../shared/data/real not found (looked in {})",
            dir.display()
        );
        return None;
    }
    Some(dir.join(name))
}
