//! Arbitrary bytes → the PLY mesh (scene) reader.
//!
//! Must never panic, hang, or allocate more than the input can justify.

#![no_main]

use libfuzzer_sys::fuzz_target;
use skyground_core::io::parse_ply_mesh;

fuzz_target!(|data: &[u8]| {
    let _ = parse_ply_mesh(data);
});
