//! Arbitrary `LASF_Projection` records (a WKT text, GeoTIFF key directory,
//! doubles and ASCII params) → the CRS a LAS header states.
//!
//! Must never panic or overflow the stack (a 600 kB extended WKT record of
//! nested brackets once did), and a CRS it reads must read back in the
//! same unit from the records skyground's writer makes for it.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use skyground_core::crs::{Crs, CrsRecord, without_nodes};

/// The four record ids a LAS CRS lives in, so most inputs reach a parser.
#[derive(Debug, Arbitrary)]
enum Id {
    Wkt,
    GeoKeys,
    Doubles,
    Ascii,
    Other(u16),
}

#[derive(Debug, Arbitrary)]
struct Record {
    id: Id,
    data: Vec<u8>,
}

fuzz_target!(|records: Vec<Record>| {
    let records: Vec<CrsRecord> = records
        .into_iter()
        .map(|r| CrsRecord {
            record_id: match r.id {
                Id::Wkt => 2112,
                Id::GeoKeys => 34735,
                Id::Doubles => 34736,
                Id::Ascii => 34737,
                Id::Other(n) => n,
            },
            description: String::new(),
            data: r.data,
        })
        .collect();
    for r in records.iter().filter(|r| r.record_id == 2112) {
        let _ = without_nodes(&String::from_utf8_lossy(&r.data), "TOWGS84");
    }
    if let Ok(Some(mut crs)) = Crs::from_las_records(records) {
        // The records our writer makes for it, not the ones it came in.
        crs.las_records.clear();
        for extended in [false, true] {
            let written = crs.las_records_for(extended);
            if written.is_empty() {
                continue;
            }
            let back = Crs::from_las_records(written);
            let back = back.unwrap_or_else(|e| panic!("{crs:?} written, then: {e}"));
            let back = back.expect("records were written");
            assert_eq!(back.horizontal_unit, crs.horizontal_unit, "{crs:?}");
        }
    }
});
