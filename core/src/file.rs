//! Whole-file reads and writes whose errors name the file, for every reader
//! and writer of the crate.

use std::fs::File;
use std::path::{Path, PathBuf};

/// Opening, reading or writing a file failed; the message starts with the path.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct FileError {
    /// The file.
    pub path: PathBuf,
    /// The OS error.
    #[source]
    pub source: std::io::Error,
}

impl FileError {
    /// The error `source` met on `path`.
    pub fn new(path: &Path, source: std::io::Error) -> Self {
        FileError {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// The whole file.
pub fn read(path: &Path) -> Result<Vec<u8>, FileError> {
    std::fs::read(path).map_err(|e| FileError::new(path, e))
}

/// Writes `bytes` as the whole file.
pub fn write(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), FileError> {
    std::fs::write(path, bytes).map_err(|e| FileError::new(path, e))
}

/// Opens the file for reading.
pub fn open(path: &Path) -> Result<File, FileError> {
    File::open(path).map_err(|e| FileError::new(path, e))
}

/// Creates (or truncates) the file for writing.
pub fn create(path: &Path) -> Result<File, FileError> {
    File::create(path).map_err(|e| FileError::new(path, e))
}

/// The entries of a directory.
pub fn read_dir(path: &Path) -> Result<std::fs::ReadDir, FileError> {
    std::fs::read_dir(path).map_err(|e| FileError::new(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_names_the_file() {
        let p = Path::new("/nonexistent/skyground/x.ply");
        let e = read(p).unwrap_err();
        assert_eq!(e.path, p);
        assert!(
            e.to_string().starts_with("/nonexistent/skyground/x.ply: "),
            "{e}"
        );
        assert_eq!(e.source.kind(), std::io::ErrorKind::NotFound);
    }
}
