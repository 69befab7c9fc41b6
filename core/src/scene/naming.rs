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

/// The class an OBJ material names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MaterialClass {
    /// A kind of scene object.
    Kind(ObjectKind),
    /// A class the scene leaves out, as the CityJSON reader leaves out
    /// `WaterBody` and `Bridge`: water, bridges, separation walls.
    LeftOut,
}

/// The class a material name announces (case-insensitive prefix): an object
/// name's kinds ([`kind_from_name`]), and 3dfier's classes as the CityJSON
/// reader maps them (`Road` and `Forest`, its `PlantCover`, are ground;
/// `Water`, `Bridge` and `Separation` left out); `None` for anything else
/// (a colour, a texture).
pub fn kind_from_material(name: &str) -> Option<MaterialClass> {
    if let Some(kind) = kind_from_name(name) {
        return Some(MaterialClass::Kind(kind));
    }
    let n = name.trim().to_ascii_lowercase();
    let starts = |prefixes: &[&str]| prefixes.iter().any(|p| n.starts_with(p));
    if starts(&["road", "forest"]) {
        Some(MaterialClass::Kind(ObjectKind::Ground))
    } else if starts(&["water", "bridge", "separation"]) {
        Some(MaterialClass::LeftOut)
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
        assert_eq!(
            kind_from_material("Road"),
            Some(MaterialClass::Kind(ObjectKind::Ground))
        );
        assert_eq!(kind_from_material("Water"), Some(MaterialClass::LeftOut));
        assert_eq!(kind_from_material("red"), None);
    }
}
