//! How large a cloud may be in plan before the raster steps (ground model,
//! occupancy and site grids, footprints) could not hold their cells: said
//! from the cloud's extent before anything is allocated.

use super::Cloud;

/// Largest plan area one run grids, m²: 100 km², beyond the largest tiles
/// producers deliver (AHN 31 km², IGN LiDAR HD 1 km²); 0.25 m cells over it
/// are 1.6e9 cells, a few GB per grid.
pub const MAX_PLAN_AREA_M2: f64 = 1e8;

/// The cloud covers more ground than one run can grid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "the points span {:.0} m × {:.0} m in plan ({:.3e} m²), more than the {:.0} km² one run can grid in memory: split the survey into tiles, or check the header's scale and offset",
    size[0], size[1], size[0] * size[1], MAX_PLAN_AREA_M2 / 1e6
)]
pub struct TooLarge {
    /// Plan extent, m.
    pub size: [f64; 2],
}

/// `Err` when `cloud`'s plan extent is above [`MAX_PLAN_AREA_M2`] (or not finite).
pub fn check_plan_extent(cloud: &Cloud) -> Result<(), TooLarge> {
    let Some((lo, hi)) = cloud.bounds() else {
        return Ok(());
    };
    let size = [0, 1].map(|k| f64::from(hi[k]) - f64::from(lo[k]));
    let area = size[0] * size[1];
    if area.is_finite() && area <= MAX_PLAN_AREA_M2 && size.iter().all(|s| s.is_finite()) {
        Ok(())
    } else {
        Err(TooLarge { size })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_survey_tile_passes_and_random_coordinates_do_not() {
        let tile = Cloud::from_xyz(vec![[0.0, 0.0, 0.0], [5000.0, 6250.0, 80.0]]);
        assert_eq!(check_plan_extent(&tile), Ok(()));
        assert_eq!(check_plan_extent(&Cloud::default()), Ok(()));
        // laz-perf's rand1_6.las: coordinates over ±2.1e9 m.
        let random = Cloud::from_xyz(vec![[-2.1e9, -2.1e9, 0.0], [2.1e9, 2.1e9, 0.0]]);
        let e = check_plan_extent(&random).unwrap_err();
        assert!(e.to_string().contains("4200000000 m × 4200000000 m"), "{e}");
        // A long thin strip is judged by its area, not its length.
        let strip = Cloud::from_xyz(vec![[0.0, 0.0, 0.0], [200_000.0, 100.0, 0.0]]);
        assert_eq!(check_plan_extent(&strip), Ok(()));
    }
}
