//! Reading the vertex and face elements of a mesh body through the shared
//! PLY row readers ([`crate::cloud::ply::reader`]).

use crate::cloud::ply::reader::{self, Element, PropertyKind, RowCtx, Rows};

use super::error::{PlyMeshError, PlyPlace};
use super::{CLASS_NAMES, Face, SPLIT_NAMES};

/// Where row `ctx` is: its line (ASCII) or element and row (binary).
fn place<R: Rows>(rows: &R, ctx: RowCtx<'_>) -> PlyPlace {
    rows.line().map_or_else(
        || PlyPlace::Row {
            element: ctx.element.name.clone(),
            row: row_index(ctx.index),
        },
        PlyPlace::Line,
    )
}

/// A row index as `usize` (saturating; only used in messages and checks).
pub fn row_index(index: u64) -> usize {
    usize::try_from(index).unwrap_or(usize::MAX)
}

/// Reads past every row of an element the mesh does not use.
pub fn skip_element<R: Rows>(rows: &mut R, element: &Element) -> Result<(), PlyMeshError> {
    rows.skip_element(element).map_err(|e| {
        let at = PlyPlace::Row {
            element: element.name.clone(),
            row: 0,
        };
        PlyMeshError::from_body(e, rows.line().map_or(at, PlyPlace::Line))
    })
}

/// Reads one row, handing `(property index, values)` to `take`; an error
/// says where in the file it is.
fn read_row<R: Rows>(
    rows: &mut R,
    ctx: RowCtx<'_>,
    take: impl FnMut(usize, &[f64]),
) -> Result<(), PlyMeshError> {
    let mut items = Vec::new();
    reader::read_row(rows, ctx, Some(&mut items), take)
        .map_err(|e| PlyMeshError::from_body(e, place(rows, ctx)))
}

fn find(element: &Element, names: &[&str], list: bool) -> Option<usize> {
    names.iter().find_map(|n| {
        element
            .properties
            .iter()
            .position(|p| p.name == *n && matches!(p.kind, PropertyKind::List { .. }) == list)
    })
}

/// Reads the vertex element's `x`, `y`, `z` (any numeric type) into `out`.
pub fn read_vertices<R: Rows>(
    rows: &mut R,
    element: &Element,
    out: &mut Vec<[f64; 3]>,
) -> Result<(), PlyMeshError> {
    let axes = ["x", "y", "z"].map(|a| find(element, &[a], false));
    let [Some(x), Some(y), Some(z)] = axes else {
        return Err(PlyMeshError::MissingProperty {
            element: "vertex",
            property: "x, y, z",
        });
    };
    for index in 0..element.count {
        let ctx = RowCtx { element, index };
        let mut p = [f64::NAN; 3];
        read_row(rows, ctx, |k, v| {
            for (axis, &at) in [x, y, z].iter().enumerate() {
                if k == at {
                    p[axis] = v.first().copied().unwrap_or(f64::NAN);
                }
            }
        })?;
        if !p.iter().all(|v| v.is_finite()) {
            return Err(PlyMeshError::NonFinite {
                vertex: row_index(index),
            });
        }
        out.push(p);
    }
    Ok(())
}

/// Reads the face element: corner list, split value and class of each face.
pub fn read_faces<R: Rows>(
    rows: &mut R,
    element: &Element,
    out: &mut Vec<Face>,
) -> Result<(), PlyMeshError> {
    let Some(list) = find(element, &["vertex_indices", "vertex_index"], true) else {
        return Err(PlyMeshError::MissingProperty {
            element: "face",
            property: "vertex_indices",
        });
    };
    let split = find(element, &SPLIT_NAMES, false);
    let class = find(element, &CLASS_NAMES, false);
    let mut corners = Vec::new();
    for index in 0..element.count {
        let ctx = RowCtx { element, index };
        let (mut key, mut kind) = (None, None);
        corners.clear();
        read_row(rows, ctx, |k, v| {
            if k == list {
                corners.extend_from_slice(v);
            } else if Some(k) == split {
                key = v.first().copied();
            } else if Some(k) == class {
                kind = v.first().copied();
            }
        })?;
        let whole = |x: f64| {
            (x.fract() == 0.0 && x.abs() < 9.0e15)
                .then_some(x as i64)
                .ok_or_else(|| PlyMeshError::BadValue {
                    at: place(rows, ctx),
                    token: x.to_string(),
                    ty: "whole number",
                })
        };
        let face = Face {
            corners: corners
                .iter()
                .map(|&i| whole(i))
                .collect::<Result<_, _>>()?,
            key: key.map(whole).transpose()?,
            class: kind.map(whole).transpose()?,
        };
        if face.corners.len() < 3 {
            return Err(PlyMeshError::ShortFace {
                face: row_index(index),
                got: face.corners.len(),
            });
        }
        out.push(face);
    }
    Ok(())
}
