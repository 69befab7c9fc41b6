//! Arbitrary bytes → the CityJSON / CityJSONSeq scene reader (documents,
//! transform, boundaries, the ground it adds around buildings).
//!
//! Must never panic, hang, or allocate more than the input can justify.

#![no_main]

use libfuzzer_sys::fuzz_target;
use skyground_core::io::{CityJsonOptions, parse_cityjson};

fuzz_target!(|data: &[u8]| {
    let _ = parse_cityjson(data, &CityJsonOptions::default());
});
