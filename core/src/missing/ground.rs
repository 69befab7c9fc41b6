//! Terrain height around buildings, from ground points: on sloped ground a
//! building's lowest point is not the foot of every wall, and slices below
//! the local terrain must not be tested. It also keeps where ground was
//! actually observed: ground seen under a building's outline means the
//! outline is not a wall down to the ground there (a slab on pillars).

/// Cell of the observed-ground bitmap, metres (fine enough to tell the
/// ground under a slab from the ground at its wall's foot).
pub const SEEN_CELL: f32 = 0.5;

/// Mean ground height per square cell, holes (under buildings) filled from
/// their neighbours.
#[derive(Debug, Clone)]
pub struct GroundGrid {
    origin: [f32; 2],
    /// The far corner of the ground points' extent (`origin` is the near one).
    far: [f32; 2],
    cell: f32,
    size: [usize; 2],
    z: Vec<f32>,
    seen_size: [usize; 2],
    seen: Vec<bool>,
}

impl GroundGrid {
    /// Grid of cell `cell` metres over `ground` points (finite ones); cells
    /// without points take the mean of filled neighbours, up to `fill`
    /// cells away. None without finite points or with a bad cell size.
    pub fn from_points(ground: &[[f32; 3]], cell: f32, fill: usize) -> Option<Self> {
        if !(cell.is_finite() && cell > 0.0) {
            return None;
        }
        let pts: Vec<&[f32; 3]> = ground
            .iter()
            .filter(|p| p.iter().all(|v| v.is_finite()))
            .collect();
        let (mut lo, mut hi) = ([f32::MAX; 2], [f32::MIN; 2]);
        for p in &pts {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if pts.is_empty() {
            return None;
        }
        let size = [
            ((hi[0] - lo[0]) / cell) as usize + 1,
            ((hi[1] - lo[1]) / cell) as usize + 1,
        ];
        let seen_size = [
            ((hi[0] - lo[0]) / SEEN_CELL) as usize + 1,
            ((hi[1] - lo[1]) / SEEN_CELL) as usize + 1,
        ];
        let mut seen = vec![false; seen_size[0] * seen_size[1]];
        for p in &pts {
            let i = (((p[0] - lo[0]) / SEEN_CELL) as usize).min(seen_size[0] - 1);
            let j = (((p[1] - lo[1]) / SEEN_CELL) as usize).min(seen_size[1] - 1);
            seen[j * seen_size[0] + i] = true;
        }
        let mut sum = vec![0.0f64; size[0] * size[1]];
        let mut n = vec![0u32; size[0] * size[1]];
        for p in &pts {
            let i = (((p[0] - lo[0]) / cell) as usize).min(size[0] - 1);
            let j = (((p[1] - lo[1]) / cell) as usize).min(size[1] - 1);
            sum[j * size[0] + i] += p[2] as f64;
            n[j * size[0] + i] += 1;
        }
        let mut z: Vec<f32> = sum
            .iter()
            .zip(&n)
            .map(|(&s, &c)| {
                if c > 0 {
                    (s / c as f64) as f32
                } else {
                    f32::NAN
                }
            })
            .collect();
        for _ in 0..fill {
            let prev = z.clone();
            let mut changed = false;
            for j in 0..size[1] {
                for i in 0..size[0] {
                    if prev[j * size[0] + i].is_finite() {
                        continue;
                    }
                    let (mut s, mut c) = (0.0, 0);
                    let near = [
                        (i.wrapping_sub(1), j),
                        (i + 1, j),
                        (i, j.wrapping_sub(1)),
                        (i, j + 1),
                    ];
                    for (a, b) in near {
                        if a < size[0] && b < size[1] && prev[b * size[0] + a].is_finite() {
                            s += prev[b * size[0] + a];
                            c += 1;
                        }
                    }
                    if c > 0 {
                        z[j * size[0] + i] = s / c as f32;
                        changed = true;
                    }
                }
            }
            if !changed {
                break;
            }
        }
        Some(GroundGrid {
            origin: lo,
            far: hi,
            cell,
            size,
            z,
            seen_size,
            seen,
        })
    }

    /// Ground height at (x, y), None off the grid or where unknown.
    pub fn at(&self, x: f64, y: f64) -> Option<f32> {
        let i = ((x as f32 - self.origin[0]) / self.cell).floor();
        let j = ((y as f32 - self.origin[1]) / self.cell).floor();
        if i < 0.0 || j < 0.0 || i as usize >= self.size[0] || j as usize >= self.size[1] {
            return None;
        }
        Some(self.z[j as usize * self.size[0] + i as usize]).filter(|z| z.is_finite())
    }

    /// Whether (x, y) lies outside the ground points' extent: beyond the
    /// survey's edge, where a tile cut a building rather than a wall ending it.
    pub fn beyond_data(&self, x: f64, y: f64) -> bool {
        let (x, y) = (x as f32, y as f32);
        x < self.origin[0] || y < self.origin[1] || x > self.far[0] || y > self.far[1]
    }

    /// Whether a ground point was observed within the [`SEEN_CELL`] cell of (x, y).
    pub fn seen(&self, x: f64, y: f64) -> bool {
        let i = ((x as f32 - self.origin[0]) / SEEN_CELL).floor();
        let j = ((y as f32 - self.origin[1]) / SEEN_CELL).floor();
        let [nx, ny] = self.seen_size;
        i >= 0.0
            && j >= 0.0
            && (i as usize) < nx
            && (j as usize) < ny
            && self.seen[j as usize * nx + i as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_is_kept_and_holes_filled() {
        let mut pts = Vec::new();
        for i in 0..50 {
            for j in 0..50 {
                let (x, y) = (i as f32 + 0.5, j as f32 + 0.5);
                if !((20.0..30.0).contains(&x) && (20.0..30.0).contains(&y)) {
                    pts.push([x, y, 0.1 * x]);
                }
            }
        }
        let g = GroundGrid::from_points(&pts, 2.0, 10).unwrap();
        assert!((g.at(5.0, 5.0).unwrap() - 0.5).abs() < 0.2);
        assert!((g.at(25.0, 25.0).unwrap() - 2.5).abs() < 0.5);
        assert!(g.at(-5.0, 5.0).is_none());
        assert!(g.seen(5.6, 5.6) && !g.seen(25.6, 25.6) && !g.seen(-5.0, 5.0));
        assert!(GroundGrid::from_points(&[], 2.0, 10).is_none());
    }
}
