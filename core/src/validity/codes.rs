//! val3dity's error codes for the checks this module runs, and their names.

/// A ring with fewer than 3 distinct vertices.
pub const TOO_FEW_POINTS: u16 = 101;
/// Two consecutive vertices of a ring at the same position.
pub const CONSECUTIVE_POINTS_SAME: u16 = 102;
/// A ring crossing or touching itself, or visiting a vertex twice.
pub const RING_SELF_INTERSECTION: u16 = 104;
/// An inner ring crossing the outer ring or another inner ring.
pub const INTERSECTION_RINGS: u16 = 201;
/// A vertex farther than the tolerance from the surface's plane.
pub const NON_PLANAR_POLYGON_DISTANCE_PLANE: u16 = 203;
/// A triangle of the surface tilted more than the tolerance from its plane.
pub const NON_PLANAR_POLYGON_NORMALS_DEVIATION: u16 = 204;
/// An inner ring outside the outer ring.
pub const INNER_RING_OUTSIDE: u16 = 206;
/// An inner ring turning the same way as the outer ring.
pub const ORIENTATION_RINGS_SAME: u16 = 208;
/// A shell with fewer than 4 surfaces.
pub const TOO_FEW_POLYGONS: u16 = 301;
/// An edge used by only one surface: the shell has a hole.
pub const SHELL_NOT_CLOSED: u16 = 302;
/// An edge used by more than two surfaces, or a vertex where surfaces meet in more than one fan.
pub const NON_MANIFOLD_CASE: u16 = 303;
/// Surfaces falling into groups not connected by edges.
pub const MULTIPLE_CONNECTED_COMPONENTS: u16 = 305;
/// Two surfaces crossing or touching other than along shared edges and vertices.
pub const SHELL_SELF_INTERSECTION: u16 = 306;
/// A surface whose normal points the wrong way.
pub const POLYGON_WRONG_ORIENTATION: u16 = 307;
/// Input the checks cannot read (here: a vertex index out of range).
pub const INVALID_INPUT_FILE: u16 = 901;
/// A solid without shells.
pub const EMPTY_PRIMITIVE: u16 = 902;

/// val3dity's name of `code` (e.g. 302 → `SHELL_NOT_CLOSED`); `UNKNOWN` for codes not listed here.
pub fn code_name(code: u16) -> &'static str {
    match code {
        TOO_FEW_POINTS => "TOO_FEW_POINTS",
        CONSECUTIVE_POINTS_SAME => "CONSECUTIVE_POINTS_SAME",
        RING_SELF_INTERSECTION => "RING_SELF_INTERSECTION",
        INTERSECTION_RINGS => "INTERSECTION_RINGS",
        NON_PLANAR_POLYGON_DISTANCE_PLANE => "NON_PLANAR_POLYGON_DISTANCE_PLANE",
        NON_PLANAR_POLYGON_NORMALS_DEVIATION => "NON_PLANAR_POLYGON_NORMALS_DEVIATION",
        INNER_RING_OUTSIDE => "INNER_RING_OUTSIDE",
        ORIENTATION_RINGS_SAME => "ORIENTATION_RINGS_SAME",
        TOO_FEW_POLYGONS => "TOO_FEW_POLYGONS",
        SHELL_NOT_CLOSED => "SHELL_NOT_CLOSED",
        NON_MANIFOLD_CASE => "NON_MANIFOLD_CASE",
        MULTIPLE_CONNECTED_COMPONENTS => "MULTIPLE_CONNECTED_COMPONENTS",
        SHELL_SELF_INTERSECTION => "SHELL_SELF_INTERSECTION",
        POLYGON_WRONG_ORIENTATION => "POLYGON_WRONG_ORIENTATION",
        INVALID_INPUT_FILE => "INVALID_INPUT_FILE",
        EMPTY_PRIMITIVE => "EMPTY_PRIMITIVE",
        _ => "UNKNOWN",
    }
}
