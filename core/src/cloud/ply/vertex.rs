//! Which vertex properties we keep, and turning vertex rows into a [`Cloud`].
//!
//! Names are matched ASCII-case-insensitively; when several properties map to
//! the same attribute (say `label` and `classification`), the first one wins.

use super::PlyError;
use super::header::{Element, PropertyKind};
use super::rows::{RowCtx, Rows, read_row};
use crate::cloud::Cloud;
use crate::cloud::origin::{local_origin, to_local};

/// What a vertex property feeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    X,
    Y,
    Z,
    Intensity,
    Label,
    Building,
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl Role {
    fn of(name: &str) -> Option<Self> {
        let is = |names: &[&str]| names.iter().any(|n| n.eq_ignore_ascii_case(name));
        Some(if is(&["x"]) {
            Self::X
        } else if is(&["y"]) {
            Self::Y
        } else if is(&["z"]) {
            Self::Z
        } else if is(&["intensity", "scalar_intensity"]) {
            Self::Intensity
        } else if is(&["label", "class", "classification", "scalar_classification"]) {
            Self::Label
        } else if is(&["building", "building_id"]) {
            Self::Building
        } else {
            return None;
        })
    }

    fn slot(self) -> usize {
        self as usize
    }
}

/// The role of each vertex property, checked against the header.
#[derive(Debug, Clone)]
pub struct VertexPlan {
    roles: Vec<Option<Role>>,
    names: [String; 6],
    present: [bool; 6],
}

impl VertexPlan {
    /// Assigns roles and checks that x, y, z exist as float/double and kept attributes are scalars.
    pub fn new(vertex: &Element) -> Result<Self, PlyError> {
        let mut plan = Self {
            roles: Vec::with_capacity(vertex.properties.len()),
            names: Default::default(),
            present: [false; 6],
        };
        for p in &vertex.properties {
            let role = Role::of(&p.name).filter(|r| !plan.present[r.slot()]);
            if let Some(role) = role {
                check_kind(role, &p.name, p.kind)?;
                plan.present[role.slot()] = true;
                plan.names[role.slot()].clone_from(&p.name);
            }
            plan.roles.push(role);
        }
        for (axis, present) in AXES.iter().zip(plan.present) {
            if !present {
                return Err(PlyError::MissingCoordinate { axis });
            }
        }
        Ok(plan)
    }
}

fn check_kind(role: Role, name: &str, kind: PropertyKind) -> Result<(), PlyError> {
    let axis = AXES.get(role.slot()).copied();
    match (axis, kind) {
        (Some(_), PropertyKind::Scalar(s)) if s.is_float() => Ok(()),
        (Some(axis), PropertyKind::Scalar(s)) => Err(PlyError::CoordinateType {
            axis,
            found: s.name().into(),
        }),
        (Some(axis), PropertyKind::List { .. }) => Err(PlyError::CoordinateType {
            axis,
            found: "a list".into(),
        }),
        (None, PropertyKind::List { .. }) => Err(PlyError::ListAttribute { name: name.into() }),
        (None, PropertyKind::Scalar(_)) => Ok(()),
    }
}

/// Reads every row of the vertex element into a cloud.
///
/// With `origin` given (our own files) the coordinates are already local;
/// otherwise the origin is [`local_origin`] of the first vertex and is subtracted.
pub fn read_vertices<R: Rows>(
    rows: &mut R,
    vertex: &Element,
    plan: &VertexPlan,
    origin: Option<[f64; 3]>,
) -> Result<Cloud, PlyError> {
    let capacity = usize::try_from(vertex.count.min(rows.max_rows(vertex))).unwrap_or(0);
    fn column<T>(plan: &VertexPlan, role: Role, capacity: usize) -> Option<Vec<T>> {
        plan.present[role.slot()].then(|| Vec::with_capacity(capacity))
    }
    let mut cloud = Cloud {
        xyz: Vec::with_capacity(capacity),
        intensity: column(plan, Role::Intensity, capacity),
        label: column(plan, Role::Label, capacity),
        building: column(plan, Role::Building, capacity),
        return_number: None,
        number_of_returns: None,
        origin: origin.unwrap_or_default(),
        crs: None,
    };
    let mut values = [0.0f64; 6];
    let mut shift = [0.0f64; 3];
    for index in 0..vertex.count {
        let ctx = RowCtx {
            element: vertex,
            index,
        };
        read_row(rows, ctx, None, |k, v| {
            if let (Some(Some(role)), [v]) = (plan.roles.get(k), v) {
                values[role.slot()] = *v;
            }
        })?;
        if index == 0 && origin.is_none() {
            shift = local_origin([values[0], values[1], values[2]]);
            cloud.origin = shift;
        }
        push_vertex(&mut cloud, plan, index, &values, shift)?;
    }
    Ok(cloud)
}

fn push_vertex(
    cloud: &mut Cloud,
    plan: &VertexPlan,
    index: u64,
    v: &[f64; 6],
    shift: [f64; 3],
) -> Result<(), PlyError> {
    let mut p = [0.0f32; 3];
    for (((slot, axis), &value), o) in p.iter_mut().zip(AXES).zip(v).zip(shift) {
        *slot = to_local(value, o).ok_or(PlyError::BadCoordinate { index, axis, value })?;
    }
    cloud.xyz.push(p);
    if let Some(col) = &mut cloud.intensity {
        // Intensity is stored as f32 whatever its PLY type.
        col.push(v[Role::Intensity.slot()] as f32);
    }
    let range_error = |role: Role, range| PlyError::AttributeRange {
        index,
        property: plan.names[role.slot()].clone(),
        value: v[role.slot()],
        range,
    };
    if let Some(col) = &mut cloud.label {
        let value = whole(v[Role::Label.slot()], u8::MAX.into())
            .and_then(|w| u8::try_from(w).ok())
            .ok_or_else(|| range_error(Role::Label, "0..=255"))?;
        col.push(value);
    }
    if let Some(col) = &mut cloud.building {
        let value = whole(v[Role::Building.slot()], u32::MAX.into())
            .and_then(|w| u32::try_from(w).ok())
            .ok_or_else(|| range_error(Role::Building, "0..=4294967295"))?;
        col.push(value);
    }
    Ok(())
}

/// `v` as an integer when it is a whole number in `0..=max`.
fn whole(v: f64, max: f64) -> Option<u64> {
    // In range and whole, so the conversion is exact.
    (v.fract() == 0.0 && (0.0..=max).contains(&v)).then_some(v as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aliases_map_to_roles() {
        assert_eq!(Role::of("scalar_Classification"), Some(Role::Label));
        assert_eq!(Role::of("class"), Some(Role::Label));
        assert_eq!(Role::of("scalar_intensity"), Some(Role::Intensity));
        assert_eq!(Role::of("building_id"), Some(Role::Building));
        assert_eq!(Role::of("X"), Some(Role::X));
        assert_eq!(Role::of("nx"), None);
    }

    #[test]
    fn whole_rejects_fractions_and_out_of_range() {
        assert_eq!(whole(6.0, 255.0), Some(6));
        assert_eq!(whole(6.5, 255.0), None);
        assert_eq!(whole(-1.0, 255.0), None);
        assert_eq!(whole(256.0, 255.0), None);
        assert_eq!(whole(f64::NAN, 255.0), None);
    }
}
