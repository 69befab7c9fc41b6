//! Voxel de-duplication of merged clouds (for /resampled_cloud): one point
//! per voxel, kept incrementally as scans arrive.

use rustc_hash::FxHashMap;

use super::error::ExploreError;

/// Incremental voxel de-duplication: the first point of every `voxel`-wide
/// cube is kept, in insertion order.
#[derive(Debug, Clone)]
pub struct VoxelMerge {
    voxel: f64,
    // One bit per voxel in chunks of CHUNK³ voxels. A set of voxel keys
    // (15 M of them after the reference demo) made every insert a cache
    // miss: 71 % of the explorer's CPU. A scan's points fall in few chunks,
    // so the chunk table stays small and hot. Fx, not SipHash: the keys are
    // our own indices, no untrusted input to guard against.
    seen: FxHashMap<[i64; 3], Box<Chunk>>,
    points: Vec<[f32; 3]>,
}

/// Voxels along a chunk's edge.
const CHUNK: i64 = 16;

/// A chunk's voxels, one bit each.
type Chunk = [u64; (CHUNK * CHUNK * CHUNK / 64) as usize];

impl VoxelMerge {
    /// An empty merge with cubes `voxel_m` wide; the size must be finite
    /// and ≥ 0 (0: no thinning, every finite point is kept).
    pub fn new(voxel_m: f32) -> Result<Self, ExploreError> {
        if !(voxel_m.is_finite() && voxel_m >= 0.0) {
            return Err(ExploreError::Voxel(voxel_m));
        }
        Ok(Self {
            voxel: f64::from(voxel_m),
            seen: FxHashMap::default(),
            points: Vec::new(),
        })
    }

    /// Adds `p`; true when it falls in a voxel not seen before (non-finite points are ignored).
    pub fn add(&mut self, p: [f32; 3]) -> bool {
        if !p.iter().all(|v| v.is_finite()) {
            return false;
        }
        if self.voxel == 0.0 {
            self.points.push(p);
            return true;
        }
        // f64 so that large local coordinates with small voxels do not overflow or collapse.
        let key: [i64; 3] = std::array::from_fn(|k| (f64::from(p[k]) / self.voxel).floor() as i64);
        let l = key.map(|c| c.rem_euclid(CHUNK) as usize);
        let bit = (l[0] * CHUNK as usize + l[1]) * CHUNK as usize + l[2];
        let chunk = self
            .seen
            .entry(key.map(|c| c.div_euclid(CHUNK)))
            .or_insert_with(|| Box::new([0; (CHUNK * CHUNK * CHUNK / 64) as usize]));
        let (word, mask) = (bit / 64, 1u64 << (bit % 64));
        let new = chunk[word] & mask == 0;
        if new {
            chunk[word] |= mask;
            self.points.push(p);
        }
        new
    }

    /// Number of voxels (points) kept.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True when no point has been kept.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The kept points: the first of each voxel, in insertion order.
    pub fn points(&self) -> &[[f32; 3]] {
        &self.points
    }
}

/// Keeps the first point of every `voxel`-wide cube, in input order;
/// non-finite points are dropped.
pub fn resample(points: &[[f32; 3]], voxel: f32) -> Result<Vec<[f32; 3]>, ExploreError> {
    if voxel == 0.0 {
        return Err(ExploreError::Voxel(voxel));
    }
    let mut merge = VoxelMerge::new(voxel)?;
    for p in points {
        merge.add(*p);
    }
    Ok(merge.points)
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

    #[test]
    fn a_zero_voxel_merge_keeps_every_finite_point() {
        let mut m = VoxelMerge::new(0.0).unwrap();
        for p in [[0.1, 0.1, 0.1], [0.1, 0.1, 0.1], [f32::INFINITY, 0.0, 0.0]] {
            m.add(p);
        }
        assert_eq!(m.len(), 2);
        assert!(VoxelMerge::new(-0.01).is_err() && VoxelMerge::new(f32::NAN).is_err());
    }

    #[test]
    fn merge_dedups_within_a_voxel() {
        let mut m = VoxelMerge::new(1.0).unwrap();
        assert!(m.is_empty());
        assert!(m.add([0.1, 0.2, 0.3]));
        assert!(!m.add([0.9, 0.9, 0.9]));
        assert!(!m.add([0.5, 0.0, 0.99]));
        assert_eq!(m.len(), 1);
        assert_eq!(m.points(), &[[0.1, 0.2, 0.3]]);
    }

    #[test]
    fn merge_keeps_distinct_voxels_in_order() {
        let mut m = VoxelMerge::new(0.25).unwrap();
        // Neighbouring voxels on each axis, and across zero (floor, not truncation).
        let pts = [
            [0.1, 0.1, 0.1],
            [0.3, 0.1, 0.1],
            [0.1, 0.3, 0.1],
            [0.1, 0.1, 0.3],
            [-0.1, 0.1, 0.1],
        ];
        for p in pts {
            assert!(m.add(p), "{p:?} should be a new voxel");
        }
        assert_eq!(m.len(), pts.len());
        assert_eq!(m.points(), &pts);
        // A second scan of the same places adds nothing.
        for p in pts {
            assert!(!m.add([p[0] + 0.01, p[1], p[2]]));
        }
        assert_eq!(m.len(), pts.len());
    }

    #[test]
    fn merge_matches_a_set_of_voxel_keys_across_chunks() {
        // Points on a ±3 m lattice straddling chunk borders and zero, each
        // visited twice: the same answer as a plain set of voxel keys.
        let voxel = 0.05f32;
        let mut m = VoxelMerge::new(voxel).unwrap();
        let mut keys = std::collections::HashSet::new();
        for pass in 0..2 {
            for i in -60..60 {
                for j in [-33, -1, 0, 15, 16, 17] {
                    let p = [
                        i as f32 * 0.051,
                        j as f32 * 0.05 + 0.01,
                        (i * j % 7) as f32 * 0.049,
                    ];
                    let key = p.map(|c| (f64::from(c) / f64::from(voxel)).floor() as i64);
                    assert_eq!(m.add(p), keys.insert(key), "pass {pass} {p:?}");
                }
            }
        }
        assert_eq!(m.len(), keys.len());
    }

    #[test]
    fn merge_ignores_non_finite_points() {
        let mut m = VoxelMerge::new(0.5).unwrap();
        assert!(!m.add([f32::NAN, 0.0, 0.0]));
        assert!(!m.add([0.0, f32::INFINITY, 0.0]));
        assert!(!m.add([0.0, 0.0, f32::NEG_INFINITY]));
        assert!(m.is_empty());
        assert!(m.add([0.0, 0.0, 0.0]));
        assert_eq!(m.len(), 1);
    }

    #[test]
    fn merge_rejects_bad_voxel() {
        // 0 is full density (a_zero_voxel_merge_keeps_every_finite_point).
        for v in [-1.0, f32::NAN, f32::INFINITY] {
            assert!(
                matches!(VoxelMerge::new(v), Err(ExploreError::Voxel(_))),
                "{v}"
            );
        }
    }
}
