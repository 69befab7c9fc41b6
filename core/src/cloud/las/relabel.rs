//! New classes in a copy of LAS/LAZ files: every other field of every
//! point (GPS time, colour, scan angle, flight line, user data, flags,
//! extra bytes) and the header's version, point format, scales, offsets and
//! records (the CRS among them) stay as the producer wrote them, as a
//! classifier in PDAL or LAStools leaves them.

use std::io::{Read, Seek, Write};

use ::las::{Builder, PointData, PointDataBuilder, Reader, Writer};

use super::LasError;
use super::read::{UnreadableCrs, crs_in};
use super::write::crs_vlrs;
use crate::crs::{Crs, LAS_PROJECTION};

/// Points copied per batch.
const BATCH: u64 = 1 << 16;
/// The record that says a file is LAZ; the writer adds its own.
const LASZIP_USER_ID: &str = "laszip encoded";

/// Copies the points of `sources`, in order, to `sink`, each with its class
/// from `labels` (one per point of all sources together); LAZ when
/// `compressed`. The header is the first source's (bounds and counts those
/// of what was written); every source must have its point format. A source
/// with other scales or offsets has its points re-quantised to the first's.
/// When the first states no CRS, or records that cannot be read, `stated`
/// (the user's `--crs`) is written in the records its point format calls
/// for.
pub fn relabel_las<R, W>(
    sources: Vec<R>,
    sink: W,
    labels: &[u8],
    compressed: bool,
    stated: Option<&Crs>,
) -> Result<W, LasError>
where
    R: Read + Seek + Send + Sync + 'static,
    W: Write + Seek + Send + Sync + 'static,
{
    let mut readers = Vec::with_capacity(sources.len());
    for s in sources {
        readers.push(Reader::new(s)?);
    }
    let first = readers.first().ok_or(LasError::NoSource)?;
    let total: u64 = readers.iter().map(|r| r.header().number_of_points()).sum();
    if total != labels.len() as u64 {
        return Err(LasError::LabelCount {
            points: total,
            labels: labels.len(),
        });
    }
    let mut builder = Builder::from(first.header().clone());
    builder.generating_software = "skyground".into();
    builder.point_format.is_compressed = compressed;
    builder.vlrs.retain(|v| v.user_id != LASZIP_USER_ID);
    let readable = !matches!(
        crs_in(
            builder.vlrs.iter().chain(&builder.evlrs),
            UnreadableCrs::Skip
        ),
        Ok(None)
    );
    if let (false, Some(crs)) = (readable, stated) {
        // Records nobody can read would sit beside the stated ones and
        // contradict them.
        builder.vlrs.retain(|v| v.user_id != LAS_PROJECTION);
        builder.evlrs.retain(|v| v.user_id != LAS_PROJECTION);
        let records = crs.las_records_for(builder.point_format.is_extended);
        builder.vlrs.extend(crs_vlrs(records));
    }
    let mut writer = Writer::new(sink, builder.into_header()?)?;
    let format = *writer.header().point_format();
    let mut next = 0usize;
    for (k, mut reader) in readers.into_iter().enumerate() {
        let mut theirs = *reader.header().point_format();
        theirs.is_compressed = format.is_compressed;
        if theirs != format {
            return Err(LasError::SourceFormat {
                source_index: k,
                format: theirs.to_u8()?,
                first: format.to_u8()?,
            });
        }
        let same_grid = reader.header().transforms() == writer.header().transforms();
        loop {
            let batch = reader.read_points(BATCH)?;
            if batch.is_empty() {
                break;
            }
            let own = &labels[next..next + batch.len()];
            next += batch.len();
            let slab = if same_grid {
                with_classes(&batch, own, &writer)?
            } else {
                let points = batch.points().zip(own).map(|(p, &c)| {
                    let mut p = p?;
                    p.classification = ::las::point::Classification::new(c)?;
                    Ok(p)
                });
                let points = points.collect::<Result<Vec<_>, ::las::Error>>()?;
                PointDataBuilder::new()
                    .for_header(writer.header())
                    .build_from_points(points)?
            };
            writer.write_points(&slab)?;
        }
    }
    Ok(writer.into_inner()?)
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
            if c > 31 {
                return Err(LasError::LegacyClass { class: c });
            }
            rec[15] = (rec[15] & 0b1110_0000) | c;
        }
    }
    Ok(PointDataBuilder::new()
        .for_header(writer.header())
        .build_from_bytes(bytes)?)
}
