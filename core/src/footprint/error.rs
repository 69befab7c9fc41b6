//! What is wrong with footprint data, as the readers in [`crate::io`] report it.

/// What is wrong with footprint data (without the file name).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParseError {
    /// No bytes (or only whitespace).
    #[error("the file is empty")]
    Empty,
    /// Not valid JSON.
    #[error("invalid JSON at line {line}, column {column}: {message}")]
    Json {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// serde_json's message.
        message: String,
    },
    /// Valid syntax but not the expected structure.
    #[error("{what}")]
    Shape {
        /// What was expected and found.
        what: String,
    },
    /// Nothing usable was left after skipping bad polygons.
    #[error("no usable footprint ({skipped} polygon(s) skipped{})", first.as_ref().map(|f| format!("; first: {f}")).unwrap_or_default())]
    NoFootprints {
        /// How many polygons were skipped.
        skipped: usize,
        /// Why the first one was skipped.
        first: Option<String>,
    },
}

/// A [`ParseError::Shape`] saying `what`.
pub(crate) fn shape(what: &str) -> ParseError {
    ParseError::Shape {
        what: what.to_string(),
    }
}

/// Why one polygon of a file was skipped (the file still loads).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RingProblem {
    /// Fewer than 3 distinct vertices.
    #[error("ring has {0} distinct vertices (3 or more needed)")]
    TooFewVertices(usize),
    /// GeoJSON rings must end where they start.
    #[error("ring is not closed (last position differs from the first)")]
    NotClosed,
    /// A coordinate is NaN or infinite, or a position has < 2 numbers.
    #[error("a position is not two or three finite numbers")]
    BadPosition,
    /// A geometry that is not a polygon (point, line, null).
    #[error("geometry type `{0}` is not a polygon")]
    NotPolygon(String),
    /// The polygon encloses no area (collinear or fully cancelled).
    #[error("polygon has no area")]
    NoArea,
}

/// One skipped polygon: where and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Skipped {
    /// Which feature / object / face (as in the source).
    pub source: String,
    /// Why.
    pub problem: RingProblem,
}

impl std::fmt::Display for Skipped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.source, self.problem)
    }
}
