//! Arbitrary bytes → the PLY reader, through an in-memory `Read`.
//!
//! Must never panic, hang, or allocate more than the input can justify.

#![no_main]

use libfuzzer_sys::fuzz_target;
use skyground_core::cloud::read_ply;

fuzz_target!(|data: &[u8]| {
    if let Ok(cloud) = read_ply(data) {
        // Whatever the reader accepts must be a consistent cloud.
        assert_eq!(cloud.validate(), Ok(()));
        assert!(cloud.xyz.iter().flatten().all(|v| v.is_finite()));
    }
});
