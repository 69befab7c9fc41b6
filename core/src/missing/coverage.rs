//! The collected/missing test of one boundary point: how much of the wall
//! strip near q_n, around segment s_m → q_n, the slice's points cover.
//!
//! The strip is |u| ≤ δ across the segment and from `near` inside to
//! `outside` beyond q_n along it; it is sampled on a grid of (u, z) nodes
//! spaced like the ground-truth samples, and a node is covered when a point
//! lies within the coverage radius of it in the wall plane. This mirrors the
//! completeness metric, so "collected" means what the evaluation means.

use super::band::BandIndex;

/// Points this close behind q_n lie on the outline's own face (the outline
/// is up to a raster cell outside its wall); deeper ones are set back, metres.
pub const FACE_DEPTH: f64 = 1.0;

/// The strip of one test.
#[derive(Debug, Clone, Copy)]
pub struct Strip {
    /// q_n.
    pub q: [f64; 2],
    /// Unit direction s_m → q_n.
    pub dir: [f64; 2],
    /// δ.
    pub half_width: f64,
    /// Depth inside q_n searched.
    pub near: f64,
    /// Depth outside q_n searched.
    pub outside: f64,
    /// Band index and its z range to cover.
    pub band: usize,
    /// Lower and upper z of the wall part tested.
    pub z: [f32; 2],
    /// Coverage radius.
    pub radius: f32,
}

impl Strip {
    /// Offsets of `p` from q_n: along s→q (negative: inside) and across it
    /// (left of s→q positive), metres.
    pub fn along_across(&self, p: [f32; 3]) -> (f64, f64) {
        let rel = [f64::from(p[0]) - self.q[0], f64::from(p[1]) - self.q[1]];
        (
            rel[0] * self.dir[0] + rel[1] * self.dir[1],
            rel[1] * self.dir[0] - rel[0] * self.dir[1],
        )
    }
}

/// What the strip holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripCoverage {
    /// Covered share of the strip's sample nodes.
    pub share: f32,
    /// Mean offset of the strip's points along s→q from q_n (negative:
    /// inside), where the wall actually is; None without points.
    pub wall_offset: Option<f64>,
    /// Lowest z of the strip's points within [`FACE_DEPTH`] behind q_n (the
    /// outline's own face); None without such points.
    pub face_z_min: Option<f32>,
}

/// Covered share of the strip's sample nodes (0 when it has none) and where
/// its points put the wall.
pub fn strip_coverage(index: &BandIndex, s: &Strip) -> StripCoverage {
    let step = s.radius.max(0.05);
    let nu = ((2.0 * s.half_width) as f32 / step).round().max(1.0) as usize;
    let nz = ((s.z[1] - s.z[0]) / step).round().max(1.0) as usize;
    let mut covered = vec![false; nu * nz];
    let r2 = s.radius * s.radius;
    let reach = s.near.max(s.outside).hypot(s.half_width) + s.radius as f64;
    let du = 2.0 * s.half_width as f32 / nu as f32;
    let dz = (s.z[1] - s.z[0]) / nz as f32;
    let (mut v_sum, mut v_n) = (0.0, 0usize);
    let mut z_min = f32::INFINITY;
    index.for_each_near(s.band, s.q, reach, |p| {
        let (v, u) = s.along_across(*p);
        if v < -s.near || v > s.outside {
            return;
        }
        let u = u as f32 + s.half_width as f32;
        let z = p[2] - s.z[0];
        if !(0.0..=2.0 * s.half_width as f32).contains(&u) || !(0.0..=s.z[1] - s.z[0]).contains(&z)
        {
            return;
        }
        v_sum += v;
        v_n += 1;
        if v >= -FACE_DEPTH {
            z_min = z_min.min(p[2]);
        }
        // Only the nodes within the radius: the rows and columns a point can
        // reach (one spare each side against rounding; the distance test decides).
        let (a0, a1) = reach_of(u, s.radius, du, nu);
        let (b0, b1) = reach_of(z, s.radius, dz, nz);
        for a in a0..a1 {
            let cu = (a as f32 + 0.5) * du - u;
            if cu.abs() > s.radius {
                continue;
            }
            for b in b0..b1 {
                let cz = (b as f32 + 0.5) * dz - z;
                if cu * cu + cz * cz <= r2 {
                    covered[b * nu + a] = true;
                }
            }
        }
    });
    StripCoverage {
        share: covered.iter().filter(|&&c| c).count() as f32 / covered.len() as f32,
        wall_offset: (v_n > 0).then(|| v_sum / v_n as f64),
        face_z_min: z_min.is_finite().then_some(z_min),
    }
}

/// The node indices `[lo, hi)` (of `n`, spaced `d` from 0.5 d) within `r` of `x`.
fn reach_of(x: f32, r: f32, d: f32, n: usize) -> (usize, usize) {
    let lo = ((x - r) / d - 0.5).floor() - 1.0;
    let hi = ((x + r) / d - 0.5).ceil() + 2.0;
    (
        lo.clamp(0.0, n as f32) as usize,
        hi.clamp(0.0, n as f32) as usize,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::grid::GridFrame;

    fn wall(density: f32, z_to: f32) -> Vec<[f32; 3]> {
        // a wall on x = 10 from y = 0..10, points every 1/density metres
        let step = 1.0 / density;
        let mut pts = Vec::new();
        let mut y = 0.0;
        while y < 10.0 {
            let mut z = 0.0;
            while z < z_to {
                pts.push([10.0, y, z]);
                z += step;
            }
            y += step;
        }
        pts
    }

    fn strip(band: usize) -> Strip {
        Strip {
            q: [10.3, 5.0],
            dir: [1.0, 0.0],
            half_width: 0.5,
            near: 1.25,
            outside: 0.5,
            band,
            z: [band as f32, band as f32 + 1.0],
            radius: 0.25,
        }
    }

    #[test]
    fn dense_wall_is_covered_gap_is_not() {
        let pts = wall(5.0, 1.0);
        let idx = BandIndex::new(
            &pts,
            0.0,
            1.0,
            2,
            GridFrame::covering([0.0; 2], [19.5; 2], 1.0, 0),
        );
        assert!(strip_coverage(&idx, &strip(0)).share > 0.9);
        assert_eq!(strip_coverage(&idx, &strip(1)).share, 0.0);
        let off = strip_coverage(&idx, &strip(0)).wall_offset.unwrap();
        assert!((off + 0.3).abs() < 1e-3, "{off}");
        // one stray point covers little
        let idx = BandIndex::new(
            &[[10.0, 5.0, 0.5]],
            0.0,
            1.0,
            2,
            GridFrame::covering([0.0; 2], [19.5; 2], 1.0, 0),
        );
        assert!(strip_coverage(&idx, &strip(0)).share < 0.3);
    }

    #[test]
    fn reach_holds_every_node_within_the_radius() {
        // Against the full scan of nodes, over points inside and outside the strip.
        for (d, n, r) in [
            (0.25f32, 8usize, 0.25f32),
            (0.1, 40, 0.25),
            (0.5, 3, 0.3),
            (0.05, 200, 0.12),
        ] {
            for k in 0..400 {
                let x = -0.7 + k as f32 * (n as f32 * d + 1.4) / 400.0;
                let (lo, hi) = reach_of(x, r, d, n);
                for i in 0..n {
                    let c = (i as f32 + 0.5) * d - x;
                    if c.abs() <= r {
                        assert!(
                            (lo..hi).contains(&i),
                            "x {x} d {d}: node {i} not in {lo}..{hi}"
                        );
                    }
                }
            }
        }
    }
}
