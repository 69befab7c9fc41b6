//! Polygons a node's params name (the detector's footprints, the drone's
//! geofence): read as footprints are and moved into the clouds' frame,
//! each polygon left out said in the log.

use skyground_core::footprint::Footprint;
use skyground_core::io::load_given;

use crate::runtime::{Logger, RuntimeError};

/// The polygons of `spec` (param `param`) in the frame whose origin is
/// `origin` in `crs` (`EPSG:N`, blank: none known), each one's id from
/// `id_field`; an error names the param's file and why.
pub fn load_logged(
    log: &Logger,
    param: &str,
    spec: &str,
    (id_field, crs, origin): (&str, &str, &[f64]),
) -> Result<Vec<Footprint>, RuntimeError> {
    let loaded = load_given(spec, id_field, crs, origin)
        .map_err(|e| RuntimeError::Node(format!("{param} {spec}: {e}")))?;
    for s in &loaded.skipped {
        log.warn(&format!("{param} {spec}: {s}"));
    }
    log.info(&format!(
        "{param} {spec}: {} polygon(s)",
        loaded.footprints.len()
    ));
    Ok(loaded.footprints)
}
