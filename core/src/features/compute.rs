//! The feature matrix of a cloud: one row per point, [`FEATURE_NAMES`] columns.

use std::num::NonZeroUsize;

use kiddo::ImmutableKdTree;
use rayon::prelude::*;

use super::echo::{Echoes, UNKNOWN, voxel_counts};
use super::error::FeatureError;
use super::params::FeatureParams;
use super::voxel::{ScaleStats, VoxelStats, thin, voxel_stats};
use crate::cloud::ColumnLength;
use crate::geom::shape::nearest_moments;

/// Column names of [`Features::data`], in order. `knn_*` lengths are divided
/// by the k-NN radius (scale-free); `r1_*` / `r2_*` are the small / large
/// radius spheres on voxel centroids, in metres where they are lengths;
/// `echo_*` are [`super::echo`]'s (−1 without echo information).
pub const FEATURE_NAMES: [&str; 30] = [
    "hag",
    "knn_linearity",
    "knn_planarity",
    "knn_sphericity",
    "knn_curvature",
    "knn_normal_z",
    "knn_roughness",
    "knn_z_range",
    "knn_z_offset",
    "r1_linearity",
    "r1_planarity",
    "r1_sphericity",
    "r1_curvature",
    "r1_normal_z",
    "r1_z_range",
    "r1_z_offset",
    "r2_linearity",
    "r2_planarity",
    "r2_sphericity",
    "r2_curvature",
    "r2_normal_z",
    "r2_z_range",
    "r2_z_offset",
    "count_ratio",
    "column_above",
    "column_below",
    "echo_returns",
    "echo_place",
    "echo_multiple_r1",
    "echo_multiple_column",
];

/// Number of features per point.
pub const DIMS: usize = FEATURE_NAMES.len();

/// Column of `r1_planarity` (the 1.5 m sphere's planarity) in [`FEATURE_NAMES`].
pub const R1_PLANARITY: usize = 10;

/// A row-major feature matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct Features {
    /// Columns per row (= `FEATURE_NAMES.len()`).
    pub dims: usize,
    /// `rows × dims` values, row-major.
    pub data: Vec<f32>,
}

impl Features {
    /// Number of rows.
    pub fn len(&self) -> usize {
        self.data.len() / self.dims.max(1)
    }

    /// True when there are no rows.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// One row.
    pub fn row(&self, i: usize) -> &[f32] {
        &self.data[i * self.dims..(i + 1) * self.dims]
    }
}

/// Features of every point of `xyz`, given each point's height above the
/// ground model `hag` (metres) and, when the cloud has them, its echoes.
pub fn compute(
    xyz: &[[f32; 3]],
    hag: &[f32],
    echoes: Option<Echoes<'_>>,
    params: &FeatureParams,
) -> Result<Features, FeatureError> {
    let rows: Vec<usize> = (0..xyz.len()).collect();
    compute_subset(xyz, hag, echoes, &rows, params)
}

/// Features of the points `rows` of `xyz` (in that order); neighbourhoods
/// still use the whole cloud. For training on a sample of a large cloud,
/// or classifying only the points that are not ground.
pub fn compute_subset(
    xyz: &[[f32; 3]],
    hag: &[f32],
    echoes: Option<Echoes<'_>>,
    rows: &[usize],
    params: &FeatureParams,
) -> Result<Features, FeatureError> {
    check_request(xyz, hag, echoes.as_ref(), rows, params)?;
    let tree =
        ImmutableKdTree::<f32, 3>::new_from_slice(xyz).map_err(|_| FeatureError::TooFewPoints {
            got: xyz.len(),
            need: params.min_points(),
        })?;
    let voxels = thin(xyz, params.voxel_m);
    let mut needed = vec![false; voxels.centroid.len()];
    for &r in rows {
        needed[voxels.of_point[r] as usize] = true;
    }
    let counts = echoes
        .as_ref()
        .map(|e| voxel_counts(&voxels.of_point, voxels.centroid.len(), e));
    let stats = voxel_stats(&voxels, &needed, params, counts.as_deref());
    let k = NonZeroUsize::new((params.k + 1).min(xyz.len())).unwrap_or(NonZeroUsize::MIN);
    let mut data = vec![0.0f32; rows.len() * DIMS];
    data.par_chunks_mut(DIMS)
        .zip(rows.par_iter())
        .for_each(|(out, &r)| {
            let p = xyz[r];
            let mut r2 = 0.0f32;
            let m = nearest_moments(&tree, xyz, p, k, |_, d2| r2 = r2.max(d2));
            let radius = f64::from(r2.sqrt()).max(1e-6);
            let s = m.shape();
            // The point's distance from the fitted plane (the anchor is the point).
            let off: f64 = (0..3).map(|i| -s.mean[i] * s.normal[i]).sum();
            out[0] = hag[r];
            out[1] = s.linearity as f32;
            out[2] = s.planarity as f32;
            out[3] = s.sphericity as f32;
            out[4] = s.curvature as f32;
            out[5] = s.normal[2].abs() as f32;
            out[6] = (off.abs() / radius) as f32;
            out[7] = ((s.z_max - s.z_min) / radius) as f32;
            out[8] = (-s.mean[2] / radius) as f32;
            let v: &VoxelStats = &stats[voxels.of_point[r] as usize];
            write_scale(&mut out[9..16], &v.small, p[2]);
            write_scale(&mut out[16..23], &v.large, p[2]);
            out[23] = v.count_ratio;
            out[24] = (v.column_top - p[2]).max(0.0);
            out[25] = (p[2] - v.column_bottom).max(0.0);
            let [returns, place] = echoes.as_ref().map_or([UNKNOWN; 2], |e| e.point(r));
            out[26] = returns;
            out[27] = place;
            out[28] = v.multiple_small;
            out[29] = v.multiple_column;
            for x in out.iter_mut() {
                if !x.is_finite() {
                    *x = 0.0;
                }
            }
        });
    Ok(Features { dims: DIMS, data })
}

/// Everything [`compute_subset`] refuses, checked before any work: the
/// parameters, the cloud, its columns' lengths and the rows asked for.
pub(crate) fn check_request(
    xyz: &[[f32; 3]],
    hag: &[f32],
    echoes: Option<&Echoes<'_>>,
    rows: &[usize],
    params: &FeatureParams,
) -> Result<(), FeatureError> {
    params.validate()?;
    check_input(xyz, hag, params)?;
    if let Some(e) = echoes {
        for (what, got) in [
            ("return_number", e.return_number.len()),
            ("number_of_returns", e.number_of_returns.len()),
        ] {
            ColumnLength::check(what, xyz.len(), got)?;
        }
    }
    if let Some(&row) = rows.iter().find(|&&r| r >= xyz.len()) {
        return Err(FeatureError::RowOutOfRange {
            row,
            len: xyz.len(),
        });
    }
    Ok(())
}

fn write_scale(out: &mut [f32], s: &ScaleStats, z: f32) {
    out[..6].copy_from_slice(&s[..6]);
    out[6] = z - s[6];
}

fn check_input(xyz: &[[f32; 3]], hag: &[f32], params: &FeatureParams) -> Result<(), FeatureError> {
    let need = params.min_points();
    if xyz.is_empty() {
        return Err(FeatureError::Empty { need });
    }
    ColumnLength::check("hag", xyz.len(), hag.len())?;
    if xyz.len() < need {
        return Err(FeatureError::TooFewPoints {
            got: xyz.len(),
            need,
        });
    }
    if let Some(index) = xyz.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
        return Err(FeatureError::NonFinite { what: "xyz", index });
    }
    if let Some(index) = hag.iter().position(|v| !v.is_finite()) {
        return Err(FeatureError::NonFinite { what: "hag", index });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn named_columns_point_at_their_names() {
        assert_eq!(FEATURE_NAMES[R1_PLANARITY], "r1_planarity");
    }

    use super::*;

    #[test]
    fn roof_plane_versus_blob() {
        // A flat roof 10 m up and a noisy ball: the roof is planar, the ball is not.
        let mut xyz = crate::geom::fixtures::lattice(40, 40, 0.25, |_, _| 10.0);
        let mut s = 1u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 40) as f32 / (1u64 << 24) as f32 - 0.5
        };
        for _ in 0..1600 {
            xyz.push([30.0 + 4.0 * rnd(), 30.0 + 4.0 * rnd(), 8.0 + 4.0 * rnd()]);
        }
        let hag: Vec<f32> = xyz.iter().map(|p| p[2]).collect();
        let f = compute(&xyz, &hag, None, &FeatureParams::default()).unwrap();
        assert_eq!(f.len(), xyz.len());
        assert!(f.data.iter().all(|v| v.is_finite()));
        let col = |name: &str| FEATURE_NAMES.iter().position(|n| *n == name).unwrap();
        let roof = f.row(20 * 40 + 20);
        let blob = f.row(1600 + 10);
        assert!(roof[col("knn_planarity")] > 0.5 && roof[col("knn_normal_z")] > 0.99);
        assert!(blob[col("knn_sphericity")] > roof[col("knn_sphericity")] + 0.1);
        assert!(roof[col("r1_curvature")] < 1e-3 && blob[col("r2_curvature")] > 0.1);
        assert!((roof[col("count_ratio")] - 2.0).abs() < 0.5);
    }

    #[test]
    fn bad_input_is_typed() {
        let p = FeatureParams::default();
        assert!(matches!(
            compute(&[], &[], None, &p),
            Err(FeatureError::Empty { .. })
        ));
        let xyz = vec![
            [0.0f32, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.5],
        ];
        assert!(matches!(
            compute(&xyz, &[0.0; 3], None, &p),
            Err(FeatureError::LengthMismatch(ColumnLength { got: 3, .. }))
        ));
        let mut nan = xyz.clone();
        nan[2][1] = f32::NAN;
        assert!(matches!(
            compute(&nan, &[0.0; 4], None, &p),
            Err(FeatureError::NonFinite { index: 2, .. })
        ));
        assert!(matches!(
            compute(&xyz[..2], &[0.0; 2], None, &p),
            Err(FeatureError::TooFewPoints { got: 2, .. })
        ));
        assert!(matches!(
            compute_subset(&xyz, &[0.0; 4], None, &[7], &p),
            Err(FeatureError::RowOutOfRange { row: 7, .. })
        ));
        let bad = FeatureParams { k: 1, ..p };
        assert!(matches!(
            compute(&xyz, &[0.0; 4], None, &bad),
            Err(FeatureError::Param(_))
        ));
        // Duplicates are degenerate, not NaN.
        let f = compute(
            &[[1.0, 2.0, 3.0]; 10],
            &[0.0; 10],
            None,
            &FeatureParams::default(),
        )
        .unwrap();
        assert!(f.data.iter().all(|v| v.is_finite()));
    }
}
