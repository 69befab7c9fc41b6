//! Building points bucketed by slice band and 1 m xy cell, for the strip
//! queries of the boundary test.

use crate::geom::grid::GridFrame;

/// Points of one building sorted by (band, cell).
#[derive(Debug, Clone)]
pub struct BandIndex {
    frame: GridFrame,
    keys: Vec<u64>,
    points: Vec<[f32; 3]>,
}

impl BandIndex {
    /// Buckets `points` into bands of thickness `spacing` starting at `base`
    /// (`bands` of them) and the cells of `frame`; points outside are left out.
    pub fn new(
        points: &[[f32; 3]],
        base: f32,
        spacing: f32,
        bands: usize,
        frame: GridFrame,
    ) -> Self {
        let cells = frame.len() as u64;
        let mut keyed: Vec<(u64, [f32; 3])> = points
            .iter()
            .filter_map(|p| {
                let k = ((p[2] - base) / spacing).floor();
                let cell = frame.index_of(f64::from(p[0]), f64::from(p[1]))?;
                (k >= 0.0 && (k as usize) < bands).then(|| (k as u64 * cells + cell as u64, *p))
            })
            .collect();
        keyed.sort_unstable_by_key(|(k, _)| *k);
        BandIndex {
            frame,
            keys: keyed.iter().map(|(k, _)| *k).collect(),
            points: keyed.into_iter().map(|(_, p)| p).collect(),
        }
    }

    /// Calls `f` on every point of band `band` in the cells overlapping the
    /// square of half-side `r` around `q`.
    pub fn for_each_near(&self, band: usize, q: [f64; 2], r: f64, mut f: impl FnMut(&[f32; 3])) {
        let f0 = &self.frame;
        let (lo_i, lo_j) = f0.key(q[0] - r, q[1] - r);
        let (hi_i, hi_j) = f0.key(q[0] + r, q[1] + r);
        if hi_i < 0 || hi_j < 0 {
            return;
        }
        let (lo_i, lo_j) = (lo_i.max(0) as usize, lo_j.max(0) as usize);
        let hi_i = (hi_i as usize).min(f0.nx.saturating_sub(1));
        let hi_j = (hi_j as usize).min(f0.ny.saturating_sub(1));
        for j in lo_j..=hi_j {
            let row = band as u64 * f0.len() as u64 + (j * f0.nx) as u64;
            let (a, b) = (row + lo_i as u64, row + hi_i as u64);
            let start = self.keys.partition_point(|&k| k < a);
            let end = self.keys.partition_point(|&k| k <= b);
            self.points[start..end.max(start)].iter().for_each(&mut f);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_points_of_the_right_band_and_place() {
        let pts = vec![
            [1.5, 1.5, 0.5],
            [1.5, 1.5, 1.5],
            [8.5, 1.5, 0.5],
            [2.2, 0.9, 0.2],
        ];
        let idx = BandIndex::new(
            &pts,
            0.0,
            1.0,
            2,
            GridFrame::covering([0.0; 2], [9.5; 2], 1.0, 0),
        );
        let mut got = Vec::new();
        idx.for_each_near(0, [1.5, 1.5], 1.0, |p| got.push(*p));
        got.sort_by(|a, b| a[0].total_cmp(&b[0]));
        assert_eq!(got, vec![[1.5, 1.5, 0.5], [2.2, 0.9, 0.2]]);
        let mut n = 0;
        idx.for_each_near(1, [1.5, 1.5], 1.0, |_| n += 1);
        assert_eq!(n, 1);
    }
}
