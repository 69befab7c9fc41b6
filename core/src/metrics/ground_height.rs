//! Height of a scene's Ground objects below a point (2D grid over triangles).

use std::collections::HashMap;

use crate::scene::vec3::wide;
use crate::scene::{ObjectKind, Scene};

/// Ground triangles bucketed by the xy cells their boxes overlap.
pub struct GroundHeight {
    tris: Vec<[[f64; 3]; 3]>,
    cell: f64,
    buckets: HashMap<(i64, i64), Vec<u32>>,
    /// Triangles too large to bucket, checked for every query.
    big: Vec<u32>,
}

impl GroundHeight {
    /// Indexes the triangles of the scene's Ground objects.
    pub fn new(scene: &Scene) -> Self {
        let tris: Vec<[[f64; 3]; 3]> = (0..scene.triangles.len())
            .filter(|&t| {
                scene
                    .triangle_kind(t)
                    .is_some_and(|o| o.kind == ObjectKind::Ground)
            })
            .filter_map(|t| scene.triangle_corners(t).map(|c| c.map(wide)))
            .filter(|t| t.iter().flatten().all(|v| v.is_finite()))
            .collect();
        let mean = tris
            .iter()
            .map(|t| extent(t, 0).max(extent(t, 1)))
            .sum::<f64>()
            / tris.len().max(1) as f64;
        let cell = mean.clamp(1.0, 50.0);
        let mut buckets: HashMap<(i64, i64), Vec<u32>> = HashMap::new();
        let mut big = Vec::new();
        for (i, t) in tris.iter().enumerate() {
            let (lo, hi) = bounds(t);
            let key = |v: f64| (v / cell).floor() as i64;
            let (nx, ny) = (key(hi[0]) - key(lo[0]), key(hi[1]) - key(lo[1]));
            if (nx + 1).saturating_mul(ny + 1) > 65_536 {
                big.push(u32::try_from(i).unwrap_or(u32::MAX));
                continue;
            }
            for by in key(lo[1])..=key(hi[1]) {
                for bx in key(lo[0])..=key(hi[0]) {
                    buckets
                        .entry((bx, by))
                        .or_default()
                        .push(u32::try_from(i).unwrap_or(u32::MAX));
                }
            }
        }
        Self {
            tris,
            cell,
            buckets,
            big,
        }
    }

    /// The highest ground surface at `(x, y)`, or `None` when no ground
    /// triangle covers that point.
    pub fn at(&self, x: f64, y: f64) -> Option<f64> {
        let key = (
            (x / self.cell).floor() as i64,
            (y / self.cell).floor() as i64,
        );
        let mut best: Option<f64> = None;
        let bucket = self.buckets.get(&key).map_or(&[][..], Vec::as_slice);
        for &i in bucket.iter().chain(&self.big) {
            let [a, b, c] = self.tris[i as usize];
            let d = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            if d.abs() < 1e-12 {
                continue;
            }
            let u = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / d;
            let v = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / d;
            let eps = 1e-9;
            if u >= -eps && v >= -eps && u + v <= 1.0 + eps {
                let z = a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]);
                best = Some(best.map_or(z, |h: f64| h.max(z)));
            }
        }
        best
    }
}

fn extent(t: &[[f64; 3]; 3], k: usize) -> f64 {
    let (lo, hi) = bounds(t);
    hi[k] - lo[k]
}

fn bounds(t: &[[f64; 3]; 3]) -> ([f64; 3], [f64; 3]) {
    let mut lo = t[0];
    let mut hi = t[0];
    for p in &t[1..] {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}
