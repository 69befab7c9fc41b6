//! OBJ footprints: every face (`f`) is one footprint polygon (its xy), ids
//! 1.. in file order, named by the current `o`/`g` name when there is one.

use geo::Polygon;

use crate::footprint::error::{ParseError, Skipped};
use crate::footprint::polygon::{ring, union_valid};
use crate::footprint::{Footprint, Loaded};

/// Decodes OBJ text; coordinates have `origin` subtracted.
pub fn parse_obj_footprints(data: &[u8], origin: [f64; 3]) -> Result<Loaded, ParseError> {
    if data.iter().all(u8::is_ascii_whitespace) {
        return Err(ParseError::Empty);
    }
    let text = std::str::from_utf8(data).map_err(|e| ParseError::Shape {
        what: format!("OBJ is not UTF-8 text (byte {})", e.valid_up_to()),
    })?;
    let mut vertices: Vec<[f64; 2]> = Vec::new();
    let mut footprints = Vec::new();
    let mut skipped = Vec::new();
    let mut group: Option<String> = None;
    let mut faces = 0usize;
    for (n, line) in text.lines().enumerate() {
        let bad = |what: &str| ParseError::Shape {
            what: format!("line {}: {what}", n + 1),
        };
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let xy: Vec<f64> = it.take(2).filter_map(|t| t.parse().ok()).collect();
                match xy.as_slice() {
                    [x, y] => vertices.push([x - origin[0], y - origin[1]]),
                    _ => return Err(bad("a vertex needs numeric x y z")),
                }
            }
            Some("o" | "g") => group = Some(it.collect::<Vec<_>>().join(" ")),
            Some("f") => {
                faces += 1;
                let mut pts = Vec::new();
                for t in it {
                    let i: i64 = t
                        .split('/')
                        .next()
                        .and_then(|s| s.parse().ok())
                        .ok_or_else(|| bad("a face index must be an integer"))?;
                    // OBJ indices are 1-based; negative ones count back from the last vertex.
                    let k = if i < 0 {
                        i64::try_from(vertices.len()).unwrap_or(i64::MAX) + i
                    } else {
                        i - 1
                    };
                    let p = usize::try_from(k)
                        .ok()
                        .and_then(|k| vertices.get(k))
                        .ok_or_else(|| bad(&format!("face index {i} refers to no vertex")))?;
                    pts.push(*p);
                }
                let source = format!("face {faces} (line {})", n + 1);
                let made = ring(&pts, false).and_then(|r| union_valid(&[Polygon::new(r, vec![])]));
                match made {
                    Ok(polygon) => {
                        let id = u32::try_from(footprints.len() + 1).unwrap_or(u32::MAX);
                        let name = match &group {
                            Some(g) if !g.is_empty() => g.clone(),
                            _ => format!("face_{faces}"),
                        };
                        footprints.push(Footprint { id, polygon, name });
                    }
                    Err(problem) => skipped.push(Skipped { source, problem }),
                }
            }
            _ => {}
        }
    }
    Loaded::new(footprints, skipped)
}
