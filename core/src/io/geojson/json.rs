//! Reading JSON bytes with the errors footprint readers report.

use serde_json::Value;

use crate::footprint::ParseError;

/// Parses JSON; empty input and syntax errors become typed errors.
pub fn parse(data: &[u8]) -> Result<Value, ParseError> {
    if data.iter().all(u8::is_ascii_whitespace) {
        return Err(ParseError::Empty);
    }
    serde_json::from_slice(data).map_err(|e| ParseError::Json {
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })
}
