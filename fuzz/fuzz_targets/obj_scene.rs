//! Arbitrary text → the OBJ scene reader.
//!
//! Must never panic, hang, or allocate more than the input can justify.

#![no_main]

use libfuzzer_sys::fuzz_target;
use skyground_core::io::{ObjOptions, parse_obj};

fuzz_target!(|data: &[u8]| {
    let _ = parse_obj(&String::from_utf8_lossy(data), &ObjOptions::default());
});
