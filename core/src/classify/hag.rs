//! Height above ground from the points flagged as ground: inverse-distance
//! weighting of the nearest ground points in plan. A stand-in for the
//! ground filter's own surface; swap in the CSF cloth heights when present.

use std::num::NonZeroUsize;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

use super::error::ClassifyError;
use crate::cloud::ColumnLength;

/// Ground points interpolated per query.
const NEIGHBOURS: usize = 6;

/// Height of every point above the ground interpolated from the points
/// with `is_ground` set (ground points get ≈ 0).
pub fn hag_from_ground_points(
    xyz: &[[f32; 3]],
    is_ground: &[bool],
) -> Result<Vec<f32>, ClassifyError> {
    ColumnLength::check("is_ground", xyz.len(), is_ground.len())?;
    if let Some(index) = xyz.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
        return Err(ClassifyError::NonFinite { index });
    }
    let ground: Vec<[f32; 3]> = xyz
        .iter()
        .zip(is_ground)
        .filter(|(_, g)| **g)
        .map(|(p, _)| *p)
        .collect();
    if ground.is_empty() {
        return Err(ClassifyError::NoGround);
    }
    let plan: Vec<[f32; 2]> = ground.iter().map(|p| [p[0], p[1]]).collect();
    let tree =
        ImmutableKdTree::<f32, 2>::new_from_slice(&plan).map_err(|_| ClassifyError::NoGround)?;
    let k = NonZeroUsize::new(NEIGHBOURS.min(ground.len())).unwrap_or(NonZeroUsize::MIN);
    Ok(xyz
        .par_iter()
        .map(|p| {
            let near = tree
                .query(&[p[0], p[1]])
                .nearest_n::<SquaredEuclidean<f32>>(k)
                .execute();
            let (mut wz, mut w) = (0.0f64, 0.0f64);
            for nb in &near {
                let d2 = f64::from(nb.distance);
                if d2 < 1e-8 {
                    (wz, w) = (f64::from(ground[nb.item as usize][2]), 1.0);
                    break;
                }
                wz += f64::from(ground[nb.item as usize][2]) / d2;
                w += 1.0 / d2;
            }
            if w > 0.0 { p[2] - (wz / w) as f32 } else { 0.0 }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sloped_ground_and_errors() {
        // Ground z = 0.1 x on a grid; a roof point 8 m above it.
        let mut xyz = crate::geom::fixtures::lattice(20, 20, 1.0, |x, _| 0.1 * x);
        let mut flags = vec![true; xyz.len()];
        xyz.push([10.5, 10.5, 1.05 + 8.0]);
        flags.push(false);
        let h = hag_from_ground_points(&xyz, &flags).unwrap();
        assert!((h[400] - 8.0).abs() < 0.05, "{}", h[400]);
        assert!(h[..400].iter().all(|v| v.abs() < 1e-5));
        assert!(matches!(
            hag_from_ground_points(&xyz, &flags[..3]),
            Err(ClassifyError::LengthMismatch(_))
        ));
        assert!(matches!(
            hag_from_ground_points(&xyz, &vec![false; xyz.len()]),
            Err(ClassifyError::NoGround)
        ));
    }
}
