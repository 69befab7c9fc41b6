//! Waveform data packets, which the `las` crate neither reads nor writes:
//! the header's waveform bits (global encoding bits 1 and 2) and a LAS 1.3
//! file's internal packet record (after the points, where the header's
//! "start of waveform data packet record" points). A relabelled copy gets
//! both back, so the points' wave packet descriptors (formats 4, 5, 9, 10)
//! still point at their packets.

use std::io::{Read, Seek, SeekFrom, Write};

use super::LasError;

/// Global encoding bits: packets in this file (1), in a `.wdp` beside it (2).
const WAVEFORM_BITS: u16 = 0b110;
const INTERNAL: u16 = 0b010;
/// Header fields (byte offsets).
const GLOBAL_ENCODING: u64 = 6;
const MINOR_VERSION: usize = 25;
const START_OF_WAVEFORMS: u64 = 227;
const START_OF_FIRST_EVLR: u64 = 235;
const NUMBER_OF_EVLRS: u64 = 243;

/// What a source says about its waveforms.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Waveforms {
    /// Its waveform bits.
    bits: u16,
    /// A LAS 1.3 file's internal packet record, header included.
    packets: Vec<u8>,
}

impl Waveforms {
    /// The waveforms of the LAS stream `source` (left at its start), if it has any.
    pub fn find<R: Read + Seek>(source: &mut R) -> Result<Option<Waveforms>, LasError> {
        let file_len = source.seek(SeekFrom::End(0))?;
        source.seek(SeekFrom::Start(0))?;
        let mut head = Vec::with_capacity(235);
        source.by_ref().take(235).read_to_end(&mut head)?;
        let field = |at: usize, n: usize| head.get(at..at + n);
        let (Some(b"LASF"), Some(&minor), Some(ge)) = (
            head.get(..4),
            head.get(MINOR_VERSION),
            field(6, 2).and_then(|b| b.try_into().ok()),
        ) else {
            source.seek(SeekFrom::Start(0))?;
            return Ok(None);
        };
        let bits = u16::from_le_bytes(ge) & WAVEFORM_BITS;
        let start = field(227, 8)
            .and_then(|b| b.try_into().ok())
            .map(u64::from_le_bytes)
            .unwrap_or(0);
        let mut packets = Vec::new();
        // LAS 1.4 keeps the packets in an EVLR, which the crate copies.
        if minor == 3 && bits & INTERNAL != 0 && start > 0 && start < file_len {
            source.seek(SeekFrom::Start(start))?;
            source.read_to_end(&mut packets)?;
        }
        source.seek(SeekFrom::Start(0))?;
        Ok((bits != 0).then_some(Waveforms { bits, packets }))
    }

    /// Puts the waveforms into the finished copy `sink` (at its start, and
    /// left there), whose header the crate wrote as `written`: the packets
    /// after everything else, the header's bits and pointers.
    pub fn append_to<W: Write + Seek>(
        &self,
        mut sink: W,
        written: &Written,
    ) -> Result<W, LasError> {
        if !self.packets.is_empty() {
            let at = sink.seek(SeekFrom::End(0))?;
            sink.write_all(&self.packets)?;
            sink.seek(SeekFrom::Start(START_OF_WAVEFORMS))?;
            sink.write_all(&at.to_le_bytes())?;
            if written.minor >= 4 {
                // An upgraded copy: the record is one more EVLR.
                if written.evlrs == 0 {
                    sink.seek(SeekFrom::Start(START_OF_FIRST_EVLR))?;
                    sink.write_all(&at.to_le_bytes())?;
                }
                sink.seek(SeekFrom::Start(NUMBER_OF_EVLRS))?;
                sink.write_all(&(written.evlrs + 1).to_le_bytes())?;
            }
        }
        let ge = written.global_encoding | self.bits;
        sink.seek(SeekFrom::Start(GLOBAL_ENCODING))?;
        sink.write_all(&ge.to_le_bytes())?;
        sink.seek(SeekFrom::Start(0))?;
        Ok(sink)
    }
}

/// What the `las` crate wrote in the copy's header.
#[derive(Debug, Clone, Copy)]
pub struct Written {
    /// Minor version.
    pub minor: u8,
    /// Global encoding bits.
    pub global_encoding: u16,
    /// Number of EVLRs.
    pub evlrs: u32,
}

impl Written {
    /// From the header the writer was made with.
    pub fn of(header: &::las::Header) -> Result<Written, LasError> {
        // As the writer starts it: counts and bounds cleared (a source's
        // bounds may not fit its own grid: laspy's simple1_3.las).
        let mut h = header.clone();
        h.clear();
        let raw = h.into_raw()?;
        Ok(Written {
            minor: raw.version.minor,
            global_encoding: raw.global_encoding,
            evlrs: u32::try_from(header.evlrs().len()).unwrap_or(u32::MAX),
        })
    }
}
