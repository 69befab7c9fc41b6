//! LAS and LAZ files through the `las` crate.
//!
//! Reading keeps positions (in a local frame, see [`read_las`]), intensity,
//! classification as `label`, and our `building` extra-bytes dimension.
//! Writing produces LAS 1.4 point format 6 ([`write_las`]); new classes
//! in a copy of the files a cloud was read from keep every other field
//! ([`relabel_las`]).

mod close;
mod error;
mod extra_bytes;
mod preflight;
mod read;
mod relabel;
mod waveform;
mod write;

pub use error::LasError;
pub use read::{UnreadableCrs, read_las, read_las_bounds, read_las_with};
pub use relabel::{Relabel, relabel_las};
pub use write::{SCALE, write_las};

#[cfg(test)]
mod tests;
