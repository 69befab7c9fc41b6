//! Arbitrary bytes → the GeoJSON footprint reader.
//!
//! Must never panic, hang, or allocate more than the input can justify.

#![no_main]

use libfuzzer_sys::fuzz_target;
use skyground_core::io::parse_geojson;

fuzz_target!(|data: &[u8]| {
    let _ = parse_geojson(data, [0.0; 3]);
});
