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

/// Writes `bytes` as the whole file, atomically: to `PATH.part` first,
/// renamed over `path` once complete, so a failure leaves an earlier file
/// as it was and never a half-written one.
pub fn write(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), FileError> {
    let part = part_path(path);
    let written = std::fs::write(&part, bytes).map_err(|e| FileError::new(&part, e));
    commit(written, &part, path)
}

/// Where a file is written before it is renamed into place: `PATH.part`.
pub fn part_path(path: &Path) -> PathBuf {
    let mut part = path.as_os_str().to_owned();
    part.push(".part");
    PathBuf::from(part)
}

/// Writes the file through `fill` at `PATH.part`, renamed over `path` when
/// `fill` succeeds; on any error the part file is removed and `path` is as
/// it was. `fill` gets the open file (wrap it in a `BufWriter` and flush).
pub fn write_with<T, E: From<FileError>>(
    path: &Path,
    fill: impl FnOnce(File) -> Result<T, E>,
) -> Result<T, E> {
    let part = part_path(path);
    let filled = create(&part).map_err(E::from).and_then(fill);
    match filled {
        Ok(v) => commit(Ok(()), &part, path).map(|()| v).map_err(E::from),
        Err(e) => {
            let _ = std::fs::remove_file(&part);
            Err(e)
        }
    }
}

/// Renames `part` over `path` after a successful write; removes it otherwise.
fn commit(written: Result<(), FileError>, part: &Path, path: &Path) -> Result<(), FileError> {
    let renamed =
        written.and_then(|()| std::fs::rename(part, path).map_err(|e| FileError::new(path, e)));
    if renamed.is_err() {
        let _ = std::fs::remove_file(part);
    }
    renamed
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
    fn a_failed_write_leaves_the_earlier_file_and_no_part() {
        let dir = std::env::temp_dir().join(format!("skyground-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("out.txt");
        write(&path, "earlier").unwrap();
        let failed: Result<(), FileError> = write_with(&path, |mut f| {
            std::io::Write::write_all(&mut f, b"half").unwrap();
            Err(FileError::new(
                &path,
                std::io::Error::other("the writer failed"),
            ))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "earlier");
        assert!(!part_path(&path).exists());
        write_with(&path, |mut f| {
            std::io::Write::write_all(&mut f, b"new").map_err(|e| FileError::new(&path, e))
        })
        .unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        write(&path, "newer").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "newer");
        assert!(!part_path(&path).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

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
