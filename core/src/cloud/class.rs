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

/// Bridge deck (LAS 17).
pub const BRIDGE_DECK: u8 = 17;

/// Low noise (LAS 7).
pub const LOW_NOISE: u8 = 7;
/// High noise (LAS 18, from LAS 1.4).
pub const HIGH_NOISE: u8 = 18;

/// True for a producer's noise classes: such points are left out of ground
/// filtering and classification (a return from below the ground would hold
/// the terrain down; a bird would be a roof) and keep their class.
pub fn is_noise(code: u8) -> bool {
    matches!(code, LOW_NOISE | HIGH_NOISE)
}

/// True for the producer classes the classifier replaces with its own:
/// never classified, unclassified, ground, vegetation and building, and
/// LAS 1.1–1.3's model key-point (8) and overlap (12), which say no more
/// than that. Water, bridges, wires, noise, roads and producers' own codes
/// (AHN's 26, IGN's 64–67) say more than ground, vegetation or building
/// could, and are kept.
pub fn replaced_by_classifier(code: u8) -> bool {
    matches!(code, 0..=6 | 8 | 12)
}

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

    #[test]
    fn noise_and_specific_classes_are_the_producers() {
        assert!(is_noise(7) && is_noise(18) && !is_noise(1));
        for code in [0, 1, 2, 3, 4, 5, 6, 8, 12] {
            assert!(replaced_by_classifier(code), "{code}");
        }
        for code in [7, 9, 10, 11, 13, 14, 15, 16, 17, 18, 26, 64, 65, 66, 67] {
            assert!(!replaced_by_classifier(code), "{code}");
        }
    }
}
