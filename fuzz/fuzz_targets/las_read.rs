//! Arbitrary bytes → the LAS/LAZ reader (header checks, VLRs, LAZ chunks,
//! point records), through an in-memory stream.
//!
//! Must never panic, hang, or allocate more than the input can justify;
//! whatever it accepts must be a consistent cloud.

#![no_main]

use std::io::Cursor;

use libfuzzer_sys::fuzz_target;
use skyground_core::cloud::read_las;

fuzz_target!(|data: &[u8]| {
    if let Ok(cloud) = read_las(Cursor::new(data.to_vec())) {
        assert_eq!(cloud.validate(), Ok(()));
    }
});
