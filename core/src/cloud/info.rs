//! What `skyground info` says about a cloud: size, extent, density, classes.

use std::collections::BTreeMap;

use rustc_hash::FxHashSet;

use super::Cloud;

/// Side of the xy cells over which density is measured, metres.
pub const DENSITY_CELL_M: f64 = 1.0;

/// A cloud's summary; extents both in metres and in the source unit.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CloudInfo {
    /// Number of points.
    pub points: usize,
    /// Lowest corner in the source CRS and unit.
    pub min: [f64; 3],
    /// Highest corner in the source CRS and unit.
    pub max: [f64; 3],
    /// Size of the extent in the source unit.
    pub size: [f64; 3],
    /// Size of the extent in metres.
    pub size_m: [f64; 3],
    /// Area of the occupied [`DENSITY_CELL_M`] cells, m².
    pub occupied_m2: f64,
    /// Points per m² over the occupied cells (empty ground does not dilute it).
    pub density_per_m2: f64,
    /// Points per class code, when the cloud has labels.
    pub classes: Option<BTreeMap<u8, usize>>,
}

/// Summarises `cloud`; `None` when it is empty.
pub fn cloud_info(cloud: &Cloud) -> Option<CloudInfo> {
    let (lo, hi) = cloud.bounds()?;
    let min = cloud.source_coordinates(lo);
    let max = cloud.source_coordinates(hi);
    let size = [0, 1, 2].map(|k| max[k] - min[k]);
    let size_m = [0, 1, 2].map(|k| f64::from(hi[k]) - f64::from(lo[k]));
    let cells: FxHashSet<(i64, i64)> = cloud
        .xyz
        .iter()
        .map(|p| {
            let key = |k: usize| ((f64::from(p[k]) - f64::from(lo[k])) / DENSITY_CELL_M).floor();
            // Cell indices of a bounded cloud: far inside i64.
            (key(0) as i64, key(1) as i64)
        })
        .collect();
    let occupied_m2 = cells.len() as f64 * DENSITY_CELL_M * DENSITY_CELL_M;
    let classes = cloud.label_histogram().map(|h| {
        h.iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
            // Index of a 256-entry table: fits u8.
            .map(|(c, n)| (c as u8, *n))
            .collect()
    });
    Some(CloudInfo {
        points: cloud.len(),
        min,
        max,
        size,
        size_m,
        occupied_m2,
        density_per_m2: cloud.len() as f64 / occupied_m2.max(f64::MIN_POSITIVE),
        classes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::crs::LinearUnit;

    #[test]
    fn density_counts_occupied_cells_only_and_extent_keeps_feet() {
        // 4 points per cell in 2 cells 10 m apart: 4 pts/m², not 8 / 11 m².
        let mut xyz = Vec::new();
        for x0 in [0.0f32, 10.0] {
            for d in [0.1, 0.3, 0.5, 0.7] {
                xyz.push([x0 + d, d, 1.0]);
            }
        }
        let mut c = Cloud::from_xyz(xyz);
        c.label = Some(vec![2; 8]);
        let i = cloud_info(&c).unwrap();
        assert_eq!(i.points, 8);
        assert_eq!(i.occupied_m2, 2.0);
        assert_eq!(i.density_per_m2, 4.0);
        assert_eq!(i.classes, Some(BTreeMap::from([(2, 8)])));
        c.set_unit(LinearUnit::Foot);
        let f = cloud_info(&c).unwrap();
        assert!((f.size[0] - 10.6).abs() < 1e-5, "{:?}", f.size);
        assert!((f.size_m[0] - 10.6 * 0.3048).abs() < 1e-5);
        assert!(cloud_info(&Cloud::default()).is_none());
    }
}
