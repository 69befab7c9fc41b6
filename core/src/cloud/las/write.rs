//! [`Cloud`] → LAS 1.4 point format 6, plain or LAZ-compressed.

use std::io::{Seek, Write};

use ::las::point::Format;
use ::las::{Builder, PointDataBuilder, Transform, Vector, Vlr, Writer};

use super::{LasError, close, extra_bytes};
use crate::cloud::Cloud;
use crate::crs::{CrsRecord, LAS_PROJECTION};

/// Coordinate resolution of written files, in the file's unit (mm, or 0.001 ft).
pub const SCALE: f64 = 0.001;
/// Points encoded per batch.
const BATCH: usize = 1 << 16;

/// Writes `cloud` as LAS 1.4, point format 6 (LAZ when `compressed`).
///
/// Coordinates: 1 mm integers with the header offset = `cloud.origin`, so
/// [`super::read_las`] gives the origin back. Intensity is rounded to u16
/// (error outside 0..=65535; 0 when absent), label is written as the
/// classification byte (0 when absent), return number and number of returns
/// as given (1 of 1 when absent), GPS time 0. The building id, when present,
/// goes to the `building` extra-bytes dimension (an Extra Bytes VLR declaring
/// a u32 named `building`).
/// With a `crs`, coordinates go back to its unit and its LAS records are
/// written unchanged (a CRS known only by EPSG code gets the registry's WKT).
/// Returns the sink, positioned at its start.
pub fn write_las<W: Write + Seek + Send + Sync + 'static>(
    sink: W,
    cloud: &Cloud,
    compressed: bool,
) -> Result<W, LasError> {
    cloud.validate()?;
    if !cloud.origin.iter().all(|v| v.is_finite()) {
        return Err(LasError::NonFiniteOrigin {
            origin: cloud.origin,
        });
    }
    let mut builder = Builder::from((1, 4));
    builder.generating_software = "skyground".into();
    builder.point_format = Format::new(6)?;
    builder.point_format.is_compressed = compressed;
    if cloud.building.is_some() {
        builder.point_format.extra_bytes = extra_bytes::LEN;
        builder.vlrs.push(extra_bytes::building_vlr());
    }
    if let Some(crs) = &cloud.crs {
        builder.vlrs.extend(crs_vlrs(crs.las_records_for(true)));
    }
    let f = cloud.to_metre();
    let [x, y, z] = [0, 1, 2].map(|k| Transform {
        scale: SCALE,
        offset: cloud.origin[k] / f[k],
    });
    builder.transforms = Vector { x, y, z };
    let mut writer = Writer::new(sink, builder.into_header()?)?;
    let written = write_points(&mut writer, cloud);
    close::finish(writer, written)
}

/// Every point of `cloud`, in batches.
fn write_points<W: Write + Seek + Send + Sync + 'static>(
    writer: &mut Writer<W>,
    cloud: &Cloud,
) -> Result<(), LasError> {
    let slab = PointDataBuilder::new().for_header(writer.header());
    let mut bytes = Vec::new();
    let mut start = 0;
    while start < cloud.len() {
        let end = (start + BATCH).min(cloud.len());
        bytes.clear();
        for i in start..end {
            encode(&mut bytes, cloud, i)?;
        }
        let points = slab.clone().build_from_bytes(std::mem::take(&mut bytes))?;
        writer.write_points(&points)?;
        start = end;
    }
    Ok(())
}

/// `records` as the file's `LASF_Projection` records.
pub(super) fn crs_vlrs(records: Vec<CrsRecord>) -> impl Iterator<Item = Vlr> {
    records.into_iter().map(|r| Vlr {
        user_id: LAS_PROJECTION.into(),
        record_id: r.record_id,
        description: r.description,
        data: r.data,
    })
}

/// Appends point `i` as a format 6 record (+ building u32 when present).
fn encode(out: &mut Vec<u8>, cloud: &Cloud, i: usize) -> Result<(), LasError> {
    let p = cloud.xyz.get(i).copied().unwrap_or_default();
    let f = cloud.to_metre();
    for ((axis, value), f) in ["x", "y", "z"].into_iter().zip(p).zip(f) {
        let scaled = (f64::from(value) / f / SCALE).round();
        if !(f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&scaled) {
            return Err(LasError::CoordinateRange {
                index: i,
                axis,
                value,
            });
        }
        // In range and whole, checked just above.
        out.extend_from_slice(&(scaled as i32).to_le_bytes());
    }
    let intensity = match cloud.intensity.as_ref().and_then(|c| c.get(i)) {
        None => 0,
        Some(&value) => {
            let r = value.round();
            if !(0.0..=f32::from(u16::MAX)).contains(&r) {
                return Err(LasError::IntensityRange { index: i, value });
            }
            // In range and whole, checked just above.
            r as u16
        }
    };
    out.extend_from_slice(&intensity.to_le_bytes());
    let label = cloud.label.as_ref().and_then(|c| c.get(i)).copied();
    let echo = |col: &Option<Vec<u8>>| col.as_ref().and_then(|c| c.get(i)).copied();
    // Format 6 packs the return number in the low and the count in the high nibble.
    let rn = echo(&cloud.return_number).unwrap_or(1).min(15);
    let nr = echo(&cloud.number_of_returns).unwrap_or(1).min(15);
    // returns; no flags; classification; user data 0; scan angle 0; source id 0
    out.extend_from_slice(&[rn | (nr << 4), 0, label.unwrap_or(0), 0, 0, 0, 0, 0]);
    out.extend_from_slice(&0f64.to_le_bytes());
    if let Some(col) = &cloud.building {
        let id = col.get(i).copied().unwrap_or(0);
        out.extend_from_slice(&id.to_le_bytes());
    }
    Ok(())
}
