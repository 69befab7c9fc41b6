//! `--footprints`: the building outlines a subcommand splits a cloud by,
//! instead of deriving them from its points (`skyground detect`,
//! `skyground reconstruct`).

use std::path::PathBuf;

use skyground_core::crs::SourceFrame;
use skyground_core::footprint::{Footprint, load_footprints_in};

use crate::runtime::RuntimeError;

/// The `--footprints` option.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct FootprintsArg {
    /// Footprints (GeoJSON, CityJSON, OBJ) in the cloud's coordinates; default: derived from the points.
    #[arg(long)]
    pub footprints: Option<PathBuf>,
}

impl FootprintsArg {
    /// The footprints given, moved into the cloud's `frame` (`None` without
    /// `--footprints`); those the file holds but cannot be used are named
    /// on stderr, and the rest load.
    pub fn load(&self, frame: &SourceFrame) -> Result<Option<Vec<Footprint>>, RuntimeError> {
        let Some(path) = &self.footprints else {
            return Ok(None);
        };
        let loaded = load_footprints_in(path, frame).map_err(super::err)?;
        for s in &loaded.skipped {
            eprintln!("footprints {}: {s}", path.display());
        }
        Ok(Some(loaded.footprints))
    }
}
