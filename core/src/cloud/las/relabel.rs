//! New classes in a copy of LAS/LAZ files: every other field of every
//! point (GPS time, colour, scan angle, flight line, user data, flags,
//! extra bytes) and the header's version, point format, scales, offsets and
//! records (the CRS among them) stay as the producer wrote them, as a
//! classifier in PDAL or LAStools leaves them, unless the points need more:
//! a file of point format 0–5 whose points have more than 5 returns or get a
//! class above 31 is written as LAS 1.4 in the matching format 6–10. A COPC
//! file's `copc` records are left out (the copy is plain LAS/LAZ in the
//! input's order, not a COPC octree).

use std::io::{Read, Seek, Write};

use ::las::point::Format;
use ::las::{Builder, PointData, PointDataBuilder, Reader, Version, Writer};

use super::read::{UnreadableCrs, crs_in};
use super::write::crs_vlrs;
use super::{LasError, close, waveform};
use crate::crs::{Crs, LAS_PROJECTION};

/// Points copied per batch.
const BATCH: u64 = 1 << 16;
/// The record that says a file is LAZ; the writer adds its own.
const LASZIP_USER_ID: &str = "laszip encoded";
/// The records of a COPC file (its info VLR and hierarchy EVLR).
const COPC_USER_ID: &str = "copc";
/// Returns and classes that point formats 0–5 hold.
const LEGACY_RETURNS: u8 = 5;
const LEGACY_CLASSES: u8 = 31;

/// How to write a relabelled copy.
#[derive(Debug, Clone, Copy)]
pub struct Relabel<'a> {
    /// The new class of every point of all sources together, in order.
    pub labels: &'a [u8],
    /// The largest return number (or number of returns) among the points.
    pub max_return: u8,
    /// LAZ instead of LAS.
    pub compressed: bool,
    /// The CRS to write when the first source states none (the user's `--crs`).
    pub stated: Option<&'a Crs>,
}

/// Copies the points of `sources`, in order, to `sink`, each with its class
/// from `how.labels`. The header is the first source's (bounds and counts
/// those of what was written; the version and format as the module says);
/// every source must have its point format. A source with other scales or
/// offsets has its points re-quantised to the first's. When the first
/// states no CRS, or records that cannot be read, `how.stated` is written
/// in the records its point format calls for.
pub fn relabel_las<R, W>(sources: Vec<R>, sink: W, how: &Relabel) -> Result<W, LasError>
where
    R: Read + Seek + Send + Sync + 'static,
    W: Write + Seek + Send + Sync + 'static,
{
    let mut sources = sources;
    let waveforms = match sources.first_mut() {
        Some(s) => waveform::Waveforms::find(s)?,
        None => None,
    };
    let mut readers = Vec::with_capacity(sources.len());
    for s in sources {
        readers.push(Reader::new(s)?);
    }
    let first = readers.first().ok_or(LasError::NoSource)?;
    let total: u64 = readers.iter().map(|r| r.header().number_of_points()).sum();
    if total != how.labels.len() as u64 {
        return Err(LasError::LabelCount {
            points: total,
            labels: how.labels.len(),
        });
    }
    let source_format = *first.header().point_format();
    let builder = header_for(Builder::from(first.header().clone()), how)?;
    let header = builder.into_header()?;
    let written = waveform::Written::of(&header)?;
    let mut writer = Writer::new(sink, header)?;
    let copied = copy_points(readers, &mut writer, how.labels, source_format);
    let sink = close::finish(writer, copied)?;
    match waveforms {
        Some(w) => w.append_to(sink, &written),
        None => Ok(sink),
    }
}

/// The copy's header: the first source's, in the version and format its
/// points need, without the records that describe the source alone.
fn header_for(mut builder: Builder, how: &Relabel) -> Result<Builder, LasError> {
    builder.generating_software = "skyground".into();
    builder.point_format.is_compressed = how.compressed;
    builder.vlrs.retain(|v| v.user_id != LASZIP_USER_ID);
    builder.vlrs.retain(|v| v.user_id != COPC_USER_ID);
    builder.evlrs.retain(|v| v.user_id != COPC_USER_ID);
    let needs_extended =
        how.max_return > LEGACY_RETURNS || how.labels.iter().any(|&c| c > LEGACY_CLASSES);
    let upgraded = !builder.point_format.is_extended && needs_extended;
    if upgraded {
        builder.version = Version::new(1, 4);
        let mut f = Format::new(extended_of(builder.point_format.to_u8()?))?;
        f.extra_bytes = builder.point_format.extra_bytes;
        f.is_compressed = how.compressed;
        builder.point_format = f;
    }
    let records = builder.vlrs.iter().chain(&builder.evlrs);
    let read = crs_in(records, UnreadableCrs::Skip).ok().flatten();
    // Format 6+ states its CRS as WKT: an upgraded file gets the WKT of the
    // CRS it had (or of the stated one); records nobody can read would sit
    // beside the stated ones and contradict them.
    let crs = match (&read, how.stated) {
        (Some(c), _) if upgraded => Some(c),
        (None, Some(c)) => Some(c),
        _ => None,
    };
    if let Some(crs) = crs {
        builder.vlrs.retain(|v| v.user_id != LAS_PROJECTION);
        builder.evlrs.retain(|v| v.user_id != LAS_PROJECTION);
        let records = crs.las_records_for(builder.point_format.is_extended);
        builder.vlrs.extend(crs_vlrs(records));
    }
    Ok(builder)
}

/// The format 6–10 that holds what format 0–5 does (colour, waveform).
fn extended_of(legacy: u8) -> u8 {
    match legacy {
        0 | 1 => 6,
        2 | 3 => 7,
        4 => 9,
        _ => 10,
    }
}

/// Every source's points with their new classes, in order.
fn copy_points<W: Write + Seek + Send + Sync + 'static>(
    readers: Vec<Reader>,
    writer: &mut Writer<W>,
    labels: &[u8],
    source_format: Format,
) -> Result<(), LasError> {
    let format = *writer.header().point_format();
    let mut first = source_format;
    first.is_compressed = format.is_compressed;
    let mut next = 0usize;
    for (k, mut reader) in readers.into_iter().enumerate() {
        let mut theirs = *reader.header().point_format();
        theirs.is_compressed = format.is_compressed;
        if theirs != first {
            return Err(LasError::SourceFormat {
                source_index: k,
                format: theirs.to_u8()?,
                first: first.to_u8()?,
            });
        }
        let raw = theirs == format && reader.header().transforms() == writer.header().transforms();
        loop {
            let batch = reader.read_points(BATCH)?;
            if batch.is_empty() {
                break;
            }
            let own = labels
                .get(next..next + batch.len())
                .ok_or(LasError::LabelCount {
                    points: (next + batch.len()) as u64,
                    labels: labels.len(),
                })?;
            next += batch.len();
            let slab = if raw {
                with_classes(&batch, own, writer)?
            } else {
                converted(&batch, own, writer)?
            };
            writer.write_points(&slab)?;
        }
    }
    Ok(())
}

/// `batch`'s points in the writer's grid and format, with `classes`.
fn converted<W: Write + Seek + Send + Sync + 'static>(
    batch: &PointData,
    classes: &[u8],
    writer: &Writer<W>,
) -> Result<PointData, LasError> {
    let timed = writer.header().point_format().has_gps_time;
    let points = batch.points().zip(classes).map(|(p, &c)| {
        let mut p = p?;
        p.classification = ::las::point::Classification::new(c)?;
        if timed && p.gps_time.is_none() {
            // Formats 6+ always carry a time; the source had none to give.
            p.gps_time = Some(0.0);
        }
        Ok(p)
    });
    let points = points.collect::<Result<Vec<_>, ::las::Error>>()?;
    Ok(PointDataBuilder::new()
        .for_header(writer.header())
        .build_from_points(points)?)
}

/// `batch`'s records with their classification bytes set to `classes`.
fn with_classes<W: Write + Seek + Send + Sync + 'static>(
    batch: &PointData,
    classes: &[u8],
    writer: &Writer<W>,
) -> Result<PointData, LasError> {
    let len = batch.record_len();
    let mut bytes = batch.raw_bytes().to_vec();
    let extended = batch.format().is_extended;
    for (rec, &c) in bytes.chunks_exact_mut(len).zip(classes) {
        if extended {
            rec[16] = c;
        } else {
            // Formats 0–5 keep the synthetic, key-point and withheld flags
            // in the byte's top three bits; the class has five.
            if c > LEGACY_CLASSES {
                return Err(LasError::LegacyClass { class: c });
            }
            rec[15] = (rec[15] & 0b1110_0000) | c;
        }
    }
    Ok(PointDataBuilder::new()
        .for_header(writer.header())
        .build_from_bytes(bytes)?)
}
