//! The cloud thinned to one centroid per voxel, and the statistics of the
//! fixed-radius spheres and vertical columns around those centroids.
//!
//! Thinning makes the radius scales independent of point density (a 40
//! pts/m² roof and a 2 pts/m² roof give similar centroid sets) and keeps
//! the radius queries cheap.

use std::collections::HashMap;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

use super::echo;
use super::params::FeatureParams;
use crate::geom::shape::Moments;

/// Voxel centroids and which voxel each point fell into.
pub struct Voxels {
    /// Centroid of each occupied voxel.
    pub centroid: Vec<[f32; 3]>,
    /// Voxel index of each point.
    pub of_point: Vec<u32>,
}

/// Groups points into cubic voxels of edge `edge`.
pub fn thin(xyz: &[[f32; 3]], edge: f32) -> Voxels {
    let mut index: HashMap<[i64; 3], u32> = HashMap::with_capacity(xyz.len() / 4);
    let mut sums: Vec<([f64; 3], u32)> = Vec::new();
    let mut of_point = Vec::with_capacity(xyz.len());
    for p in xyz {
        let key = p.map(|v| (f64::from(v) / f64::from(edge)).floor() as i64);
        let next = u32::try_from(sums.len()).unwrap_or(u32::MAX);
        let id = *index.entry(key).or_insert(next);
        if id == next {
            sums.push(([0.0; 3], 0));
        }
        let s = &mut sums[id as usize];
        for (acc, v) in s.0.iter_mut().zip(p) {
            *acc += f64::from(*v);
        }
        s.1 += 1;
        of_point.push(id);
    }
    let centroid = sums
        .iter()
        .map(|(s, n)| s.map(|v| (v / f64::from(*n)) as f32))
        .collect();
    Voxels { centroid, of_point }
}

/// Shape of one radius scale: linearity, planarity, sphericity, curvature,
/// |normal z|, z extent, and the mean z (absolute, for per-point offsets).
pub type ScaleStats = [f32; 7];

/// What the radius scales and the column say about one voxel.
#[derive(Debug, Clone, Copy, Default)]
pub struct VoxelStats {
    /// The small-radius sphere.
    pub small: ScaleStats,
    /// The large-radius sphere.
    pub large: ScaleStats,
    /// log2 of (centroids in the large sphere / in the small one): ~2 on a
    /// plane, ~3 in a volume, ~1 along a line, whatever the density.
    pub count_ratio: f32,
    /// Highest centroid z in the vertical column.
    pub column_top: f32,
    /// Lowest centroid z in the vertical column.
    pub column_bottom: f32,
    /// Share of multiple-return points in the small sphere (echo::UNKNOWN
    /// without echo information).
    pub multiple_small: f32,
    /// Share of multiple-return points in the vertical column.
    pub multiple_column: f32,
}

/// Statistics of the voxels flagged in `needed` (the others stay default).
/// `counts`: points and multiple-return points per voxel, when the cloud
/// has echo information.
pub fn voxel_stats(
    voxels: &Voxels,
    needed: &[bool],
    params: &FeatureParams,
    counts: Option<&[[u32; 2]]>,
) -> Vec<VoxelStats> {
    let c = &voxels.centroid;
    let mut out = vec![VoxelStats::default(); c.len()];
    let (Ok(tree3), Ok(tree2)) = (
        ImmutableKdTree::<f32, 3>::new_from_slice(c),
        ImmutableKdTree::<f32, 2>::new_from_slice(
            &c.iter().map(|p| [p[0], p[1]]).collect::<Vec<_>>(),
        ),
    ) else {
        return out;
    };
    let rs2 = params.radius_small_m * params.radius_small_m;
    let rl2 = params.radius_large_m * params.radius_large_m;
    let rc2 = params.column_radius_m * params.column_radius_m;
    let ids: Vec<usize> = (0..c.len()).filter(|&i| needed[i]).collect();
    let stats: Vec<VoxelStats> = ids
        .par_iter()
        .map(|&i| {
            let a = c[i];
            let (mut small, mut large) = (Moments::default(), Moments::default());
            let (mut echo_small, mut echo_column) = ([0u32; 2], [0u32; 2]);
            let tally = |acc: &mut [u32; 2], v: u32| {
                if let Some(c) = counts.and_then(|c| c.get(v as usize)) {
                    acc[0] += c[0];
                    acc[1] += c[1];
                }
            };
            let near = tree3
                .query(&a)
                .within::<SquaredEuclidean<f32>>(rl2)
                .unsorted()
                .execute();
            for nb in &near {
                let q = c[nb.item as usize];
                let d = std::array::from_fn(|k| f64::from(q[k]) - f64::from(a[k]));
                large.add(d);
                if nb.distance <= rs2 {
                    small.add(d);
                    tally(&mut echo_small, nb.item);
                }
            }
            let (mut top, mut bottom) = (a[2], a[2]);
            let column = tree2
                .query(&[a[0], a[1]])
                .within::<SquaredEuclidean<f32>>(rc2)
                .unsorted()
                .execute();
            for nb in &column {
                let z = c[nb.item as usize][2];
                top = top.max(z);
                bottom = bottom.min(z);
                tally(&mut echo_column, nb.item);
            }
            let echo_share = |acc: [u32; 2]| match counts {
                Some(_) => echo::share(acc[0], acc[1]),
                None => echo::UNKNOWN,
            };
            VoxelStats {
                small: scale_stats(&small, a[2]),
                large: scale_stats(&large, a[2]),
                count_ratio: (large.count().max(1.0) / small.count().max(1.0)).log2() as f32,
                column_top: top,
                column_bottom: bottom,
                multiple_small: echo_share(echo_small),
                multiple_column: echo_share(echo_column),
            }
        })
        .collect();
    for (i, s) in ids.into_iter().zip(stats) {
        out[i] = s;
    }
    out
}

fn scale_stats(m: &Moments, anchor_z: f32) -> ScaleStats {
    let s = m.shape();
    [
        s.linearity as f32,
        s.planarity as f32,
        s.sphericity as f32,
        s.curvature as f32,
        s.normal[2].abs() as f32,
        (s.z_max - s.z_min) as f32,
        anchor_z + s.mean[2] as f32,
    ]
}
