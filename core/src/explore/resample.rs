//! Voxel de-duplication of merged clouds (for /resampled_cloud).

use std::collections::HashSet;

use super::error::ExploreError;

/// Keeps the first point of every `voxel`-wide cube, in input order;
/// non-finite points are dropped.
pub fn resample(points: &[[f32; 3]], voxel: f32) -> Result<Vec<[f32; 3]>, ExploreError> {
    if !(voxel.is_finite() && voxel > 0.0) {
        return Err(ExploreError::Voxel(voxel));
    }
    let mut seen = HashSet::with_capacity(points.len() / 2);
    Ok(points
        .iter()
        .filter(|p| p.iter().all(|v| v.is_finite()))
        .filter(|p| {
            let key: [i64; 3] =
                std::array::from_fn(|k| (f64::from(p[k]) / f64::from(voxel)).floor() as i64);
            seen.insert(key)
        })
        .copied()
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_point_per_voxel() {
        let pts = [
            [0.1, 0.1, 0.1],
            [0.2, 0.3, 0.4],
            [1.1, 0.1, 0.1],
            [f32::NAN, 0.0, 0.0],
            [-0.1, 0.0, 0.0],
        ];
        let r = resample(&pts, 0.5).unwrap();
        assert_eq!(r, vec![[0.1, 0.1, 0.1], [1.1, 0.1, 0.1], [-0.1, 0.0, 0.0]]);
        assert_eq!(resample(&pts, 0.0), Err(ExploreError::Voxel(0.0)));
        assert!(resample(&[], 0.1).unwrap().is_empty());
    }
}
