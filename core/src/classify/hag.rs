//! Height above ground from the points flagged as ground (a labelled
//! cloud without a cloth run): the terrain model built from them, as
//! detection and targets build it.

use rayon::prelude::*;

use super::error::ClassifyError;
use crate::ground::Dtm;

/// Terrain cell, metres: fine enough that a cell's mean height is the
/// terrain at its centre on the slopes of a city.
const TERRAIN_CELL: f32 = 1.0;

/// Height of every point above the ground interpolated from the points
/// with `is_ground` set (ground points get ≈ 0).
pub fn hag_from_ground_points(
    xyz: &[[f32; 3]],
    is_ground: &[bool],
) -> Result<Vec<f32>, ClassifyError> {
    if is_ground.len() != xyz.len() {
        return Err(ClassifyError::LengthMismatch {
            what: "is_ground",
            expected: xyz.len(),
            got: is_ground.len(),
        });
    }
    if let Some(index) = xyz.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
        return Err(ClassifyError::NonFinite { index });
    }
    let ground = xyz
        .iter()
        .zip(is_ground)
        .filter(|(_, g)| **g)
        .map(|(p, _)| p);
    let dtm =
        Dtm::from_ground_points(ground, TERRAIN_CELL, usize::MAX).ok_or(ClassifyError::NoGround)?;
    Ok(xyz
        .par_iter()
        .map(|p| p[2] - dtm.height_at(p[0], p[1]))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sloped_ground_and_errors() {
        // Ground z = 0.1 x sampled every 0.25 m; a roof point 8 m above it.
        let mut xyz = crate::geom::fixtures::lattice(80, 80, 0.25, |x, _| 0.1 * x);
        let n = xyz.len();
        let mut flags = vec![true; n];
        xyz.push([10.2, 10.7, 1.02 + 8.0]);
        flags.push(false);
        let h = hag_from_ground_points(&xyz, &flags).unwrap();
        // A cell's mean sits an eighth of a metre before its centre: 1.25 cm on this slope.
        assert!((h[n] - 8.0).abs() < 0.02, "{}", h[n]);
        // Beyond the last centre the edge value holds: 3.75 cm at the far edge.
        assert!(h[..n].iter().all(|v| v.abs() < 0.04));
        assert!(matches!(
            hag_from_ground_points(&xyz, &flags[..3]),
            Err(ClassifyError::LengthMismatch { .. })
        ));
        assert!(matches!(
            hag_from_ground_points(&xyz, &vec![false; xyz.len()]),
            Err(ClassifyError::NoGround)
        ));
    }
}
