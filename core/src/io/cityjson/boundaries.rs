//! Walking a geometry's nested `boundaries` down to surfaces (rings of
//! indices), with each surface's semantic index from the parallel
//! `semantics.values`.

use serde_json::Value;

/// One surface: its outer ring, then its holes, as vertex indices.
#[derive(Debug, Clone, PartialEq)]
pub struct Surface {
    /// Outer ring first, then holes.
    pub rings: Vec<Vec<u64>>,
    /// Index into the geometry's `semantics.surfaces`, if it has one.
    pub semantic: Option<u64>,
}

/// Collects the surfaces of `boundaries`, which has `depth` array levels
/// above the surface level (0 for MultiSurface, 1 for Solid, 2 for MultiSolid);
/// `values` is the geometry's `semantics.values` (same nesting, one level less).
pub fn surfaces(
    boundaries: &Value,
    values: Option<&Value>,
    depth: usize,
) -> Result<Vec<Surface>, &'static str> {
    let mut out = Vec::new();
    walk(boundaries, values, depth, &mut out)?;
    Ok(out)
}

fn walk(
    v: &Value,
    values: Option<&Value>,
    depth: usize,
    out: &mut Vec<Surface>,
) -> Result<(), &'static str> {
    let items = v
        .as_array()
        .ok_or("expected an array of surfaces, shells or solids")?;
    let vals = values.and_then(Value::as_array);
    for (k, item) in items.iter().enumerate() {
        let value = vals.and_then(|a| a.get(k));
        if depth > 0 {
            walk(item, value, depth - 1, out)?;
            continue;
        }
        let rings = item
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
        out.push(Surface {
            rings: s,
            semantic: value.and_then(Value::as_u64),
        });
    }
    Ok(())
}

/// `boundaries` with every vertex index mapped by `f` (same nesting); `None`
/// when `f` refuses an index or a leaf is not an index.
pub fn map_indices(v: &Value, f: &mut impl FnMut(u64) -> Option<u64>) -> Option<Value> {
    match v {
        Value::Array(items) => items
            .iter()
            .map(|i| map_indices(i, f))
            .collect::<Option<Vec<Value>>>()
            .map(Value::Array),
        Value::Number(n) => f(n.as_u64()?).map(Value::from),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn json(s: &str) -> Value {
        serde_json::from_str(s).unwrap_or_default()
    }

    #[test]
    fn nesting_per_type() {
        let ms = json("[[[0,1,2]],[[2,3,4],[5,6,7]]]");
        assert_eq!(surfaces(&ms, None, 0).map(|s| s.len()), Ok(2));
        let solid = json("[[[[0,1,2]],[[2,3,4]]]]");
        assert_eq!(surfaces(&solid, None, 1).map(|s| s.len()), Ok(2));
        assert!(surfaces(&solid, None, 0).is_err());
        let bad = json("[[[0,-1,2]]]");
        assert!(surfaces(&bad, None, 0).is_err());
    }

    #[test]
    fn semantics_follow_the_nesting() {
        let solid = json("[[[[0,1,2]],[[2,3,4]],[[4,5,6]]]]");
        let values = json("[[1,null,0]]");
        let s = surfaces(&solid, Some(&values), 1).unwrap_or_default();
        let sem: Vec<Option<u64>> = s.iter().map(|s| s.semantic).collect();
        assert_eq!(sem, [Some(1), None, Some(0)]);
    }

    #[test]
    fn indices_mapped_in_place() {
        let solid = json("[[[[0,1,2]],[[2,3,4]]]]");
        let moved = map_indices(&solid, &mut |i| Some(i + 10));
        assert_eq!(moved, Some(json("[[[[10,11,12]],[[12,13,14]]]]")));
        assert_eq!(map_indices(&json("[[[0,\"x\"]]]"), &mut Some), None);
        assert_eq!(map_indices(&solid, &mut |i| (i < 4).then_some(i)), None);
    }
}
