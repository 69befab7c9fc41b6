//! Point clouds as plain data, and reading/writing them from/to files.

mod data;

pub use data::{Cloud, CloudError};
