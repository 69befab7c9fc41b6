//! Object kinds from object names, as scene files spell them.

use super::ObjectKind;

/// The kind an object name announces (case-insensitive prefix):
/// `ground*` / `terrain*` → Ground, `building*` → Building,
/// `tree*` / `vegetation*` → Vegetation; `None` for anything else.
pub fn kind_from_name(name: &str) -> Option<ObjectKind> {
    let n = name.trim().to_ascii_lowercase();
    let starts = |prefixes: &[&str]| prefixes.iter().any(|p| n.starts_with(p));
    if starts(&["ground", "terrain"]) {
        Some(ObjectKind::Ground)
    } else if starts(&["building"]) {
        Some(ObjectKind::Building)
    } else if starts(&["tree", "vegetation"]) {
        Some(ObjectKind::Vegetation)
    } else {
        None
    }
}

/// What to do with an object whose name announces no kind.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum UnknownObjects {
    /// Fail with an error naming the object (the default: a misread scene is
    /// worse than none).
    #[default]
    Error,
    /// Treat it as a building.
    Building,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixes() {
        assert_eq!(kind_from_name("Terrain_01"), Some(ObjectKind::Ground));
        assert_eq!(kind_from_name("ground"), Some(ObjectKind::Ground));
        assert_eq!(kind_from_name("BUILDING.003"), Some(ObjectKind::Building));
        assert_eq!(kind_from_name("tree_4"), Some(ObjectKind::Vegetation));
        assert_eq!(kind_from_name("vegetation"), Some(ObjectKind::Vegetation));
        assert_eq!(kind_from_name("Cube.001"), None);
    }
}
