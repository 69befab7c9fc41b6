//! LAS/LAZ → [`Cloud`].

use std::io::{Read, Seek};

use ::las::{Header, PointData, Reader, Vlr};

use super::{LasError, extra_bytes, preflight};
use crate::cloud::Cloud;
use crate::cloud::origin::{SMALL_COORDINATE, local_origin, to_local};
use crate::crs::{Crs, CrsError, CrsRecord, LAS_PROJECTION};

/// What reading does with `LASF_Projection` records it cannot make out
/// (a malformed WKT or GeoTIFF key directory).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UnreadableCrs {
    /// Reading fails: a CRS is not guessed.
    #[default]
    Fail,
    /// The points are read and the cloud has no CRS: for a caller told the
    /// CRS another way (the user's `--crs`). A geographic CRS still fails:
    /// its coordinates are degrees, whatever the caller states.
    Skip,
}

/// Points decoded per batch (bounds the temporary record buffer).
const BATCH: u64 = 1 << 16;
/// Most points pre-allocated before any is read.
const MAX_PREALLOC: u64 = 1 << 24;

/// Reads a LAS or LAZ stream (detected from the header).
///
/// Intensity, classification (as `label`), return number and number of
/// returns are always present; `building` is
/// present when the file has our `building` extra-bytes dimension.
/// Origin per axis: the header's offset when the header bounds lie within
/// 10 km of it, else [`local_origin`] of the bounds' minimum (or of the first
/// point when the bounds are not usable).
/// The CRS records (WKT, GeoTIFF keys) go to `crs`; coordinates in feet are
/// scaled to metres (see [`Cloud`]'s frame).
pub fn read_las<R: Read + Seek + Send + Sync + 'static>(source: R) -> Result<Cloud, LasError> {
    read_las_with(source, UnreadableCrs::Fail)
}

/// [`read_las`], with CRS records it cannot make out failing or skipped.
pub fn read_las_with<R: Read + Seek + Send + Sync + 'static>(
    mut source: R,
    unreadable: UnreadableCrs,
) -> Result<Cloud, LasError> {
    let preflight = preflight::check(&mut source)?;
    let mut reader = Reader::new(source)?;
    let header = reader.header().clone();
    let count = header.number_of_points();
    let capacity = usize::try_from(preflight.capacity.min(count).min(MAX_PREALLOC)).unwrap_or(0);
    let building_at = extra_bytes::building_offset(&header);
    let mut cloud = Cloud {
        xyz: Vec::with_capacity(capacity),
        intensity: Some(Vec::with_capacity(capacity)),
        label: Some(Vec::with_capacity(capacity)),
        building: building_at.map(|_| Vec::with_capacity(capacity)),
        return_number: Some(Vec::with_capacity(capacity)),
        number_of_returns: Some(Vec::with_capacity(capacity)),
        origin: [0.0; 3],
        // Before the points: a file refused for its CRS records is refused
        // without decoding them (the CLI then reads it again with `--crs`).
        crs: crs_of(&header, unreadable)?,
    };
    let mut origin = header_origin(&header);
    let mut index = 0u64;
    loop {
        let batch = read_batch(&mut reader, index, count)?;
        if batch.is_empty() {
            break;
        }
        let origin = origin.get_or_insert_with(|| first_point_origin(&batch));
        push_batch(&mut cloud, &batch, *origin, index, building_at)?;
        index += batch.len() as u64;
    }
    cloud.origin = origin.unwrap_or_default();
    // Points and origin were read in the file's unit.
    cloud.rescale(cloud.to_metre());
    Ok(cloud)
}

/// The next batch of points. A panic inside the decoder is caught and
/// becomes an error: a guard only, for decoder panics the preflight checks
/// do not foresee (the `laz` crate has several on malformed chunks).
fn read_batch(reader: &mut Reader, index: u64, count: u64) -> Result<PointData, LasError> {
    let decoded =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| reader.read_points(BATCH)));
    match decoded {
        Ok(batch) => batch.map_err(|source| LasError::Points {
            index,
            count,
            source,
        }),
        Err(panic) => Err(LasError::DecoderPanic {
            index,
            message: panic_message(panic.as_ref()),
        }),
    }
}

/// The text a panic carried.
fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "no message".into())
}

/// The header's bounding box alone, as a cloud of its two corners (same
/// frame, CRS and metres as [`read_las`] would give), without decoding a
/// point: to find which tiles of a survey touch which. `None` when the
/// header's bounds are unusable (read the file whole instead).
pub fn read_las_bounds<R: Read + Seek + Send + Sync + 'static>(
    source: R,
    unreadable: UnreadableCrs,
) -> Result<Option<Cloud>, LasError> {
    let reader = Reader::new(source)?;
    let header = reader.header().clone();
    let Some(origin) = header_origin(&header) else {
        return Ok(None);
    };
    let b = header.bounds();
    let mut xyz = Vec::with_capacity(2);
    for corner in [[b.min.x, b.min.y, b.min.z], [b.max.x, b.max.y, b.max.z]] {
        let mut p = [0.0f32; 3];
        for (k, slot) in p.iter_mut().enumerate() {
            *slot = to_local(corner[k], origin[k]).ok_or(LasError::BadCoordinate {
                index: 0,
                axis: ["x", "y", "z"][k],
                value: corner[k],
            })?;
        }
        xyz.push(p);
    }
    let mut cloud = Cloud {
        xyz,
        origin,
        crs: crs_of(&header, unreadable)?,
        ..Cloud::default()
    };
    cloud.rescale(cloud.to_metre());
    Ok(Some(cloud))
}

/// The CRS stated by the header's `LASF_Projection` (E)VLRs.
fn crs_of(header: &Header, unreadable: UnreadableCrs) -> Result<Option<Crs>, LasError> {
    Ok(crs_in(header.all_vlrs(), unreadable)?)
}

/// The CRS stated by the `LASF_Projection` records among `vlrs` (None when
/// there are none, or, with [`UnreadableCrs::Skip`], none can be read).
pub(super) fn crs_in<'a>(
    vlrs: impl Iterator<Item = &'a Vlr>,
    unreadable: UnreadableCrs,
) -> Result<Option<Crs>, CrsError> {
    let records = vlrs
        .filter(|v| v.user_id == LAS_PROJECTION)
        .map(|v| CrsRecord {
            record_id: v.record_id,
            description: v.description.clone(),
            data: v.data.clone(),
        })
        .collect();
    match Crs::from_las_records(records) {
        Err(e) if e.is_malformed() && unreadable == UnreadableCrs::Skip => Ok(None),
        read => read,
    }
}

/// The origin from the header, or `None` when its bounds are unusable.
fn header_origin(header: &Header) -> Option<[f64; 3]> {
    let (b, t) = (header.bounds(), header.transforms());
    let axes = [
        (b.min.x, b.max.x, t.x.offset),
        (b.min.y, b.max.y, t.y.offset),
        (b.min.z, b.max.z, t.z.offset),
    ];
    if !axes
        .iter()
        .all(|&(lo, hi, _)| lo.is_finite() && hi.is_finite() && lo <= hi)
    {
        return None;
    }
    let fallback = local_origin([b.min.x, b.min.y, b.min.z]);
    let mut origin = [0.0; 3];
    for ((o, (lo, hi, offset)), f) in origin.iter_mut().zip(axes).zip(fallback) {
        let near = |v: f64| (v - offset).abs() < SMALL_COORDINATE;
        *o = if offset.is_finite() && near(lo) && near(hi) {
            offset
        } else {
            f
        };
    }
    Some(origin)
}

fn first_point_origin(batch: &PointData) -> [f64; 3] {
    local_origin([
        batch.x().next().unwrap_or_default(),
        batch.y().next().unwrap_or_default(),
        batch.z().next().unwrap_or_default(),
    ])
}

fn push_batch(
    cloud: &mut Cloud,
    batch: &PointData,
    origin: [f64; 3],
    first_index: u64,
    building_at: Option<usize>,
) -> Result<(), LasError> {
    let xyz = batch.x().zip(batch.y()).zip(batch.z());
    for (i, ((x, y), z)) in xyz.enumerate() {
        let mut p = [0.0f32; 3];
        let axes = [("x", x), ("y", y), ("z", z)].into_iter().zip(origin);
        for (slot, ((axis, value), o)) in p.iter_mut().zip(axes) {
            *slot = to_local(value, o).ok_or(LasError::BadCoordinate {
                index: first_index + i as u64,
                axis,
                value,
            })?;
        }
        cloud.xyz.push(p);
    }
    if let Some(col) = &mut cloud.intensity {
        col.extend(batch.intensity().map(f32::from));
    }
    if let Some(col) = &mut cloud.label {
        col.extend(batch.classification());
    }
    if let Some(col) = &mut cloud.return_number {
        col.extend(batch.return_number());
    }
    if let Some(col) = &mut cloud.number_of_returns {
        col.extend(batch.number_of_returns());
    }
    if let (Some(col), Some(at)) = (&mut cloud.building, building_at) {
        let records = batch.raw_bytes().chunks_exact(batch.record_len().max(1));
        col.extend(records.map(|r| {
            r.get(at..at + 4)
                .and_then(|b| b.try_into().ok())
                .map_or(0, u32::from_le_bytes)
        }));
    }
    Ok(())
}
