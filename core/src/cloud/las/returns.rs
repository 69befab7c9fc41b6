//! Echo counts of a LAS/LAZ file, straight from its point records.

use std::collections::BTreeMap;
use std::io::{Read, Seek};

use ::las::Reader;

use super::{LasError, preflight};

/// Points per (return number, number of returns), e.g. `(1, 2)`: first of two.
pub fn return_counts<R: Read + Seek + Send + Sync + 'static>(
    mut source: R,
) -> Result<BTreeMap<(u8, u8), usize>, LasError> {
    preflight::check(&mut source)?;
    let mut reader = Reader::new(source)?;
    let mut counts = BTreeMap::new();
    let mut index = 0u64;
    let count = reader.header().number_of_points();
    loop {
        let batch = reader
            .read_points(1 << 16)
            .map_err(|source| LasError::Points {
                index,
                count,
                source,
            })?;
        if batch.is_empty() {
            break;
        }
        for key in batch.return_number().zip(batch.number_of_returns()) {
            *counts.entry(key).or_default() += 1;
        }
        index += batch.len() as u64;
    }
    Ok(counts)
}
