//! `--units`: the unit of a cloud whose file states none (or states it
//! wrongly), shared by the subcommands that read a cloud.

use std::path::Path;

use skyground_core::cloud::{Cloud, read_cloud};
use skyground_core::crs::LinearUnit;

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
        let mut cloud = read_cloud(path).map_err(super::err)?;
        if let Some(u) = &self.units {
            cloud.set_unit(u.clone());
        }
        Ok(cloud)
    }
}

/// Parses `--units` (m, ft, ftUS and their long names).
pub fn parse_unit(text: &str) -> Result<LinearUnit, String> {
    LinearUnit::parse(text).ok_or_else(|| format!("unknown unit `{text}` (m, ft, ftUS)"))
}
