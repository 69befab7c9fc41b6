//! Known occupancy for line-of-sight tests: a dense bit grid of voxels over
//! the explored neighbourhood, filled from known points, walked by 3D DDA.

/// Occupied voxels inside a box.
#[derive(Debug, Clone)]
pub struct Voxels {
    lo: [f32; 3],
    size: f32,
    dims: [usize; 3],
    bits: Vec<u64>,
}

impl Voxels {
    /// An empty grid of voxels `size` wide over `lo..hi` (at most ~2^31 voxels: larger boxes are coarsened).
    pub fn new(lo: [f32; 3], hi: [f32; 3], size: f32) -> Self {
        let mut size = size;
        let count = |s: f32| -> [usize; 3] {
            std::array::from_fn(|k| (((hi[k] - lo[k]) / s).ceil().max(1.0)) as usize)
        };
        while count(size).iter().map(|&d| d as f64).product::<f64>() > 2.0e9 {
            size *= 2.0;
        }
        let dims = count(size);
        let n = dims[0] * dims[1] * dims[2];
        Self {
            lo,
            size,
            dims,
            bits: vec![0; n.div_ceil(64)],
        }
    }

    fn cell(&self, p: [f32; 3]) -> Option<[usize; 3]> {
        let mut c = [0usize; 3];
        for k in 0..3 {
            let v = ((p[k] - self.lo[k]) / self.size).floor();
            if !(v >= 0.0 && (v as usize) < self.dims[k]) {
                return None;
            }
            c[k] = v as usize;
        }
        Some(c)
    }

    fn flat(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// Marks the voxel holding `p` (ignored outside the box).
    pub fn insert(&mut self, p: [f32; 3]) {
        if let Some(c) = self.cell(p) {
            let f = self.flat(c);
            self.bits[f / 64] |= 1 << (f % 64);
        }
    }

    fn occupied(&self, c: [i64; 3]) -> bool {
        if (0..3).any(|k| c[k] < 0 || c[k] as usize >= self.dims[k]) {
            return false;
        }
        let f = self.flat([c[0] as usize, c[1] as usize, c[2] as usize]);
        self.bits[f / 64] >> (f % 64) & 1 == 1
    }

    /// True when an occupied voxel lies on the segment `a → b`, ignoring the
    /// first `skip_start` and the last `skip_end` metres.
    pub fn blocked(&self, a: [f32; 3], b: [f32; 3], skip_start: f32, skip_end: f32) -> bool {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !(len.is_finite() && len > skip_start + skip_end) {
            return false;
        }
        let (t0, t1) = (skip_start / len, 1.0 - skip_end / len);
        let start: [f32; 3] = std::array::from_fn(|k| (a[k] + t0 * d[k] - self.lo[k]) / self.size);
        let mut c: [i64; 3] = std::array::from_fn(|k| start[k].floor() as i64);
        let mut step = [0i64; 3];
        let mut t_max = [f32::INFINITY; 3];
        let mut t_delta = [f32::INFINITY; 3];
        for k in 0..3 {
            // Parameter t runs over the whole segment a → b (0..1).
            let dk = d[k] / self.size;
            if dk > 0.0 {
                step[k] = 1;
                t_max[k] = t0 + ((c[k] + 1) as f32 - start[k]) / dk;
                t_delta[k] = 1.0 / dk;
            } else if dk < 0.0 {
                step[k] = -1;
                t_max[k] = t0 + (c[k] as f32 - start[k]) / dk;
                t_delta[k] = -1.0 / dk;
            }
        }
        loop {
            if self.occupied(c) {
                return true;
            }
            let k = if t_max[0] < t_max[1] {
                if t_max[0] < t_max[2] { 0 } else { 2 }
            } else if t_max[1] < t_max[2] {
                1
            } else {
                2
            };
            if t_max[k] > t1 {
                return false;
            }
            c[k] += step[k];
            t_max[k] += t_delta[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Voxels;

    #[test]
    fn a_wall_blocks_and_the_ends_are_skipped() {
        let mut v = Voxels::new([0.0; 3], [10.0; 3], 0.5);
        for y in 0..20 {
            for z in 0..20 {
                v.insert([5.1, y as f32 * 0.5, z as f32 * 0.5]);
            }
        }
        assert!(v.blocked([1.0, 5.0, 2.0], [9.0, 6.0, 3.0], 0.0, 0.0));
        assert!(!v.blocked([1.0, 5.0, 2.0], [4.0, 6.0, 3.0], 0.0, 0.0));
        // The end inside the wall is skipped: the wall's own samples stay visible.
        assert!(!v.blocked([1.0, 5.0, 2.0], [5.2, 5.0, 2.0], 0.0, 0.75));
        assert!(!v.blocked([1.0, 5.0, 2.0], [1.0, 5.0, 2.0], 0.0, 0.0));
    }
}
