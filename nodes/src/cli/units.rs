//! `--units`: the unit of a cloud whose file states none (or states it
//! wrongly), shared by the subcommands that read a cloud.

use std::path::{Path, PathBuf};

use skyground_core::cloud::{Cloud, read_bounds, read_cloud};
use skyground_core::crs::LinearUnit;
use skyground_core::prior::join_tiles;

use crate::runtime::RuntimeError;

/// The `--units` option.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct UnitsArg {
    /// The unit of a cloud whose file states none (m, ft, ftUS); overrides the file's.
    #[arg(long, value_parser = parse_unit)]
    pub units: Option<LinearUnit>,
}

impl UnitsArg {
    /// Reads the cloud at `path`, its coordinates taken in `--units` when given.
    pub fn read(&self, path: &Path) -> Result<Cloud, RuntimeError> {
        Ok(self.taken_in(read_cloud(path).map_err(super::err)?))
    }

    /// The bounding box of the cloud at `path` (its two corners; a LAS/LAZ
    /// header alone), in `--units` when given.
    pub fn read_bounds(&self, path: &Path) -> Result<Cloud, RuntimeError> {
        Ok(self.taken_in(read_bounds(path).map_err(super::err)?))
    }

    /// `cloud` with its coordinates taken in `--units` when given.
    fn taken_in(&self, mut cloud: Cloud) -> Cloud {
        if let Some(u) = &self.units {
            cloud.set_unit(u.clone());
        }
        cloud
    }

    /// Reads the clouds at `paths` as one survey (tiles of one CRS side by
    /// side, as producers deliver them), each taken in `--units` when given;
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
