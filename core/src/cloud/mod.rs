//! Point clouds as plain data, and reading/writing them from/to files.
//!
//! - [`Cloud`]: the in-memory cloud (`data`).
//! - [`ply`]: our own strict PLY reader and writer.
//! - [`las`]: LAS/LAZ through the `las` crate.
//! - [`read_cloud`] / [`write_cloud`]: pick the format by file extension (`io`).
//! - [`origin`]: how readers choose the local frame's origin.

pub mod class;
mod data;
pub mod extent;
pub mod info;
mod io;
pub mod las;
pub mod origin;
pub mod ply;
pub mod synthetic;

pub use data::{Cloud, CloudError, ColumnLength, positions_where};
pub use io::{
    CloudIoError, read_bounds, read_bounds_with, read_cloud, read_cloud_with, relabel_files,
    write_cloud,
};
pub use las::{LasError, UnreadableCrs, read_las, write_las};
pub use ply::{PlyError, PlyFormat, parse_ply, read_ply, write_ply, write_ply_as};
