//! Walking a geometry's nested `boundaries` down to surfaces (rings of indices).

use serde_json::Value;

/// One surface: its outer ring, then its holes, as vertex indices.
pub type Surface = Vec<Vec<u64>>;

/// Collects the surfaces of `boundaries`, which has `depth` array levels
/// above the surface level (0 for MultiSurface, 1 for Solid, 2 for MultiSolid).
pub fn surfaces(boundaries: &Value, depth: usize) -> Result<Vec<Surface>, &'static str> {
    let mut out = Vec::new();
    walk(boundaries, depth, &mut out)?;
    Ok(out)
}

fn walk(v: &Value, depth: usize, out: &mut Vec<Surface>) -> Result<(), &'static str> {
    let items = v
        .as_array()
        .ok_or("expected an array of surfaces, shells or solids")?;
    if depth > 0 {
        for item in items {
            walk(item, depth - 1, out)?;
        }
        return Ok(());
    }
    for surface in items {
        let rings = surface
            .as_array()
            .ok_or("a surface must be an array of rings")?;
        let mut s = Vec::with_capacity(rings.len());
        for ring in rings {
            let ring = ring
                .as_array()
                .ok_or("a ring must be an array of vertex indices")?;
            let ring = ring
                .iter()
                .map(|i| {
                    i.as_u64()
                        .ok_or("a vertex index must be a non-negative integer")
                })
                .collect::<Result<Vec<u64>, _>>()?;
            s.push(ring);
        }
        out.push(s);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nesting_per_type() {
        let ms: Value = serde_json::from_str("[[[0,1,2]],[[2,3,4],[5,6,7]]]").unwrap_or_default();
        assert_eq!(surfaces(&ms, 0).map(|s| s.len()), Ok(2));
        let solid: Value = serde_json::from_str("[[[[0,1,2]],[[2,3,4]]]]").unwrap_or_default();
        assert_eq!(surfaces(&solid, 1).map(|s| s.len()), Ok(2));
        assert!(surfaces(&solid, 0).is_err());
        let bad: Value = serde_json::from_str("[[[0,-1,2]]]").unwrap_or_default();
        assert!(surfaces(&bad, 0).is_err());
    }
}
