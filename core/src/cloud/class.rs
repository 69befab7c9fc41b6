//! The point classes skyground uses: ASPRS LAS classification codes, so a
//! classified cloud opens with its classes in any LAS tool.

/// Never classified (LAS 0).
pub const CREATED: u8 = 0;
/// Looked at, no class found (LAS 1).
pub const UNCLASSIFIED: u8 = 1;
/// Bare earth, streets, open ground (LAS 2).
pub const GROUND: u8 = 2;
/// Low vegetation (LAS 3).
pub const LOW_VEGETATION: u8 = 3;
/// Medium vegetation (LAS 4).
pub const MEDIUM_VEGETATION: u8 = 4;
/// High vegetation: trees (LAS 5). The classifier's one vegetation class.
pub const VEGETATION: u8 = 5;
/// Building (LAS 6).
pub const BUILDING: u8 = 6;

/// Folds a producer's LAS class into the three classes skyground tells
/// apart (ground, vegetation, building), or `UNCLASSIFIED` for the rest
/// (wires, water, noise, ...).
pub fn fold(code: u8) -> u8 {
    match code {
        GROUND => GROUND,
        LOW_VEGETATION | MEDIUM_VEGETATION | VEGETATION => VEGETATION,
        BUILDING => BUILDING,
        _ => UNCLASSIFIED,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vegetation_classes_fold_into_one() {
        assert_eq!(fold(3), VEGETATION);
        assert_eq!(fold(4), VEGETATION);
        assert_eq!(fold(6), BUILDING);
        assert_eq!(fold(14), UNCLASSIFIED);
        assert_eq!(fold(0), UNCLASSIFIED);
    }
}
