//! `--crs` and `--units`: the CRS or the unit of a cloud whose file states
//! none (or, for the unit, states it wrongly), shared by the subcommands
//! that read a cloud.

use std::path::{Path, PathBuf};

use skyground_core::cloud::{
    Cloud, CloudIoError, UnreadableCrs, read_bounds_with, read_cloud_with,
};
use skyground_core::crs::{Crs, LinearUnit, epsg_from_reference};
use skyground_core::prior::join_tiles;

use crate::runtime::RuntimeError;

/// The `--crs` and `--units` options.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct UnitsArg {
    /// The CRS of a cloud whose file states none (EPSG:28992, or its URN): outputs carry it, its unit applies. A file that states another CRS is an error (skyground does not reproject).
    #[arg(long, value_parser = parse_epsg)]
    pub crs: Option<u32>,
    /// The unit of a cloud whose file states none (m, ft, ftUS); overrides the file's.
    #[arg(long, value_parser = parse_unit)]
    pub units: Option<LinearUnit>,
}

impl UnitsArg {
    /// Reads the cloud at `path`, in `--crs` and `--units` when given.
    pub fn read(&self, path: &Path) -> Result<Cloud, RuntimeError> {
        let cloud = self.despite_bad_crs(read_cloud_with, path)?;
        self.taken_in(path, cloud)
    }

    /// The bounding box of the cloud at `path` (its two corners; a LAS/LAZ
    /// header alone), in `--crs` and `--units` when given.
    pub fn read_bounds(&self, path: &Path) -> Result<Cloud, RuntimeError> {
        let corners = self.despite_bad_crs(read_bounds_with, path)?;
        self.taken_in(path, corners)
    }

    /// `read` of `path`; where the file's CRS records cannot be read, its
    /// points all the same when `--crs` states the CRS (said on stderr),
    /// else an error that says how to state it.
    fn despite_bad_crs(
        &self,
        read: fn(&Path, UnreadableCrs) -> Result<Cloud, CloudIoError>,
        path: &Path,
    ) -> Result<Cloud, RuntimeError> {
        match read(path, UnreadableCrs::Fail) {
            Err(e) if e.is_unreadable_crs() => match self.crs {
                Some(code) => {
                    eprintln!(
                        "{e}: the records are left out, the file is taken in EPSG:{code} (--crs)"
                    );
                    read(path, UnreadableCrs::Skip).map_err(super::err)
                }
                None => Err(super::err(format!(
                    "{e} (state the file's CRS with --crs EPSG:N to read its points all the same)"
                ))),
            },
            read => read.map_err(super::err),
        }
    }

    /// `cloud` (read from `path`) in `--crs`, then `--units`, when given.
    fn taken_in(&self, path: &Path, mut cloud: Cloud) -> Result<Cloud, RuntimeError> {
        if let Some(code) = self.crs {
            let stated = Crs::from_epsg(code).map_err(|e| super::err(format!("--crs: {e}")))?;
            match &cloud.crs {
                Some(own) if own.epsg.is_some() || own.wkt.is_some() => {
                    // RD New is the same ground as RD New + NAP height.
                    let theirs = [own.epsg, own.horizontal_epsg()];
                    let same = [Some(code), stated.horizontal_epsg()]
                        .iter()
                        .any(|c| c.is_some() && theirs.contains(c));
                    if !same {
                        return Err(super::err(format!(
                            "{} states its CRS, {}; --crs EPSG:{code} names another (skyground does not reproject: leave --crs off, or reproject the file first)",
                            path.display(),
                            own.label()
                        )));
                    }
                }
                _ => cloud.set_crs(stated),
            }
        }
        if let Some(u) = &self.units {
            cloud.set_unit(u.clone());
        }
        Ok(cloud)
    }

    /// Reads the clouds at `paths` as one survey (tiles of one CRS side by
    /// side, as producers deliver them), each taken in `--crs` and `--units` when given;
    /// tiles in different CRSs are an error.
    pub fn read_tiles(&self, paths: &[PathBuf]) -> Result<Cloud, RuntimeError> {
        if let [one] = paths {
            return self.read(one);
        }
        let mut tiles = Vec::with_capacity(paths.len());
        for p in paths {
            tiles.push((p.display().to_string(), self.read(p)?));
        }
        join_tiles(&tiles).map_err(super::err)
    }
}

/// The input files as one line (`a.laz + b.laz`), for reports.
pub fn describe(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    names.join(" + ")
}

/// Parses `--units` (m, ft, ftUS and their long names).
pub fn parse_unit(text: &str) -> Result<LinearUnit, String> {
    LinearUnit::parse(text).ok_or_else(|| format!("unknown unit `{text}` (m, ft, ftUS)"))
}

/// Parses `--crs`: `EPSG:n`, an OGC URN or URL naming an EPSG code, or `n`.
pub fn parse_epsg(text: &str) -> Result<u32, String> {
    let t = text.trim();
    t.parse()
        .ok()
        .filter(|c| *c > 0)
        .or_else(|| epsg_from_reference(t))
        .ok_or_else(|| format!("`{text}` names no EPSG code (e.g. EPSG:28992)"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crs_is_named_by_its_epsg_code_only() {
        for t in [
            "EPSG:28992",
            "28992",
            " epsg:28992 ",
            "urn:ogc:def:crs:EPSG::28992",
        ] {
            assert_eq!(parse_epsg(t), Ok(28992), "{t}");
        }
        for t in ["RD New", "0", "EPSG:", ""] {
            assert!(parse_epsg(t).is_err(), "{t}");
        }
    }
}
