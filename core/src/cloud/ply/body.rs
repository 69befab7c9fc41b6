//! Reading a PLY body: the vertex element into a cloud, every other element skipped.

use super::PlyError;
use super::ascii::AsciiRows;
use super::binary::BinaryRows;
use super::header::{Header, PlyFormat};
use super::rows::Rows;
use super::vertex::{VertexPlan, read_vertices};
use crate::cloud::Cloud;

/// Decodes `body` (the bytes after `end_header`) as described by `header`.
pub fn read_body(header: &Header, body: &[u8]) -> Result<Cloud, PlyError> {
    let vertex = header
        .elements
        .iter()
        .find(|e| e.name == "vertex")
        .ok_or(PlyError::MissingVertexElement)?;
    let plan = VertexPlan::new(vertex)?;
    for e in &header.elements {
        if e.count.checked_mul(e.min_row_bytes()).is_none() {
            return Err(PlyError::CountOverflow {
                element: e.name.clone(),
                count: e.count,
            });
        }
    }
    match header.format {
        PlyFormat::Ascii => walk(header, &plan, AsciiRows::new(body, header.lines)),
        PlyFormat::BinaryLittleEndian => walk(header, &plan, BinaryRows::new(body, false)),
        PlyFormat::BinaryBigEndian => walk(header, &plan, BinaryRows::new(body, true)),
    }
}

fn walk<R: Rows>(header: &Header, plan: &VertexPlan, mut rows: R) -> Result<Cloud, PlyError> {
    let mut cloud = None;
    for element in &header.elements {
        if element.name == "vertex" {
            cloud = Some(read_vertices(&mut rows, element, plan, header.origin)?);
        } else {
            rows.skip_element(element)?;
        }
    }
    rows.finish()?;
    cloud.ok_or(PlyError::MissingVertexElement)
}
