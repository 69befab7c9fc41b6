//! Reading and writing a cloud file, choosing the format by extension.

use std::io::{BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

use super::Cloud;
use super::las::{
    LasError, Relabel, UnreadableCrs, read_las_bounds, read_las_with, relabel_las, write_las,
};
use super::ply::{PlyError, parse_ply, write_ply};
use crate::file::{self, FileError};

/// Reading or writing a cloud file failed; the message starts with the path.
#[derive(Debug, thiserror::Error)]
pub enum CloudIoError {
    /// The extension is not `.las`, `.laz` or `.ply` (any case).
    #[error("{}: unknown point cloud extension (expected .las, .laz or .ply)", path.display())]
    UnknownExtension {
        /// The file.
        path: PathBuf,
    },
    /// Opening, reading or writing the file failed.
    #[error(transparent)]
    Io(#[from] FileError),
    /// The file exists but holds no bytes.
    #[error("{}: file is empty", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// The PLY reader or writer failed.
    #[error("{}: {source}", path.display())]
    Ply {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: PlyError,
    },
    /// The LAS/LAZ reader or writer failed.
    #[error("{}: {source}", path.display())]
    Las {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: LasError,
    },
}

impl CloudIoError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            Self::Io(e) => &e.path,
            Self::UnknownExtension { path }
            | Self::Empty { path }
            | Self::Ply { path, .. }
            | Self::Las { path, .. } => path,
        }
    }

    /// The file's CRS records are malformed (not merely geographic): its
    /// points read with [`UnreadableCrs::Skip`].
    pub fn is_unreadable_crs(&self) -> bool {
        matches!(self, Self::Las { source: LasError::Crs(e), .. } if e.is_malformed())
    }
}

/// File formats we know, by extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Ply,
    Las,
    Laz,
}

fn kind(path: &Path) -> Result<Kind, CloudIoError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("ply") => Ok(Kind::Ply),
        Some("las") => Ok(Kind::Las),
        Some("laz") => Ok(Kind::Laz),
        _ => Err(CloudIoError::UnknownExtension { path: path.into() }),
    }
}

/// Reads a `.ply`, `.las` or `.laz` file (extension case-insensitive).
pub fn read_cloud(path: &Path) -> Result<Cloud, CloudIoError> {
    read_cloud_with(path, UnreadableCrs::Fail)
}

/// [`read_cloud`], with CRS records it cannot make out failing or skipped.
pub fn read_cloud_with(path: &Path, unreadable: UnreadableCrs) -> Result<Cloud, CloudIoError> {
    let kind = kind(path)?;
    let io = |source| FileError::new(path, source);
    let mut file = file::open(path)?;
    let len = file.metadata().map_err(io)?.len();
    if len == 0 {
        return Err(CloudIoError::Empty { path: path.into() });
    }
    match kind {
        Kind::Ply => {
            let mut data = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
            file.read_to_end(&mut data).map_err(io)?;
            parse_ply(&data).map_err(|source| CloudIoError::Ply {
                path: path.into(),
                source,
            })
        }
        Kind::Las | Kind::Laz => {
            read_las_with(BufReader::new(file), unreadable).map_err(|source| CloudIoError::Las {
                path: path.into(),
                source,
            })
        }
    }
}

/// The file's bounding box as a cloud of its two corners (frame, CRS and
/// metres as [`read_cloud`] gives them): a LAS/LAZ header alone, a file
/// whose header has no usable bounds (and any PLY) read whole.
pub fn read_bounds(path: &Path) -> Result<Cloud, CloudIoError> {
    read_bounds_with(path, UnreadableCrs::Fail)
}

/// [`read_bounds`], with CRS records it cannot make out failing or skipped.
pub fn read_bounds_with(path: &Path, unreadable: UnreadableCrs) -> Result<Cloud, CloudIoError> {
    if matches!(kind(path)?, Kind::Las | Kind::Laz) {
        let file = file::open(path)?;
        let bounds = read_las_bounds(BufReader::new(file), unreadable).map_err(|source| {
            CloudIoError::Las {
                path: path.into(),
                source,
            }
        })?;
        if let Some(b) = bounds {
            return Ok(b);
        }
    }
    let c = read_cloud_with(path, unreadable)?;
    let corners = c.bounds().map_or_else(Vec::new, |(lo, hi)| vec![lo, hi]);
    Ok(Cloud {
        xyz: corners,
        origin: c.origin,
        crs: c.crs,
        ..Cloud::default()
    })
}

/// Writes `cloud` as binary PLY, LAS or LAZ according to the extension
/// (atomically: an error leaves an earlier file at `path` as it was).
pub fn write_cloud(path: &Path, cloud: &Cloud) -> Result<(), CloudIoError> {
    let kind = kind(path)?;
    let io = |source| FileError::new(path, source);
    file::write_with(path, |file| match kind {
        Kind::Ply => write_ply(file, cloud).map_err(|source| CloudIoError::Ply {
            path: path.into(),
            source,
        }),
        Kind::Las | Kind::Laz => {
            let las = |source| CloudIoError::Las {
                path: path.into(),
                source,
            };
            let mut sink =
                write_las(BufWriter::new(file), cloud, kind == Kind::Laz).map_err(las)?;
            Ok(sink.flush().map_err(io)?)
        }
    })
}

/// Writes `cloud`'s labels as the classes of a copy of the LAS/LAZ
/// `sources` it was read from (in order, one class per point) to `path`
/// (LAS or LAZ by its extension): every other field of the points and the
/// first source's header and records stay (see [`relabel_las`] for when the
/// version and point format change). `Ok(false)`, with nothing written,
/// when a source or `path` is not LAS/LAZ: write the cloud with
/// [`write_cloud`] instead. A first source without CRS records gets the
/// cloud's CRS (the user's `--crs`). Atomic: a failure leaves an earlier
/// file at `path` as it was.
pub fn relabel_files(
    sources: &[PathBuf],
    path: &Path,
    cloud: &Cloud,
) -> Result<bool, CloudIoError> {
    let las_like = |k: Kind| matches!(k, Kind::Las | Kind::Laz);
    let out_kind = kind(path)?;
    for s in sources {
        if !las_like(kind(s)?) {
            return Ok(false);
        }
    }
    if !las_like(out_kind) {
        return Ok(false);
    }
    let mut readers = Vec::with_capacity(sources.len());
    for s in sources {
        readers.push(BufReader::new(file::open(s)?));
    }
    let most = |c: &Option<Vec<u8>>| c.iter().flatten().copied().max().unwrap_or(0);
    let how = Relabel {
        labels: cloud.label.as_deref().unwrap_or_default(),
        max_return: most(&cloud.return_number).max(most(&cloud.number_of_returns)),
        compressed: out_kind == Kind::Laz,
        stated: cloud.crs.as_ref(),
    };
    // Written beside and renamed at the end: `path` may be one of the
    // sources (still being read), and a failure leaves no half file there.
    file::write_with(path, |file| {
        let las = |source| CloudIoError::Las {
            path: path.into(),
            source,
        };
        let mut sink = relabel_las(readers, BufWriter::new(file), &how).map_err(las)?;
        sink.flush().map_err(|e| FileError::new(path, e))?;
        Ok::<(), CloudIoError>(())
    })?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh directory per test (tests run in parallel).
    fn scratch_dir(test: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("skyground-io-{}-{test}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn cloud() -> Cloud {
        Cloud {
            xyz: vec![[1.0, 2.0, 3.0], [4.5, 5.5, 6.5]],
            intensity: Some(vec![10.0, 20.0]),
            label: Some(vec![2, 6]),
            building: Some(vec![0, 42]),
            return_number: None,
            number_of_returns: None,
            origin: [637_000.0, 849_000.0, 0.0],
            crs: None,
        }
    }

    #[test]
    fn round_trips_by_extension_in_any_case() {
        let dir = scratch_dir("round_trip");
        for name in ["a.ply", "b.LAS", "c.Laz"] {
            let path = dir.join(name);
            write_cloud(&path, &cloud()).unwrap();
            let back = read_cloud(&path).unwrap();
            assert_eq!(back.label, cloud().label, "{name}");
            assert_eq!(back.building, cloud().building, "{name}");
            assert_eq!(back.origin, cloud().origin, "{name}");
            assert_eq!(back.xyz, cloud().xyz, "{name}");
        }
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn errors_name_the_file_and_the_cause() {
        let dir = scratch_dir("errors");
        let scratch = |name: &str| dir.join(name);
        let missing = scratch("missing.ply");
        let e = read_cloud(&missing).unwrap_err();
        assert!(matches!(e, CloudIoError::Io(_)), "{e:?}");
        assert_eq!(e.path(), missing);
        assert!(
            e.to_string().starts_with(&missing.display().to_string()),
            "{e}"
        );

        let e = read_cloud(Path::new("/x/y.xyz")).unwrap_err();
        assert!(matches!(e, CloudIoError::UnknownExtension { .. }), "{e}");
        assert!(write_cloud(Path::new("/x/noext"), &cloud()).is_err());

        let empty = scratch("empty.las");
        std::fs::write(&empty, b"").unwrap();
        let e = read_cloud(&empty).unwrap_err();
        assert_eq!(e.to_string(), format!("{}: file is empty", empty.display()));

        let ply = scratch("short.ply");
        let mut data = b"ply\nformat binary_little_endian 1.0\nelement vertex 100\n\
            property float x\nproperty float y\nproperty float z\nend_header\n"
            .to_vec();
        data.extend_from_slice(&[0; 12 * 12 + 3]);
        std::fs::write(&ply, data).unwrap();
        let e = read_cloud(&ply).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "{}: truncated vertex data: element 'vertex' ends at index 12 of 100",
                ply.display()
            )
        );

        let las = scratch("corrupt.las");
        std::fs::write(&las, b"LASX not a las file at all").unwrap();
        let e = read_cloud(&las).unwrap_err();
        assert!(matches!(e, CloudIoError::Las { .. }), "{e:?}");
        assert!(e.to_string().starts_with(&las.display().to_string()), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
